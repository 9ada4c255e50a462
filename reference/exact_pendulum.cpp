/// \file exact_pendulum.cpp
/// The double instantiation of PendulumExactTpl (exact_pendulum_impl.hpp).
#include "reference/exact_pendulum_impl.hpp"

namespace flexref::reference {

template class PendulumExactTpl<double>;

}  // namespace flexref::reference
