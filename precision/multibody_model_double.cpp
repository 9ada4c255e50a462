/// \file multibody_model_double.cpp
/// MultibodyModelTpl<double> (multibody_model_impl.hpp).
#include "precision/multibody_model_impl.hpp"

namespace flexref::precision {
template class MultibodyModelTpl<double>;
}  // namespace flexref::precision
