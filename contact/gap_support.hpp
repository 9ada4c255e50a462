#pragma once
/// \file gap_support.hpp
/// A support with clearance around a fixed axis (docs/contact.md, "Gap support"): the tube in
/// its support plate. A body point N — a node of a flexible body (core/node_attachment.hpp) or
/// a point of a rigid body — moves freely while it stays within the clearance c of the support
/// axis (point S, unit direction a, world frame) and is pushed back with the contact laws of
/// contact_laws.hpp when it leaves it:
///   circular  d = (I − a aᵀ)(p_WN − p_WS),  g = c − |d|,           n = −d/|d|
///   planar    s = m·(p_WN − p_WS),          g = c − |s|,           n = −sign(s) m
///             (m ⊥ a: the support acts in one transverse direction only, two planes at ±c)
/// with the penetration δ = −g, δ̇ = −n·v_N (v_N the velocity of the deformed point, the support
/// is fixed), the normal force F_n n and the friction −μ F_n tanh(|v_t|/v_reg) v_t/|v_t| on the
/// slip velocity v_t = v_N − (n·v_N) n (axial and circumferential sliding) at the point N.
/// The normal force is −∇V of V = V_law(δ): δ = |d| − c has gradient d/|d| = −n.
#include <string>

#include "contact/contact_laws.hpp"
#include "contact/gap_support_tpl.hpp"
#include "contact/penalty_load_tpl.hpp"
#include "core/force_element.hpp"
#include "core/node_attachment.hpp"
#include "core/unit_vector_tpl.hpp"

namespace flexref::contact {

struct GapSupportGeometry {
  enum class Kind { kCircular, kPlanar };
  Kind kind = Kind::kCircular;
  Eigen::Vector3d p_WS = Eigen::Vector3d::Zero();  ///< a point of the support axis, m
  Eigen::Vector3d a_W = Eigen::Vector3d::UnitX();  ///< unit support axis
  Eigen::Vector3d m_W = Eigen::Vector3d::UnitZ();  ///< planar: unit normal of the planes, ⊥ a
  double clearance = 1e-3;                         ///< c, m (> 0)
};

/// Gap, normal and contact point of the support at a configuration.
struct GapPoint {
  double gap = 0.0;
  Eigen::Vector3d n_W = Eigen::Vector3d::UnitZ();  ///< on the body, toward the axis
  Eigen::Vector3d p_WN = Eigen::Vector3d::Zero();  ///< the (deformed) point
};

class GapSupport final : public core::ForceElement {
 public:
  /// The point p_BoN_B of `body` (a node's undeformed position when `node` deforms). Throws
  /// std::invalid_argument for a non-unit or dependent axis/normal or a clearance ≤ 0.
  /// effective_mass (kg, 0: the body's mass) only sets the penalty mode of the step limit.
  GapSupport(int body, const Eigen::Vector3d& p_BoN_B, core::NodeAttachment node,
             GapSupportGeometry geometry, NormalLaw normal, FrictionLaw friction,
             double effective_mass = 0.0, std::string name = {});

  GapPoint gap_point(std::span<const core::BodyKinematics> bodies) const;

  /// Everything the support applies at a state: penetration rate, slip velocity, forces.
  /// δ̇, v_t, F_n, F_t and the dissipated power are penalty_load_tpl's (penalty_load_tpl.hpp).
  struct Evaluation : PenaltyLoadTpl<double> {
    GapPoint point;
    Eigen::Vector3d force_W() const { return normal.total * point.n_W + f_friction_W; }
  };
  Evaluation evaluate(std::span<const core::BodyKinematics> bodies) const;

  void add_wrenches(const core::LoadContext& context, std::span<const core::BodyKinematics> bodies,
                    std::span<core::Wrench> wrenches) const override;
  double potential_energy(const core::LoadContext& context,
                          std::span<const core::BodyKinematics> bodies) const override;
  double dissipated_power(const core::LoadContext& context,
                          std::span<const core::BodyKinematics> bodies) const override;
  int switching_function_count() const override { return 1; }
  void switching_functions(const core::LoadContext& context,
                           std::span<const core::BodyKinematics> bodies,
                           std::span<double> g) const override;
  bool depends_on_velocity() const override { return true; }
  int wear_channel_count() const override { return name_.empty() ? 0 : 1; }
  std::string wear_channel_name() const override { return name_; }
  void wear_samples(const core::LoadContext& context, std::span<const core::BodyKinematics> bodies,
                    std::span<core::WearSample> samples) const override;
  int max_body_index() const override { return body_; }
  std::string describe() const override;
  void append_penalty_modes(std::span<const core::Body> bodies,
                            std::vector<core::PenaltyMode>& modes) const override;

  const GapSupportGeometry& geometry() const { return geometry_; }
  /// The geometry in S (gap_support_tpl.hpp: the formulas above, written once).
  template <typename S>
  GapGeometryTpl<S> geometry_in() const {
    GapGeometryTpl<S> g;
    g.circular = geometry_.kind == GapSupportGeometry::Kind::kCircular;
    g.p_WS = geometry_.p_WS.cast<S>();
    g.a_W = core::unit_vector_in<S>(geometry_.a_W);
    g.m_W = core::unit_vector_in<S>(geometry_.m_W);
    g.clearance = S(geometry_.clearance);
    return g;
  }
  int body() const { return body_; }
  const Eigen::Vector3d& p_BoN_B() const { return p_BoN_B_; }
  const core::NodeAttachment& node() const { return node_; }
  const NormalLaw& normal_law() const { return normal_; }
  const FrictionLaw& friction_law() const { return friction_; }

 private:
  int body_;
  Eigen::Vector3d p_BoN_B_;
  core::NodeAttachment node_;
  GapSupportGeometry geometry_;
  GapGeometryTpl<double> geometry_in_s_;
  NormalLaw normal_;
  FrictionLaw friction_;
  double effective_mass_;
  std::string name_;
};

}  // namespace flexref::contact
