#pragma once
/// \file test_problems.hpp
/// Test problems for the rotation schemes, built in code from core types (no scene files),
/// each with its source and, where one exists, its exact solution (Drake test_utilities
/// style). Header-only so that any test can reuse them.
///
///   free_spin           docs/design/scenes.md `free_spin` (paper Fig. 1): torque-free asymmetric
///                       body; invariants π and kinetic energy.
///   book_toss           docs/design/scenes.md `book_toss` (paper Fig. 3): spin about the
///                       intermediate axis, sin² torque pulse on [0, 0.1).
///   book_toss_step      the same with a rectangular pulse (a load discontinuity at 0.1).
///   heavy_top           docs/design/scenes.md `heavy_top` (after Brüls & Cardona 2010).
///   book_and_top        book_toss's book and heavy_top's top in one model (uncoupled).
///   coulomb_wall        docs/design/scenes.md `coulomb_wall` (paper Fig. 2): translation and
///                       rotation coupled through configuration-dependent forces.
///   damped_coulomb_wall coulomb_wall with viscous damping (velocity-dependent loads).
///   free_spin_failing_after  free_spin with a NaN torque injected after a given time.
///   RegularPrecession   torque-free symmetric body with its closed-form solution.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/applied_load.hpp"
#include "core/body.hpp"
#include "core/gravity.hpp"
#include "core/model.hpp"
#include "core/point_charge_potential.hpp"
#include "core/state.hpp"
#include "core/time_profile.hpp"
#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"

namespace flexref::testing {

/// The point every metric tracks: body point (1, 0, 0) from the frame origin.
inline Eigen::Vector3d tracked_point() { return Eigen::Vector3d(1.0, 0.0, 0.0); }

inline core::RigidBodyDescription rigid_body(std::string name, double mass,
                                             const Eigen::Vector3d& principal_inertia,
                                             const Eigen::Vector3d& w0_B) {
  core::RigidBodyDescription d;
  d.name = std::move(name);
  d.mass = mass;
  d.I_Bcm_B = principal_inertia.asDiagonal();
  d.initial.w_WB_B = w0_B;
  d.points.push_back({"tracked", tracked_point()});
  return d;
}

using Elements = std::vector<std::unique_ptr<const core::ForceElement>>;

/// free_spin: m = 1, J = diag(3, 4, 5), W0 = (0.2, 0.3, 2.0), identity attitude, at rest in
/// translation, no loads. Exact solution by Jacobi elliptic functions (not needed here: the
/// tests use its invariants, the kinetic energy and π = R J W).
inline core::Model free_spin() {
  std::vector<core::Body> bodies;
  bodies.emplace_back(rigid_body("spinner", 1.0, {3.0, 4.0, 5.0}, {0.2, 0.3, 2.0}));
  return core::Model(std::move(bodies), Elements{});
}

/// book_toss: m = 1, J = diag(1, 2, 2.8), W0 = (0, 10, 0) (about the intermediate axis),
/// world torque (0.2, 0, 0.2)·sin²(πt/0.1) for t < 0.1 (C¹ at both ends).
inline core::Model book_toss() {
  std::vector<core::Body> bodies;
  bodies.emplace_back(rigid_body("book", 1.0, {1.0, 2.0, 2.8}, {0.0, 10.0, 0.0}));
  Elements elements;
  elements.push_back(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d(0.2, 0.0, 0.2), core::LoadFrame::kWorld,
      core::TimeProfile::sin2_pulse(0.0, 0.1)));
  return core::Model(std::move(bodies), std::move(elements));
}

/// book_toss_step: book_toss with the torque as a rectangular pulse on [0, 0.1): the torque
/// jumps at 0.1 (a load discontinuity every integrator must step on).
inline core::Model book_toss_step() {
  std::vector<core::Body> bodies;
  bodies.emplace_back(rigid_body("book", 1.0, {1.0, 2.0, 2.8}, {0.0, 10.0, 0.0}));
  Elements elements;
  elements.push_back(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d(0.2, 0.0, 0.2), core::LoadFrame::kWorld,
      core::TimeProfile::rectangular_pulse(0.0, 0.1)));
  return core::Model(std::move(bodies), std::move(elements));
}

/// heavy_top: pivot body, m = 15, J_C = diag(0.234375, 0.46875, 0.234375) (symmetric about
/// the body y axis), centre of mass at body (0, 1, 0), pivot at the body origin, gravity
/// (0, 0, −9.81), W0 = (0, 150, −4.61538), identity attitude. A fast top: the symmetric heavy
/// top has a Lagrange closed form (docs/design/schemes.md); here it is compared with RKF7(8).
inline core::Model heavy_top() {
  core::RigidBodyDescription d =
      rigid_body("top", 15.0, {0.234375, 0.46875, 0.234375}, {0.0, 150.0, -4.61538});
  d.p_BoBcm_B = Eigen::Vector3d(0.0, 1.0, 0.0);
  d.motion = core::MotionKind::kPivot;
  d.p_BoPivot_B = Eigen::Vector3d::Zero();
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  Elements elements;
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0.0, 0.0, -9.81),
      std::vector<core::UniformGravity::BodyMass>{{0, 15.0, Eigen::Vector3d(0.0, 1.0, 0.0)}}));
  return core::Model(std::move(bodies), std::move(elements));
}

/// Two bodies in one model, uncoupled: the book of book_toss (free, torque pulse) and the top
/// of heavy_top (pivot, gravity), to check that schemes advance all bodies at once exactly as
/// they advance each alone.
inline core::Model book_and_top() {
  std::vector<core::Body> bodies;
  bodies.emplace_back(rigid_body("book", 1.0, {1.0, 2.0, 2.8}, {0.0, 10.0, 0.0}));
  core::RigidBodyDescription top =
      rigid_body("top", 15.0, {0.234375, 0.46875, 0.234375}, {0.0, 150.0, -4.61538});
  top.p_BoBcm_B = Eigen::Vector3d(0.0, 1.0, 0.0);
  top.motion = core::MotionKind::kPivot;
  bodies.emplace_back(std::move(top));
  Elements elements;
  elements.push_back(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d(0.2, 0.0, 0.2), core::LoadFrame::kWorld,
      core::TimeProfile::sin2_pulse(0.0, 0.1)));
  elements.push_back(std::make_unique<core::UniformGravity>(
      Eigen::Vector3d(0.0, 0.0, -9.81),
      std::vector<core::UniformGravity::BodyMass>{{1, 15.0, Eigen::Vector3d(0.0, 1.0, 0.0)}}));
  return core::Model(std::move(bodies), std::move(elements));
}

/// coulomb_wall: m = 1, J = diag(0.4, 0.9, 1.1); charges at body points (0.5, 0, 0) weight 1
/// and (−0.5, 0, 0) weight 0.6 in the potential c (−α/|r − M| + β/r_z), α = 4, β = 0.3,
/// M = (0, 0, −1); x_C(0) = (0, 0, 1), v(0) = (0.8, 0, 0), W0 = (0.2, 0.3, 1.5).
inline core::Model coulomb_wall() {
  core::RigidBodyDescription d = rigid_body("charged", 1.0, {0.4, 0.9, 1.1}, {0.2, 0.3, 1.5});
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, 1.0);
  d.initial.v_WBo = Eigen::Vector3d(0.8, 0.0, 0.0);
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  Elements elements;
  elements.push_back(std::make_unique<core::PointChargePotential>(
      4.0, 0.3, Eigen::Vector3d(0.0, 0.0, -1.0),
      std::vector<core::PointChargePotential::Charge>{{0, Eigen::Vector3d(0.5, 0.0, 0.0), 1.0},
                                                      {0, Eigen::Vector3d(-0.5, 0.0, 0.0), 0.6}}));
  return core::Model(std::move(bodies), std::move(elements));
}

/// Linear viscous damping of body 0 (a free body): f = −c_v v_Bcm at the centre of mass and
/// τ = −c_w ω_W, both world. Velocity-dependent, so the schemes evaluate it at their
/// predicted velocities.
class ViscousDamping final : public core::ForceElement {
 public:
  ViscousDamping(double c_v, double c_w) : c_v_(c_v), c_w_(c_w) {}
  void add_wrenches(const core::LoadContext&, std::span<const core::BodyKinematics> bodies,
                    std::span<core::Wrench> wrenches) const override {
    const core::BodyKinematics& k = bodies[0];
    wrenches[0].f_W -= c_v_ * k.state->v_WBr;
    wrenches[0].tau_Br_W -= c_w_ * (k.R_WB * k.state->w_WB_B);
  }
  bool depends_on_velocity() const override { return true; }
  int max_body_index() const override { return 0; }
  std::string describe() const override { return "viscous damping"; }

 private:
  double c_v_;
  double c_w_;
};

/// coulomb_wall with viscous damping c_v = 0.3 N·s/m, c_w = 0.2 N·m·s: configuration- and
/// velocity-dependent loads on a translating and rotating body.
inline core::Model damped_coulomb_wall() {
  core::RigidBodyDescription d = rigid_body("charged", 1.0, {0.4, 0.9, 1.1}, {0.2, 0.3, 1.5});
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, 1.0);
  d.initial.v_WBo = Eigen::Vector3d(0.8, 0.0, 0.0);
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  Elements elements;
  elements.push_back(std::make_unique<core::PointChargePotential>(
      4.0, 0.3, Eigen::Vector3d(0.0, 0.0, -1.0),
      std::vector<core::PointChargePotential::Charge>{{0, Eigen::Vector3d(0.5, 0.0, 0.0), 1.0},
                                                      {0, Eigen::Vector3d(-0.5, 0.0, 0.0), 0.6}}));
  elements.push_back(std::make_unique<ViscousDamping>(0.3, 0.2));
  return core::Model(std::move(bodies), std::move(elements));
}

/// A fault to inject: a torque that becomes NaN on body 0 for steps inside (t_bad, ∞), to
/// check that schemes and drivers detect non-finite states.
class NanTorqueAfter final : public core::ForceElement {
 public:
  explicit NanTorqueAfter(double t_bad) : t_bad_(t_bad) {}
  void add_wrenches(const core::LoadContext& context, std::span<const core::BodyKinematics>,
                    std::span<core::Wrench> wrenches) const override {
    if (context.t_segment > t_bad_) {
      wrenches[0].tau_Br_W.x() += std::numeric_limits<double>::quiet_NaN();
    }
  }
  int max_body_index() const override { return 0; }
  std::string describe() const override { return "NaN torque after t_bad"; }

 private:
  double t_bad_;
};

/// free_spin with a NanTorqueAfter(t_bad) fault.
inline core::Model free_spin_failing_after(double t_bad) {
  std::vector<core::Body> bodies;
  bodies.emplace_back(rigid_body("spinner", 1.0, {3.0, 4.0, 5.0}, {0.2, 0.3, 2.0}));
  Elements elements;
  elements.push_back(std::make_unique<NanTorqueAfter>(t_bad));
  return core::Model(std::move(bodies), std::move(elements));
}

/// Torque-free symmetric body J = diag(I1, I1, I3) (regular precession), with the exact
/// solution (e.g. Goldstein, Classical Mechanics §5.6; derived here in the body frame):
///   λ = (I3 − I1) W0_z / I1,   n = R0 J W0 / |J W0|,   μ = |J W0| / I1
///   W(t) = exp(λ t ẑ~) (J W0 / I1) − λ ẑ
///   R(t) = exp(μ t ñ) R0 exp(−λ t ẑ~)
/// (check: RᵀṘ = (μ exp(λtẑ~) R0ᵀ n − λ ẑ)~ = W̃, and Ẇ = λ ẑ × W solves the Euler equation
/// I1 Ẇ1 = (I1 − I3) W2 W3, I1 Ẇ2 = (I3 − I1) W3 W1, Ẇ3 = 0). The body also translates
/// uniformly, x(t) = x0 + v0 t. W is not constant, so the flow is not solved exactly by every
/// consistent scheme.
struct RegularPrecession {
  double I1 = 2.0;
  double I3 = 3.0;
  Eigen::Vector3d w0_B = Eigen::Vector3d(0.6, -0.4, 1.5);
  rotation::EulerParameters theta0 = rotation::exp_quaternion(Eigen::Vector3d(0.3, -0.2, 0.5));
  Eigen::Vector3d p0 = Eigen::Vector3d(0.1, 0.2, 0.3);
  Eigen::Vector3d v0 = Eigen::Vector3d(0.5, -0.25, 0.125);

  core::Model model() const {
    core::RigidBodyDescription d = rigid_body("symmetric", 2.5, {I1, I1, I3}, w0_B);
    d.initial.theta_WB = theta0;
    d.initial.p_WBo = p0;
    d.initial.v_WBo = v0;
    std::vector<core::Body> bodies;
    bodies.emplace_back(std::move(d));
    return core::Model(std::move(bodies), Elements{});
  }
  Eigen::Vector3d J_w0() const {
    return Eigen::Vector3d(I1 * w0_B.x(), I1 * w0_B.y(), I3 * w0_B.z());
  }
  double lambda() const { return (I3 - I1) * w0_B.z() / I1; }
  Eigen::Vector3d w_B(double t) const {
    return rotation::exp_so3(lambda() * t * Eigen::Vector3d::UnitZ()) * (J_w0() / I1) -
           lambda() * Eigen::Vector3d::UnitZ();
  }
  Eigen::Matrix3d R_WB(double t) const {
    const Eigen::Matrix3d R0 = rotation::rotation_matrix(theta0);
    const Eigen::Vector3d pi_W = R0 * J_w0();
    const double mu = pi_W.norm() / I1;
    return rotation::exp_so3(mu * t * pi_W.normalized()) * R0 *
           rotation::exp_so3(-lambda() * t * Eigen::Vector3d::UnitZ());
  }
  core::BodyState state(double t) const {
    core::BodyState s;
    s.p_WBr = p0 + v0 * t;  // the centre of mass is the frame origin
    s.theta_WB = rotation::euler_parameters_from_matrix(R_WB(t));
    s.v_WBr = v0;
    s.w_WB_B = w_B(t);
    return s;
  }
};

/// Error of a run against a reference on the same output times (docs/design/schemes.md default
/// metric): L∞ over times and bodies of the geodesic rotation angle, plus L∞ of the position
/// error of the tracked point (1, 0, 0) of each body.
inline double trajectory_error(const core::Model& model, const core::Trajectory& run,
                               const core::Trajectory& reference) {
  double rotation = 0.0;
  double position = 0.0;
  for (std::size_t k = 0; k < run.states.size(); ++k) {
    for (int i = 0; i < model.num_bodies(); ++i) {
      const auto& s = run.states[k][static_cast<std::size_t>(i)];
      const auto& r = reference.states[k][static_cast<std::size_t>(i)];
      rotation = std::max(rotation, rotation::geodesic_angle(r.theta_WB, s.theta_WB));
      position = std::max(
          position, (model.p_WP(i, s, tracked_point()) - model.p_WP(i, r, tracked_point())).norm());
    }
  }
  return rotation + position;
}

}  // namespace flexref::testing
