/// \file multibody_model_extended.cpp
/// MultibodyModelTpl<long double> (multibody_model_impl.hpp).
#include "precision/multibody_model_impl.hpp"

namespace flexref::precision {
template class MultibodyModelTpl<long double>;
}  // namespace flexref::precision
