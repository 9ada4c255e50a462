/// \file multibody_model_quad.cpp
/// MultibodyModelTpl<boost::multiprecision::float128> (multibody_model_impl.hpp).
#include "precision/multibody_model_impl.hpp"

namespace flexref::precision {
template class MultibodyModelTpl<boost::multiprecision::float128>;
}  // namespace flexref::precision
