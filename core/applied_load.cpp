#include "core/applied_load.hpp"

#include "core/applied_load_impl.hpp"

namespace flexref::core {

template class AppliedForceTpl<double>;
template class AppliedTorqueTpl<double>;

}  // namespace flexref::core
