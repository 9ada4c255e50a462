#pragma once

/// \file contact_models.hpp
/// Contact scenes built in code from core types (no scene files), with the parameters of
/// docs/design/scenes.md ("Bundled cases") where that table gives them. Header-only, like
/// flexible_models.hpp. Gravity is (0, 0, −9.81) except for double_pendulum_impacts, whose
/// swing plane is x–z with gravity −z as well (the wall is the plane x = 0.8).
///
///   bouncing_ball                sphere (m = 1, r = 0.1) dropped from 1 m with a lateral speed
///                                onto the frictionless plane z = 0.
///   sliding_block                0.2 cube (m = 1) on four corner contacts, launched at 2 m/s,
///                                stops by friction.
///   top_on_plane                 heavy_top scaled down on a spherical tip (free body).
///   tippe_top                    Leine & Glocker (2003) tippe top (free body, two spheres).
///   pendulum_on_sliding_support  block (4 corner contacts, μ = 0.2) + rod on a revolute bushing.
///   double_pendulum_impacts      pivoted rod + rod on a revolute bushing, tip sphere vs a wall.
///
/// Penalty parameters and the stiffness/step trade-off (docs/contact.md, docs/joints.md):
/// a stiffer penalty penetrates less (model error ~ δ) but its frequency ω = √(k_eff/m_eff)
/// bounds explicit steps by 2/ω and costs the references steps wherever the contact rings.
/// Hunt–Crossley n = 1.5 everywhere (no force jump at onset, so the references' root finding
/// is not strictly needed for accuracy but keeps steps from straddling onsets); k is chosen so
/// that the static or impact penetration is ≤ ~1 % of the smallest length of the scene and the
/// contact frequency stays within a few thousand rad/s (explicit steps ≥ ~5e-4 s). Regularized
/// friction acts like a viscous damper c_t = μ F_n / v_reg on a sticking/creeping contact; it
/// bounds explicit steps by 2 m_eff,t / c_t as well, which is why v_reg is raised to 1e-2 m/s on
/// the heavy multi-contact block (the creep speed then is ~1e-2 tan α/μ m/s).
/// ContactScene::step_limit collects all of these (see contact_step_limit()).

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "contact/bushing.hpp"
#include "contact/contact.hpp"
#include "contact/contact_laws.hpp"
#include "core/body.hpp"
#include "core/gravity.hpp"
#include "core/model.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::testing {

using ContactElements = std::vector<std::unique_ptr<const core::ForceElement>>;

/// A contact scene: its model, its end time, and the stiffest modes an explicit step must
/// resolve, each as (name, step limit in s) derived in the builder's comment.
struct ContactScene {
  std::string name;
  core::Model model;
  double end_time = 1.0;
  std::vector<std::pair<std::string, double>> step_limits;
  /// The smallest of step_limits.
  double step_limit() const {
    double h = 1e300;
    for (const auto& [what, limit] : step_limits) h = std::min(h, limit);
    return h;
  }
};

namespace contact_detail {

inline Eigen::Vector3d gravity() { return {0.0, 0.0, -9.81}; }

inline rotation::EulerParameters rotation_about(const Eigen::Vector3d& axis, double angle) {
  return rotation::exp_quaternion(angle * axis.normalized());
}

/// Step limit of a regularized-friction contact acting as a damper c_t = μ F_n / v_reg on a
/// tangential effective mass m_t: forward-Euler-like limit 2 m_t / c_t.
inline double friction_step_limit(double mu, double normal_force, double v_reg, double m_t) {
  return 2.0 * m_t * v_reg / (mu * normal_force);
}

/// Translational effective mass at a body point r (from the centre of mass) in direction n,
/// free body of mass m and inertia J about the centre of mass (docs/joints.md).
inline double effective_mass(double m, const Eigen::Matrix3d& J, const Eigen::Vector3d& r,
                             const Eigen::Vector3d& n) {
  const Eigen::Vector3d rn = r.cross(n);
  return 1.0 / (1.0 / m + rn.dot(J.ldlt().solve(rn)));
}

/// Linearized Hunt–Crossley stiffness at a static load F: n k δ^{n−1}, δ = (F/k)^{1/n}.
inline double hc_static_stiffness(double k, double n, double load) {
  return n * k * std::pow(std::pow(load / k, 1.0 / n), n - 1.0);
}

/// Linearized Hunt–Crossley stiffness at the largest penetration of an undamped impact of m at
/// speed v (docs/contact.md).
inline double hc_impact_stiffness(double k, double n, double m, double v) {
  const double delta = std::pow((n + 1.0) * m * v * v / (2.0 * k), 1.0 / (n + 1.0));
  return n * k * std::pow(delta, n - 1.0);
}

inline double explicit_limit(double stiffness, double mass) {
  return 2.0 / std::sqrt(stiffness / mass);
}

/// A uniform rod of mass m and length L along the body −z axis from its frame origin (the
/// hinge end) to (0, 0, −L); axial inertia J_axial (a rod of finite radius: 1e-3 kg·m² keeps
/// the angular joint mode about the rod axis at a reasonable frequency, docs/joints.md).
inline core::RigidBodyDescription rod(std::string name, double m, double L, double J_axial,
                                      const rotation::EulerParameters& theta,
                                      const Eigen::Vector3d& p_WBo) {
  core::RigidBodyDescription d;
  d.name = std::move(name);
  d.mass = m;
  const double J = m * L * L / 12.0;
  d.I_Bcm_B = Eigen::Vector3d(J, J, J_axial).asDiagonal();
  d.p_BoBcm_B = Eigen::Vector3d(0.0, 0.0, -0.5 * L);
  d.initial.p_WBo = p_WBo;
  d.initial.theta_WB = theta;
  d.points.push_back({"tip", Eigen::Vector3d(0.0, 0.0, -L), -1});
  return d;
}

}  // namespace contact_detail

/// bouncing_ball: solid sphere m = 1, r = 0.1 (J = 2/5 m r²), centre at z = 1, v0 = (0.5, 0, 0),
/// ω0 = (0, 0, 0); plane z = 0; Hunt–Crossley k = 1e6 N/m^1.5, n = 1.5, e = 0.5 at
/// v_ref = 4.2 m/s (the first impact speed √(2 g 0.9)); frictionless. End 2 s.
/// First impact: δ_max = 1.4e-2 m, k_lin = 1.8e5 N/m, ω = 420 rad/s → 2/ω = 4.8e-3 s.
/// Frictionless on purpose: with μ = 0.3 and v_reg = 1e-3 the impact's peak normal force
/// (~1.6e3 N) turns the rolling contact into a damper c_t = μ F_n/v_reg ≈ 5e5 N·s/m, whose
/// explicit limit 2 m_t/c_t ≈ 1e-6 s no scheme here can afford (and C1's Newton, which omits
/// ∂Γ/∂W, stops converging at the first impact for every h from 1e-4 to 1.25e-5 s:
/// docs/contact_results.md).
inline ContactScene bouncing_ball() {
  using namespace contact_detail;
  const double m = 1.0, r = 0.1, J = 0.4 * m * r * r, k = 1e6, n = 1.5, v_imp = 4.2;
  core::RigidBodyDescription d;
  d.name = "ball";
  d.mass = m;
  d.I_Bcm_B = Eigen::Matrix3d::Identity() * J;
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, 1.0);
  d.initial.v_WBo = Eigen::Vector3d(0.5, 0.0, 0.0);
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  ContactElements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      gravity(), std::vector<core::UniformGravity::BodyMass>{{0, m, Eigen::Vector3d::Zero()}}));
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::vector<contact::ContactPair>{contact::ContactPair::sphere_plane(
          0, Eigen::Vector3d::Zero(), r, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ())},
      contact::NormalLaw::hunt_crossley(k, n, 0.5, v_imp), contact::FrictionLaw{0.0, 1e-3}, m));
  ContactScene s{"bouncing_ball", core::Model(std::move(bodies), std::move(elements)), 2.0, {}};
  s.step_limits.push_back(
      {"contact normal", explicit_limit(hc_impact_stiffness(k, n, m, v_imp), m)});
  return s;
}

/// sliding_block: cube m = 1, side 0.2 (J = m a²/6), frame at the centre, bottom corners as
/// point contacts on z = 0 (initial gap 0), v0 = (2, 0, 0); Hunt–Crossley k = 1e7 N/m^1.5,
/// n = 1.5, e = 0.5 at v_ref = 0.1 m/s; μ = 0.3, v_reg = 1e-2 m/s. Stops after v0/(μ g) = 0.68 s;
/// end 1.5 s. Static load per corner m g/4 = 2.45 N: δ = 3.9e-5 m, k_lin = 9.4e4 N/m, m_eff
/// per corner ≈ m/4 → 2/ω = 3.3e-3 s; friction at rest: c_t = μ F_n/v_reg = 74 N·s/m per
/// corner, m_t ≈ m/4 → 6.8e-3 s.
inline ContactScene sliding_block() {
  using namespace contact_detail;
  const double m = 1.0, a = 0.2, k = 1e7, n = 1.5, mu = 0.3, v_reg = 1e-2;
  core::RigidBodyDescription d;
  d.name = "block";
  d.mass = m;
  d.I_Bcm_B = Eigen::Matrix3d::Identity() * (m * a * a / 6.0);
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, 0.5 * a);
  d.initial.v_WBo = Eigen::Vector3d(2.0, 0.0, 0.0);
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  std::vector<contact::ContactPair> pairs;
  for (double x : {-0.5 * a, 0.5 * a}) {
    for (double y : {-0.5 * a, 0.5 * a}) {
      pairs.push_back(contact::ContactPair::point_plane(
          0, Eigen::Vector3d(x, y, -0.5 * a), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()));
    }
  }
  ContactElements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      gravity(), std::vector<core::UniformGravity::BodyMass>{{0, m, Eigen::Vector3d::Zero()}}));
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::move(pairs), contact::NormalLaw::hunt_crossley(k, n, 0.5, 0.1),
      contact::FrictionLaw{mu, v_reg}, m / 4.0));
  ContactScene s{"sliding_block", core::Model(std::move(bodies), std::move(elements)), 1.5, {}};
  s.step_limits.push_back(
      {"contact normal", explicit_limit(hc_static_stiffness(k, n, m * 9.81 / 4.0), m / 4.0)});
  s.step_limits.push_back({"friction", friction_step_limit(mu, m * 9.81 / 4.0, v_reg, m / 4.0)});
  return s;
}

/// top_on_plane (docs/design/scenes.md): m = 0.1, J_C = diag(1e-4, 1e-4, 1.6e-4) (symmetry axis z,
/// frame at the centre of mass), tip sphere r = 0.005 centred at (0, 0, −0.04); tilt 0.2 rad
/// about x, spin 100 rad/s about the symmetry axis; the sphere touches z = 0 (gap 0). End 5.
/// Hunt–Crossley k = 1e6 N/m^1.5, n = 1.5, e = 0.5 at v_ref = 0.1 m/s; μ = 0.3, v_reg = 1e-3.
/// Static: F = m g = 0.98 N, δ = 9.9e-5 m (2 % of r), k_lin = 1.5e4 N/m; vertical m_eff at
/// the tip 0.094 kg → 2/ω = 5.0e-3 s. Friction: c_t = 294 N·s/m, tangential m_eff at the
/// contact point (tilted arm) 0.033 kg → 2.3e-4 s (the binding limit).
inline ContactScene top_on_plane() {
  using namespace contact_detail;
  const double m = 0.1, r = 0.005, l = 0.04, tilt = 0.2, k = 1e6, n = 1.5, mu = 0.3, v_reg = 1e-3;
  const Eigen::Matrix3d J = Eigen::Vector3d(1e-4, 1e-4, 1.6e-4).asDiagonal();
  const Eigen::Vector3d p_tip_B(0.0, 0.0, -l);
  core::RigidBodyDescription d;
  d.name = "top";
  d.mass = m;
  d.I_Bcm_B = J;
  d.initial.theta_WB = rotation_about(Eigen::Vector3d::UnitX(), tilt);
  const Eigen::Matrix3d R = rotation::rotation_matrix(d.initial.theta_WB);
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, r) - R * p_tip_B;
  d.initial.w_WB_B = Eigen::Vector3d(0.0, 0.0, 100.0);
  d.points.push_back({"tip", p_tip_B, -1});
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  ContactElements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      gravity(), std::vector<core::UniformGravity::BodyMass>{{0, m, Eigen::Vector3d::Zero()}}));
  const Eigen::Vector3d r_contact_B = p_tip_B - R.transpose() * Eigen::Vector3d(0, 0, r);
  const double m_n = effective_mass(m, J, r_contact_B, R.transpose() * Eigen::Vector3d::UnitZ());
  const double m_t =
      std::min(effective_mass(m, J, r_contact_B, R.transpose() * Eigen::Vector3d::UnitX()),
               effective_mass(m, J, r_contact_B, R.transpose() * Eigen::Vector3d::UnitY()));
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::vector<contact::ContactPair>{contact::ContactPair::sphere_plane(
          0, p_tip_B, r, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ())},
      contact::NormalLaw::hunt_crossley(k, n, 0.5, 0.1), contact::FrictionLaw{mu, v_reg}, m_n));
  ContactScene s{"top_on_plane", core::Model(std::move(bodies), std::move(elements)), 5.0, {}};
  s.step_limits.push_back(
      {"contact normal", explicit_limit(hc_static_stiffness(k, n, m * 9.81), m_n)});
  s.step_limits.push_back({"friction", friction_step_limit(mu, m * 9.81, v_reg, m_t)});
  return s;
}

/// The symmetry axis of a top (body z) in the world, from a body state.
inline Eigen::Vector3d symmetry_axis_W(const core::BodyState& s) {
  return rotation::rotation_matrix(s.theta_WB).col(2);
}

/// tippe_top (Leine & Glocker 2003; docs/design/scenes.md): m = 0.006, I1 = 8e-7 (transverse),
/// I3 = 7e-7 (symmetry axis z), frame at the centre of mass; ball of radius 0.015 centred
/// 0.003 above the centre of mass, stem sphere of radius 0.005 centred 0.016 above the ball's
/// centre; tilt 0.1 rad about x, spin 180 rad/s about the symmetry axis, ball touching z = 0.
/// μ = 0.3, v_reg = 1e-3, g = 9.81. Hunt–Crossley k = 1e6 N/m^1.5, n = 1.5, e = 0.5 at
/// v_ref = 0.1 m/s for both spheres. Static: F = 0.059 N, δ = 1.5e-5 m (1e-3 of the radius),
/// k_lin = 5.8e3 N/m, vertical m_eff ≈ m → 2/ω = 2.0e-3 s; friction c_t = 17.7 N·s/m,
/// tangential m_eff at the ball's contact point 2.9e-3 kg → 3.3e-4 s (binding). End 8 s
/// (the inversion is over by then; see contact_scenes_test and docs/contact_results.md).
inline ContactScene tippe_top(double end_time = 8.0) {
  using namespace contact_detail;
  const double m = 0.006, R_ball = 0.015, a = 0.003, r_stem = 0.005, l_stem = 0.016;
  const double tilt = 0.1, spin = 180.0, k = 1e6, n = 1.5, mu = 0.3, v_reg = 1e-3;
  const Eigen::Matrix3d J = Eigen::Vector3d(8e-7, 8e-7, 7e-7).asDiagonal();
  const Eigen::Vector3d p_ball_B(0.0, 0.0, a);
  const Eigen::Vector3d p_stem_B(0.0, 0.0, a + l_stem);
  core::RigidBodyDescription d;
  d.name = "tippe_top";
  d.mass = m;
  d.I_Bcm_B = J;
  d.initial.theta_WB = rotation_about(Eigen::Vector3d::UnitX(), tilt);
  const Eigen::Matrix3d R = rotation::rotation_matrix(d.initial.theta_WB);
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, R_ball) - R * p_ball_B;
  d.initial.w_WB_B = Eigen::Vector3d(0.0, 0.0, spin);
  d.points.push_back({"stem", p_stem_B, -1});
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  ContactElements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      gravity(), std::vector<core::UniformGravity::BodyMass>{{0, m, Eigen::Vector3d::Zero()}}));
  const Eigen::Vector3d r_contact_B = p_ball_B - R.transpose() * Eigen::Vector3d(0, 0, R_ball);
  const double m_n = effective_mass(m, J, r_contact_B, R.transpose() * Eigen::Vector3d::UnitZ());
  const double m_t =
      std::min(effective_mass(m, J, r_contact_B, R.transpose() * Eigen::Vector3d::UnitX()),
               effective_mass(m, J, r_contact_B, R.transpose() * Eigen::Vector3d::UnitY()));
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::vector<contact::ContactPair>{
          contact::ContactPair::sphere_plane(0, p_ball_B, R_ball, Eigen::Vector3d::Zero(),
                                             Eigen::Vector3d::UnitZ()),
          contact::ContactPair::sphere_plane(0, p_stem_B, r_stem, Eigen::Vector3d::Zero(),
                                             Eigen::Vector3d::UnitZ())},
      contact::NormalLaw::hunt_crossley(k, n, 0.5, 0.1), contact::FrictionLaw{mu, v_reg}, m_n));
  ContactScene s{"tippe_top", core::Model(std::move(bodies), std::move(elements)), end_time, {}};
  s.step_limits.push_back(
      {"contact normal", explicit_limit(hc_static_stiffness(k, n, m * 9.81), m_n)});
  s.step_limits.push_back({"friction", friction_step_limit(mu, m * 9.81, v_reg, m_t)});
  return s;
}

/// pendulum_on_sliding_support (docs/design/scenes.md): block m = 2, 0.2 cube (J = m a²/6), frame at
/// its centre, resting on four corner point contacts on z = 0 (Hunt–Crossley k = 1e7 N/m^1.5,
/// n = 1.5, e = 0.5 at v_ref = 0.1 m/s, μ = 0.2, v_reg = 1e-2 m/s); rod m = 1, L = 1 (centre of
/// mass at 0.5, J = m L²/12 across, 1e-3 axial) hinged at the block's top centre by a revolute
/// bushing, axis y in both (k = 1e5 N/m, k_θ = 1e3 N·m/rad, undamped), released at rest at 60°
/// from the downward vertical (rod end swung toward +x). End 10 s.
/// Joint: rod-end transverse m_eff 0.25 kg in series with the block's top (1/m_eff = 1/2 +
/// 0.1²/J_block = 1.25) → m_eff = 0.19 kg, ω = 725 rad/s → 2.8e-3 s; angular: rod axial
/// 1e-3 kg·m² → ω_θ = 1000 rad/s → 2.0e-3 s. Contacts: static load (3 kg) g/4 = 7.4 N per
/// corner, δ = 8.2e-5 m, k_lin = 1.4e5 N/m, m_eff ≈ 0.5 kg → 3.8e-3 s; friction c_t = 147 N·s/m,
/// m_t ≈ 0.5 kg → 6.8e-3 s. (The default bushing k = 1e6, k_θ = 1e4 would give 8.7e-4 s.)
inline ContactScene pendulum_on_sliding_support() {
  using namespace contact_detail;
  const double m_block = 2.0, a = 0.2, m_rod = 1.0, L = 1.0, angle = M_PI / 3.0;
  const double k_c = 1e7, n = 1.5, mu = 0.2, v_reg = 1e-2;
  contact::BushingParameters joint;
  joint.stiffness = 1e5;
  joint.angular_stiffness = 1e3;
  core::RigidBodyDescription block;
  block.name = "block";
  block.mass = m_block;
  block.I_Bcm_B = Eigen::Matrix3d::Identity() * (m_block * a * a / 6.0);
  block.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, 0.5 * a);
  const Eigen::Vector3d hinge_W(0.0, 0.0, a);
  core::RigidBodyDescription rod_d =
      rod("rod", m_rod, L, 1e-3, rotation_about(Eigen::Vector3d::UnitY(), -angle), hinge_W);
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(block));
  bodies.emplace_back(std::move(rod_d));
  std::vector<contact::ContactPair> pairs;
  for (double x : {-0.5 * a, 0.5 * a}) {
    for (double y : {-0.5 * a, 0.5 * a}) {
      pairs.push_back(contact::ContactPair::point_plane(
          0, Eigen::Vector3d(x, y, -0.5 * a), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()));
    }
  }
  ContactElements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      gravity(),
      std::vector<core::UniformGravity::BodyMass>{
          {0, m_block, Eigen::Vector3d::Zero()}, {1, m_rod, Eigen::Vector3d(0.0, 0.0, -0.5 * L)}}));
  elements.push_back(std::make_unique<contact::RevoluteBushing>(
      contact::BushingEnd{1, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()},
      contact::BushingEnd{0, Eigen::Vector3d(0.0, 0.0, 0.5 * a), Eigen::Vector3d::UnitY()}, joint));
  const double load = (m_block + m_rod) * 9.81 / 4.0;
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::move(pairs), contact::NormalLaw::hunt_crossley(k_c, n, 0.5, 0.1),
      contact::FrictionLaw{mu, v_reg}, m_block / 4.0));
  ContactScene s{
      "pendulum_on_sliding_support", core::Model(std::move(bodies), std::move(elements)), 10.0, {}};
  const double m_joint = 1.0 / (1.0 / 0.25 + 1.0 / m_block + 0.01 / (m_block * a * a / 6.0));
  s.step_limits.push_back({"joint translation", explicit_limit(joint.stiffness, m_joint)});
  s.step_limits.push_back({"joint rotation", explicit_limit(joint.angular_stiffness, 1e-3)});
  s.step_limits.push_back(
      {"contact normal", explicit_limit(hc_static_stiffness(k_c, n, load), m_block / 4.0)});
  s.step_limits.push_back({"friction", friction_step_limit(mu, load, v_reg, m_block / 4.0)});
  return s;
}

/// double_pendulum_impacts (docs/design/scenes.md): two rods m = 1, L = 1 (J = m L²/12 across,
/// 1e-3 axial), each frame at its upper end, rod along body −z. Rod 1 pivots at the origin
/// (MotionKind::kPivot); rod 2 hangs from rod 1's end by a revolute bushing (axis y in both;
/// k = 1e5 N/m, k_θ = 1e3 N·m/rad, undamped). Released at rest horizontal along −x (both rods
/// in line, tip at (−2, 0, 0)); gravity −z; they swing down through the vertical toward +x,
/// where the tip sphere (r = 0.05, centred at rod 2's end) hits the wall plane x = 0.8 (normal
/// −x; only the tip touches it: the rods themselves are not in contact). Hunt–Crossley
/// k = 1e6 N/m^1.5, n = 1.5, e = 0.8 at v_ref = 5 m/s, frictionless. End 10 s.
/// Wall: tip normal m_eff ≈ 0.2 kg, impact at ~5 m/s → δ_max = 8e-3 m, k_lin = 1.4e5 N/m,
/// ω = 830 rad/s → 2.4e-3 s. Joint: m_eff 1/(1/0.25 + 1/1 (rod 1's end about its pivot:
/// J_pivot = 1/3, so 1/m_eff = 3)) = 1/7 kg → ω = 837 rad/s → 2.4e-3 s; angular: both axial
/// inertias 1e-3 in series (5e-4 kg·m²) → ω_θ = 1414 rad/s → 1.4e-3 s (binding).
inline ContactScene double_pendulum_impacts(double end_time = 10.0) {
  using namespace contact_detail;
  const double m = 1.0, L = 1.0, r_tip = 0.05, k_c = 1e6, n = 1.5;
  contact::BushingParameters joint;
  joint.stiffness = 1e5;
  joint.angular_stiffness = 1e3;
  const rotation::EulerParameters theta = rotation_about(Eigen::Vector3d::UnitY(), M_PI / 2.0);
  core::RigidBodyDescription rod1 = rod("rod1", m, L, 1e-3, theta, Eigen::Vector3d::Zero());
  rod1.motion = core::MotionKind::kPivot;
  rod1.p_BoPivot_B = Eigen::Vector3d::Zero();
  core::RigidBodyDescription rod2 = rod("rod2", m, L, 1e-3, theta, Eigen::Vector3d(-L, 0.0, 0.0));
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(rod1));
  bodies.emplace_back(std::move(rod2));
  ContactElements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      gravity(),
      std::vector<core::UniformGravity::BodyMass>{{0, m, Eigen::Vector3d(0.0, 0.0, -0.5 * L)},
                                                  {1, m, Eigen::Vector3d(0.0, 0.0, -0.5 * L)}}));
  elements.push_back(std::make_unique<contact::RevoluteBushing>(
      contact::BushingEnd{1, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitY()},
      contact::BushingEnd{0, Eigen::Vector3d(0.0, 0.0, -L), Eigen::Vector3d::UnitY()}, joint));
  elements.push_back(std::make_unique<contact::ContactElement>(
      std::vector<contact::ContactPair>{contact::ContactPair::sphere_plane(
          1, Eigen::Vector3d(0.0, 0.0, -L), r_tip, Eigen::Vector3d(0.8, 0.0, 0.0),
          -Eigen::Vector3d::UnitX())},
      contact::NormalLaw::hunt_crossley(k_c, n, 0.8, 5.0), contact::FrictionLaw{0.0, 1e-3}, 0.2));
  ContactScene s{
      "double_pendulum_impacts", core::Model(std::move(bodies), std::move(elements)), end_time, {}};
  s.step_limits.push_back(
      {"wall contact", explicit_limit(hc_impact_stiffness(k_c, n, 0.2, 5.0), 0.2)});
  s.step_limits.push_back({"joint translation", explicit_limit(joint.stiffness, 1.0 / 7.0)});
  s.step_limits.push_back({"joint rotation", explicit_limit(joint.angular_stiffness, 5e-4)});
  return s;
}

/// Every contact scene, in a fixed order.
inline std::vector<ContactScene> all_contact_scenes() {
  std::vector<ContactScene> scenes;
  scenes.push_back(bouncing_ball());
  scenes.push_back(sliding_block());
  scenes.push_back(top_on_plane());
  scenes.push_back(tippe_top());
  scenes.push_back(pendulum_on_sliding_support());
  scenes.push_back(double_pendulum_impacts());
  return scenes;
}

}  // namespace flexref::testing
