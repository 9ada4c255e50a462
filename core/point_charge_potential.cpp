#include "core/point_charge_potential.hpp"

#include "core/point_charge_potential_impl.hpp"

namespace flexref::core {

template class PointChargePotentialTpl<double>;

}  // namespace flexref::core
