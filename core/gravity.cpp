#include "core/gravity.hpp"

#include "core/gravity_impl.hpp"

namespace flexref::core {

template class UniformGravityTpl<double>;

}  // namespace flexref::core
