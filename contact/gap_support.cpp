#include "contact/gap_support.hpp"

#include <cmath>
#include <stdexcept>

#include "contact/gap_support_impl.hpp"
#include "core/body.hpp"

namespace flexref::contact {
namespace {

void require_support(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

}  // namespace

namespace detail {

void validate_gap_support(int body, const Eigen::Vector3d& p_BoN_B, GapSupportGeometry& geometry,
                          const FrictionLaw& friction, double effective_mass) {
  require_support(body >= 0, "gap support body index must be >= 0");
  require_support(p_BoN_B.allFinite() && geometry.p_WS.allFinite(),
                  "gap support geometry must be finite");
  require_support(geometry.clearance > 0.0 && std::isfinite(geometry.clearance),
                  "gap support clearance must be > 0");
  const double a = geometry.a_W.norm();
  require_support(std::isfinite(a) && a > 0.0, "gap support axis must be nonzero");
  geometry.a_W /= a;
  if (geometry.kind == GapSupportGeometry::Kind::kPlanar) {
    // m projected on the plane normal to the axis, then normalized.
    const Eigen::Vector3d m = geometry.m_W - geometry.a_W.dot(geometry.m_W) * geometry.a_W;
    require_support(m.allFinite() && m.norm() > 1e-12 * geometry.m_W.norm(),
                    "gap support plane normal must not be parallel to the axis");
    geometry.m_W = m.normalized();
  }
  require_support(friction.mu >= 0.0 && std::isfinite(friction.mu),
                  "friction coefficient must be >= 0");
  require_support(friction.v_reg > 0.0 && std::isfinite(friction.v_reg),
                  "friction regularization speed must be > 0");
  require_support(effective_mass >= 0.0 && std::isfinite(effective_mass),
                  "gap support effective mass must be >= 0");
}

void validate_gap_support_wear(const core::WearLaw& wear, const GapSupportGeometry& geometry,
                               const std::string& name) {
  require_support(!name.empty(), "a gap support with a wear law needs a name");
  require_support(geometry.kind == GapSupportGeometry::Kind::kCircular,
                  "a wear law applies to a circular gap support only");
  core::validate_wear_law(wear, true, wear.sectors);
}

void append_gap_support_modes(std::span<const core::Body> bodies, int body,
                              const GapSupportGeometry& geometry, const NormalLaw& normal,
                              const FrictionLaw& friction, double effective_mass,
                              std::vector<core::PenaltyMode>& modes) {
  const double m_eff =
      effective_mass > 0.0 ? effective_mass : bodies[static_cast<std::size_t>(body)].mass();
  core::PenaltyMode mode;
  mode.kind = "contact";
  mode.inertia = m_eff;
  mode.stiffness =
      normal.kind() == NormalLaw::Kind::kLinear
          ? normal.stiffness()
          : normal.linearized_stiffness(normal.impact_penetration(m_eff, normal.reference_speed()));
  mode.frequency = std::sqrt(mode.stiffness / m_eff);
  mode.step_limit = 2.0 / mode.frequency;
  modes.push_back(mode);
  if (!(friction.mu > 0.0)) return;
  // Regularized friction below v_reg is a viscous damper c_t = μ F_n/v_reg (docs/contact.md); at
  // the normal force F_n of an impact at the law's reference speed (Hunt–Crossley) or at
  // k·(clearance) (linear) it bounds central differences by 2 m_eff/c_t (a first-order decay
  // with rate c_t/m_eff). On tube_support_impact: 9.5e-5 s; C2 runs at 1e-4 and diverges at 2e-4.
  const double delta = normal.kind() == NormalLaw::Kind::kLinear
                           ? geometry.clearance
                           : normal.impact_penetration(m_eff, normal.reference_speed());
  const double f_n = normal.force(delta, 0.0).elastic;
  core::PenaltyMode f;
  f.label = " friction";
  f.kind = "contact";
  f.inertia = m_eff;
  f.stiffness = 0.0;
  const double c_t = friction.mu * f_n / friction.v_reg;
  f.frequency = c_t / m_eff;  // the decay rate, 1/s
  f.step_limit = 2.0 * m_eff / c_t;
  modes.push_back(f);
}

}  // namespace detail

template class GapSupportTpl<double>;

}  // namespace flexref::contact
