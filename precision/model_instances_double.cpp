/// \file model_instances_double.cpp
/// OdeSystemTpl<double> (ode_system_impl.hpp): the precision references' ODE over the double
/// model, for `check_supported` and the tests of the conversion.
#include "precision/ode_system_impl.hpp"

namespace flexref::precision {
template class OdeSystemTpl<double>;
}  // namespace flexref::precision
