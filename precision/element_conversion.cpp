#include "precision/element_conversion.hpp"

// Eigen's NumTraits for float128 before any Eigen type of it.
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/float128.hpp>
#include <type_traits>

#include "constraint/ideal_joints_impl.hpp"
#include "contact/bushing_impl.hpp"
#include "contact/contact_impl.hpp"
#include "contact/gap_support_impl.hpp"
#include "contact/spring_damper.hpp"
#include "core/applied_load_impl.hpp"
#include "core/gravity_impl.hpp"
#include "core/point_charge_potential_impl.hpp"

// The class templates in extended and quad precision (double: in core/ and contact/).
namespace flexref::core {
template class AppliedForceTpl<long double>;
template class AppliedForceTpl<boost::multiprecision::float128>;
template class AppliedTorqueTpl<long double>;
template class AppliedTorqueTpl<boost::multiprecision::float128>;
template class UniformGravityTpl<long double>;
template class UniformGravityTpl<boost::multiprecision::float128>;
template class PointChargePotentialTpl<long double>;
template class PointChargePotentialTpl<boost::multiprecision::float128>;
}  // namespace flexref::core

namespace flexref::contact {
template class BushingTpl<long double, false>;
template class BushingTpl<boost::multiprecision::float128, false>;
template class BushingTpl<long double, true>;
template class BushingTpl<boost::multiprecision::float128, true>;
template class GapSupportTpl<long double>;
template class GapSupportTpl<boost::multiprecision::float128>;
template class ContactElementTpl<long double>;
template class ContactElementTpl<boost::multiprecision::float128>;
template class SpringDamperTpl<long double>;
template class SpringDamperTpl<boost::multiprecision::float128>;
}  // namespace flexref::contact

namespace flexref::constraint {
template class IdealJointsTpl<long double>;
template class IdealJointsTpl<boost::multiprecision::float128>;
}  // namespace flexref::constraint

namespace flexref::precision {
namespace {

/// The element of type E<double> as E<S>, or nullptr when `element` is not one.
template <template <typename> class E, typename S>
std::unique_ptr<const core::ForceElementTpl<S>> converted(const core::ForceElement& element) {
  const auto* e = dynamic_cast<const E<double>*>(&element);
  if (e == nullptr) return nullptr;
  if constexpr (std::is_same_v<S, double>) {
    return std::make_unique<const E<double>>(*e);
  } else {
    return std::make_unique<const E<S>>(*e);
  }
}

}  // namespace

template <typename S>
std::unique_ptr<const core::ForceElementTpl<S>> element_in(const core::ForceElement& element) {
  std::unique_ptr<const core::ForceElementTpl<S>> e;
  if ((e = converted<core::UniformGravityTpl, S>(element))) return e;
  if ((e = converted<core::AppliedForceTpl, S>(element))) return e;
  if ((e = converted<core::AppliedTorqueTpl, S>(element))) return e;
  if ((e = converted<core::PointChargePotentialTpl, S>(element))) return e;
  if ((e = converted<contact::SphericalBushingTpl, S>(element))) return e;
  if ((e = converted<contact::RevoluteBushingTpl, S>(element))) return e;
  if ((e = converted<contact::GapSupportTpl, S>(element))) return e;
  if ((e = converted<contact::SpringDamperTpl, S>(element))) return e;
  return converted<contact::ContactElementTpl, S>(element);
}

template <typename S>
std::unique_ptr<const core::ConstraintEquationsTpl<S>> constraints_in(
    const core::ConstraintEquations& equations, int body_count) {
  const auto* joints = dynamic_cast<const constraint::IdealJointsTpl<double>*>(&equations);
  if (joints == nullptr) return nullptr;
  if constexpr (std::is_same_v<S, double>) {
    return std::make_unique<const constraint::IdealJointsTpl<double>>(*joints);
  } else {
    return std::make_unique<const constraint::IdealJointsTpl<S>>(joints->joints(), body_count);
  }
}

template std::unique_ptr<const core::ForceElementTpl<double>> element_in<double>(
    const core::ForceElement&);
template std::unique_ptr<const core::ForceElementTpl<long double>> element_in<long double>(
    const core::ForceElement&);
template std::unique_ptr<const core::ForceElementTpl<boost::multiprecision::float128>>
element_in<boost::multiprecision::float128>(const core::ForceElement&);
template std::unique_ptr<const core::ConstraintEquationsTpl<double>> constraints_in<double>(
    const core::ConstraintEquations&, int);
template std::unique_ptr<const core::ConstraintEquationsTpl<long double>>
constraints_in<long double>(const core::ConstraintEquations&, int);
template std::unique_ptr<const core::ConstraintEquationsTpl<boost::multiprecision::float128>>
constraints_in<boost::multiprecision::float128>(const core::ConstraintEquations&, int);

}  // namespace flexref::precision
