/// \file model_instances_extended.cpp
/// core::BodyTpl, core::ModelTpl and OdeSystemTpl in long double (the extended references).
#include "core/body_impl.hpp"
#include "core/model_impl.hpp"
#include "precision/ode_system_impl.hpp"

namespace flexref::core {
template class BodyTpl<long double>;
template class ModelTpl<long double>;
}  // namespace flexref::core

namespace flexref::precision {
template class OdeSystemTpl<long double>;
}  // namespace flexref::precision
