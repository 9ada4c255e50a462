/// \file ideal_joints_test.cpp
/// The rows of every ideal joint (constraint/ideal_joints.hpp) against finite differences of
/// Φ along a motion: Φ̇ = J v + Φ_t and Φ̈ = J v̇ − γ, for each joint type, driven and not,
/// between two rigid bodies, a body and the ground, and a rigid body and a node of a flexible
/// body, at random states (positions, attitudes, velocities, modal coordinates, accelerations).
/// A sign error in any column of J, in Φ_t or in any term of γ fails these checks.
#include "constraint/ideal_joints.hpp"

#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "core/force_element.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/flexible_models.hpp"

namespace flexref::constraint {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;

/// Three bodies: two rigid (6 velocities each) and a flexible beam body with n modes.
struct Bodies {
  static constexpr int kModes = 3;
  flexible::ModalData beam =
      testing::beam_bending_modes(Vector3d(0.1, 0, 0), 1.0, 3.2, 1e5, 1.0, 6, kModes);
  core::VelocityLayout layout;
  std::vector<core::BodyStateTpl<double>> states = std::vector<core::BodyStateTpl<double>>(3);
  std::vector<core::BodyAcceleration> accelerations = std::vector<core::BodyAcceleration>(3);
  std::vector<Vector3d> p_BoBr_B = {Vector3d(0.1, -0.2, 0.05), Vector3d(-0.3, 0.1, 0.2),
                                    Vector3d(0.4, 0.0, 0.0)};

  Bodies() { layout.offsets = {0, 6, 12, 18 + kModes}; }

  int modes(int b) const { return b == 2 ? kModes : 0; }

  void randomize(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const auto vec = [&](double size) -> Vector3d {
      return Vector3d(u(rng), u(rng), u(rng)) * size;
    };
    for (int b = 0; b < 3; ++b) {
      core::BodyStateTpl<double>& s = states[static_cast<std::size_t>(b)];
      s.p_WBr = vec(1.0);
      s.theta_WB = Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized();
      s.v_WBr = vec(2.0);
      s.w_WB_B = vec(3.0);
      s.q_f = VectorXd::NullaryExpr(modes(b), [&] { return 0.05 * u(rng); });
      s.qd_f = VectorXd::NullaryExpr(modes(b), [&] { return 0.5 * u(rng); });
      core::BodyAcceleration& a = accelerations[static_cast<std::size_t>(b)];
      a.a_WBr = vec(5.0);
      a.alpha_WB_B = vec(7.0);
      a.qdd_f = VectorXd::NullaryExpr(modes(b), [&] { return 4.0 * u(rng); });
    }
  }

  /// The states moved along the motion by ε: p + ε v + ½ ε² a, A exp(ε ω̄ + ½ ε² α̅), q + ε q̇ + ½ ε²
  /// q̈ (second-order exact curves with the state's velocities and accelerations); velocities
  /// v + ε a.
  std::vector<core::BodyStateTpl<double>> moved(double e) const {
    std::vector<core::BodyStateTpl<double>> out = states;
    for (std::size_t b = 0; b < out.size(); ++b) {
      const core::BodyAcceleration& a = accelerations[b];
      core::BodyStateTpl<double>& s = out[b];
      s.p_WBr += e * states[b].v_WBr + 0.5 * e * e * a.a_WBr;
      s.theta_WB = rotation::quaternion_multiply(
          s.theta_WB, rotation::exp_quaternion(e * states[b].w_WB_B + 0.5 * e * e * a.alpha_WB_B));
      s.q_f += e * states[b].qd_f + 0.5 * e * e * a.qdd_f;
      s.v_WBr += e * a.a_WBr;
      s.w_WB_B += e * a.alpha_WB_B;
      s.qd_f += e * a.qdd_f;
    }
    return out;
  }

  std::vector<core::BodyKinematicsTpl<double>> kinematics(
      const std::vector<core::BodyStateTpl<double>>& s) const {
    std::vector<core::BodyKinematicsTpl<double>> k(s.size());
    for (std::size_t b = 0; b < s.size(); ++b) {
      k[b].state = &s[b];
      k[b].R_WB = rotation::rotation_matrix(s[b].theta_WB);
      k[b].p_BoBr_B = p_BoBr_B[b];
    }
    return k;
  }

  VectorXd stacked(const std::vector<core::BodyStateTpl<double>>& s) const {
    VectorXd v = VectorXd::Zero(layout.size());
    for (int b = 0; b < 3; ++b) {
      const auto k = static_cast<std::size_t>(b);
      v.segment<3>(layout.offset(b)) = s[k].v_WBr;
      v.segment<3>(layout.offset(b) + 3) = s[k].w_WB_B;
      v.segment(layout.offset(b) + 6, modes(b)) = s[k].qd_f;
    }
    return v;
  }
  VectorXd stacked_accelerations() const {
    VectorXd a = VectorXd::Zero(layout.size());
    for (int b = 0; b < 3; ++b) {
      const auto k = static_cast<std::size_t>(b);
      a.segment<3>(layout.offset(b)) = accelerations[k].a_WBr;
      a.segment<3>(layout.offset(b) + 3) = accelerations[k].alpha_WB_B;
      a.segment(layout.offset(b) + 6, modes(b)) = accelerations[k].qdd_f;
    }
    return a;
  }
};

core::ConstraintRows evaluate(const IdealJoints& joints, const Bodies& bodies, double t,
                              const std::vector<core::BodyStateTpl<double>>& states) {
  core::ConstraintRows rows;
  rows.resize(joints.row_count(), bodies.layout.size());
  const std::vector<core::BodyKinematicsTpl<double>> k = bodies.kinematics(states);
  joints.evaluate(t, std::span<const core::BodyKinematicsTpl<double>>(k), bodies.layout, rows);
  return rows;
}

/// A joint of the given type between body a and end b (body or ground, point or node), with
/// random points and unit axes (the frames need not be assembled for the derivative checks).
IdealJointSpec random_joint(JointType type, int body_b, bool node_b, bool driven,
                            const Bodies& bodies, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto random_frame = [&] {
    const Eigen::Quaterniond q(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized());
    return q.toRotationMatrix();
  };
  IdealJointSpec j;
  j.name = std::string(to_string(type)) + (driven ? "_driven" : "");
  j.type = type;
  j.a.body = 0;
  j.a.p_BoP_B = Vector3d(u(rng), u(rng), u(rng)) * 0.5;
  j.a.R_BJ = random_frame();
  j.b.body = body_b;
  j.b.R_BJ = random_frame();
  if (node_b) {
    j.b.node = 4;
    j.b.p_BoP_B = bodies.beam.p_BoNode_B.col(j.b.node);
    j.b.phi_B = bodies.beam.mode_rows(j.b.node);
  } else {
    j.b.p_BoP_B = Vector3d(u(rng), u(rng), u(rng)) * 0.5;
  }
  j.length = 0.7;
  if (driven) {
    j.drive.active = true;
    j.drive.law.kind = core::AngleLaw::Kind::kSpinUp;
    j.drive.law.rate = 3.0;
    j.drive.law.spin_up_time = 0.8;
    j.drive.offset = 0.2;
  }
  return j;
}

/// Every joint type, each on a body–body end (driven where the type can be), a body–ground end
/// and a body–node end: the joint set of the tests that compare a partial evaluation with
/// evaluate's.
std::vector<IdealJointSpec> every_joint_kind(const Bodies& bodies, std::mt19937& rng) {
  std::vector<IdealJointSpec> specs;
  const JointType types[] = {JointType::kSpherical,   JointType::kRevolute,  JointType::kPrismatic,
                             JointType::kCylindrical, JointType::kUniversal, JointType::kFixed,
                             JointType::kDistance};
  for (const JointType type : types) {
    const bool can_drive = type == JointType::kRevolute || type == JointType::kPrismatic;
    specs.push_back(random_joint(type, 1, false, can_drive, bodies, rng));
    specs.push_back(random_joint(type, kGround, false, false, bodies, rng));
    specs.push_back(random_joint(type, 2, true, false, bodies, rng));
  }
  return specs;
}

void check_rows_against_differences(const IdealJointSpec& spec, const Bodies& bodies, double t) {
  const IdealJoints joints({spec}, 3);
  const core::ConstraintRows rows = evaluate(joints, bodies, t, bodies.states);
  const VectorXd v = bodies.stacked(bodies.states);
  const VectorXd a = bodies.stacked_accelerations();

  // Φ̇ by a central difference, step 1e-6: truncation ~ε² Φ''' ≈ 1e-12 × O(1e3), round-off
  // ~ε_mach Φ/ε ≈ 1e-10 relative to the rates' size (~10): 1e-7 relative is far below any
  // missing or sign-flipped term (each O(1) relative).
  const double e1 = 1e-6;
  const VectorXd phi_plus = evaluate(joints, bodies, t + e1, bodies.moved(e1)).phi;
  const VectorXd phi_minus = evaluate(joints, bodies, t - e1, bodies.moved(-e1)).phi;
  const VectorXd rate_fd = (phi_plus - phi_minus) / (2.0 * e1);
  const VectorXd rate = rows.J * v + rows.phi_t;
  const double rate_margin = 1e-7 * (1.0 + rate_fd.cwiseAbs().maxCoeff());
  for (Eigen::Index r = 0; r < rate.size(); ++r) {
    INFO(spec.name << " row " << r << ": J v + Φ_t = " << rate(r) << ", difference " << rate_fd(r));
    CHECK(rate(r) == Approx(rate_fd(r)).margin(rate_margin));
  }
  // The same rates by J's body blocks, as the constrained solve reads them (row_dot, and the
  // transposed product add_row_transpose through vᵀ(Jᵀμ) = μᵀ(J v) for one μ per row): a block
  // at a wrong offset, or with another row's values, misses the differences by O(1).
  VectorXd sparse_rate(rate.size());
  rows.jacobian.multiply(v, sparse_rate);
  sparse_rate += rows.phi_t;
  for (Eigen::Index r = 0; r < rate.size(); ++r) {
    INFO(spec.name << " row " << r << ": by blocks J v + Φ_t = " << sparse_rate(r));
    CHECK(sparse_rate(r) == Approx(rate_fd(r)).margin(rate_margin));
    VectorXd transposed = VectorXd::Zero(v.size());
    rows.jacobian.add_row_transpose(static_cast<int>(r), 1.0, transposed);
    CHECK(transposed.dot(v) + rows.phi_t(r) == Approx(rate_fd(r)).margin(rate_margin));
  }
  // Φ̈ by the second difference along the second-order exact curve, step 1e-4: truncation
  // ~ε² Φ'''' ≈ 1e-8 × O(1e4), round-off ~4 ε_mach Φ/ε² ≈ 1e-7: 1e-5 relative to the
  // accelerations' size (~1e3) still catches every term (the smallest, 2 ω × A Φ q̇_f, is ~1).
  const double e2 = 1e-4;
  const VectorXd p2 = evaluate(joints, bodies, t + e2, bodies.moved(e2)).phi;
  const VectorXd m2 = evaluate(joints, bodies, t - e2, bodies.moved(-e2)).phi;
  const VectorXd acceleration_fd = (p2 - 2.0 * rows.phi + m2) / (e2 * e2);
  const VectorXd acceleration = rows.J * a - rows.gamma;
  const double acceleration_margin = 1e-5 * (1.0 + acceleration_fd.cwiseAbs().maxCoeff());
  for (Eigen::Index r = 0; r < acceleration.size(); ++r) {
    INFO(spec.name << " row " << r << ": J v̇ − γ = " << acceleration(r) << ", difference "
                   << acceleration_fd(r));
    CHECK(acceleration(r) == Approx(acceleration_fd(r)).margin(acceleration_margin));
  }
  // Each row moves: its Φ̇ and Φ̈ along the motion stand 100× above the comparisons' margins,
  // so that neither comparison passes as zero against zero (a row left out of evaluate, whose
  // Φ, J and γ stay zero, would). The random states and frames make every row's rates O(1).
  for (Eigen::Index r = 0; r < rate.size(); ++r) {
    INFO(spec.name << " row " << r << ": Φ̇ " << rate_fd(r) << ", Φ̈ " << acceleration_fd(r));
    CHECK(std::abs(rate_fd(r)) > 100.0 * rate_margin);
    CHECK(std::abs(acceleration_fd(r)) > 100.0 * acceleration_margin);
  }
}

TEST_CASE("ideal joints: J v + Φ_t and J v̇ − γ are Φ's rates along a motion", "[constraint]") {
  std::mt19937 rng(2026);
  Bodies bodies;
  const JointType types[] = {JointType::kSpherical,   JointType::kRevolute,  JointType::kPrismatic,
                             JointType::kCylindrical, JointType::kUniversal, JointType::kFixed,
                             JointType::kDistance};
  for (int sample = 0; sample < 4; ++sample) {
    bodies.randomize(rng);
    const double t = 0.3 + 0.2 * sample;  // inside and after the drive's spin-up
    for (const JointType type : types) {
      const bool can_drive = type == JointType::kRevolute || type == JointType::kPrismatic;
      for (const bool driven : {false, true}) {
        if (driven && !can_drive) continue;
        // body–body, body–ground, body–flexible node
        check_rows_against_differences(random_joint(type, 1, false, driven, bodies, rng), bodies,
                                       t);
        check_rows_against_differences(random_joint(type, kGround, false, driven, bodies, rng),
                                       bodies, t);
        check_rows_against_differences(random_joint(type, 2, true, driven, bodies, rng), bodies, t);
      }
    }
  }
}

TEST_CASE("ideal joints: evaluate_rows gives evaluate's bits on the rows wanted", "[constraint]") {
  // Every joint type (driven where it can be), on body–body, body–ground and body–node ends, at
  // random states: the rows wanted must be evaluate's to the bit (the reduced form's tracker mixes
  // rows of both, constraint/reduced_model.hpp), the others' J blocks and Φ_t zero and their Φ
  // and γ untouched.
  std::mt19937 rng(52);
  Bodies bodies;
  bodies.randomize(rng);
  const IdealJoints joints(every_joint_kind(bodies, rng), 3);
  const int m = joints.row_count();
  const double t = 0.5;  // inside the drives' spin-up
  const core::ConstraintRows all = evaluate(joints, bodies, t, bodies.states);
  const std::vector<core::BodyKinematicsTpl<double>> k = bodies.kinematics(bodies.states);
  std::bernoulli_distribution coin(0.3);
  for (int draw = 0; draw < 8; ++draw) {
    std::vector<char> wanted(static_cast<std::size_t>(m));
    for (char& w : wanted) w = coin(rng) ? 1 : 0;
    core::ConstraintRows some;
    some.resize(m, bodies.layout.size());
    // Stale values from an earlier evaluation, which the rows not wanted must keep.
    some.phi.setConstant(7.0);
    some.gamma.setConstant(-7.0);
    joints.evaluate_rows(t, std::span<const core::BodyKinematicsTpl<double>>(k), bodies.layout,
                         wanted, some);
    for (int r = 0; r < m; ++r) {
      INFO("draw " << draw << ", row " << r << " (joint " << joints.joint_of_row(r) << ")");
      if (wanted[static_cast<std::size_t>(r)] != 0) {
        CHECK(some.phi(r) == all.phi(r));
        CHECK(some.phi_t(r) == all.phi_t(r));
        CHECK(some.gamma(r) == all.gamma(r));
        CHECK(some.J.row(r) == all.J.row(r));
      } else {
        CHECK(some.phi(r) == 7.0);
        CHECK(some.gamma(r) == -7.0);
        CHECK(some.phi_t(r) == 0.0);
        CHECK(some.J.row(r).isZero(0.0));
      }
    }
  }
}

TEST_CASE("ideal joints: evaluate_rates gives evaluate's Φ, J and Φ_t bits, γ untouched",
          "[constraint]") {
  // The joint check's evaluation (Model::relative_joint_violation) reads no γ: every other entry
  // must be evaluate's to the bit, on every joint type (driven where it can be) and end.
  std::mt19937 rng(53);
  Bodies bodies;
  bodies.randomize(rng);
  const IdealJoints joints(every_joint_kind(bodies, rng), 3);
  const double t = 0.5;  // inside the drives' spin-up
  const core::ConstraintRows all = evaluate(joints, bodies, t, bodies.states);
  const std::vector<core::BodyKinematicsTpl<double>> k = bodies.kinematics(bodies.states);
  core::ConstraintRows rates;
  rates.resize(joints.row_count(), bodies.layout.size());
  rates.gamma.setConstant(-7.0);  // a stale γ, which must stay
  joints.evaluate_rates(t, std::span<const core::BodyKinematicsTpl<double>>(k), bodies.layout,
                        rates);
  CHECK(rates.phi == all.phi);
  CHECK(rates.phi_t == all.phi_t);
  CHECK(rates.J == all.J);
  CHECK((rates.gamma.array() == -7.0).all());
  CHECK(all.phi_t.cwiseAbs().maxCoeff() > 0.0);  // the drives' rows are in the comparison
}

TEST_CASE("ideal joints: rows per type, their owners and length rows", "[constraint]") {
  CHECK(row_count(JointType::kSpherical, false) == 3);
  CHECK(row_count(JointType::kRevolute, false) == 5);
  CHECK(row_count(JointType::kRevolute, true) == 6);
  CHECK(row_count(JointType::kPrismatic, true) == 6);
  CHECK(row_count(JointType::kCylindrical, false) == 4);
  CHECK(row_count(JointType::kUniversal, false) == 4);
  CHECK(row_count(JointType::kFixed, false) == 6);
  CHECK(row_count(JointType::kDistance, false) == 1);
  std::mt19937 rng(7);
  Bodies bodies;
  const IdealJoints joints({random_joint(JointType::kRevolute, 1, false, false, bodies, rng),
                            random_joint(JointType::kPrismatic, kGround, false, true, bodies, rng)},
                           3);
  CHECK(joints.row_count() == 11);
  CHECK(joints.joint_rows(1) == std::array<int, 2>{5, 6});
  CHECK(joints.joint_of_row(4) == 0);
  CHECK(joints.joint_of_row(5) == 1);
  CHECK(joints.row_bodies(5) == std::array<int, 2>{0, kGround});
  // Revolute: 3 point rows then 2 rotation rows; prismatic: 2 slide, 3 rotation, the drive.
  const std::vector<bool> length = {true, true,  true,  false, false, true,
                                    true, false, false, false, true};
  for (int r = 0; r < 11; ++r)
    CHECK(joints.is_length_row(r) == length[static_cast<std::size_t>(r)]);
}

TEST_CASE("ideal joints: an assembled revolute joint has Φ = 0 at any angle about its axis",
          "[constraint]") {
  Bodies bodies;
  std::mt19937 rng(11);
  bodies.randomize(rng);
  IdealJointSpec spec = random_joint(JointType::kRevolute, 1, false, true, bodies, rng);
  // Put body 1 so that its joint point and frame coincide with body 0's, then turn it about the
  // joint axis by the drive's angle at t: every row, the drive's included, vanishes.
  const double t = 0.5;
  const double angle = spec.drive.law.angle(t);
  const core::BodyStateTpl<double>& s0 = bodies.states[0];
  const Eigen::Matrix3d R0 = rotation::rotation_matrix(s0.theta_WB);
  const Eigen::Matrix3d R_WJ = R0 * spec.a.R_BJ;  // the joint frame in the world
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(angle, R_WJ.col(2)).toRotationMatrix();  // about the axis, world
  // Body a turns by +angle relative to body b: b's frame is a's turned back by −angle.
  const Eigen::Matrix3d R1 = turn.transpose() * R_WJ * spec.b.R_BJ.transpose();
  core::BodyStateTpl<double>& s1 = bodies.states[1];
  s1.theta_WB = rotation::euler_parameters_from_matrix(R1);
  const Vector3d p_WP = s0.p_WBr + R0 * (spec.a.p_BoP_B - bodies.p_BoBr_B[0]);
  s1.p_WBr = p_WP - R1 * (spec.b.p_BoP_B - bodies.p_BoBr_B[1]);
  const IdealJoints joints({spec}, 3);
  const core::ConstraintRows rows = evaluate(joints, bodies, t, bodies.states);
  // Φ of an assembled pose: round-off of sums of O(1) products, a few ε.
  CHECK(rows.phi.cwiseAbs().maxCoeff() < 1e-14);
}

TEST_CASE("ideal joints: bad specifications are refused", "[constraint]") {
  std::mt19937 rng(3);
  Bodies bodies;
  IdealJointSpec ground_first = random_joint(JointType::kSpherical, 1, false, false, bodies, rng);
  ground_first.a.body = kGround;
  CHECK_THROWS_AS(IdealJoints({ground_first}, 3), std::invalid_argument);
  IdealJointSpec same = random_joint(JointType::kSpherical, 0, false, false, bodies, rng);
  CHECK_THROWS_AS(IdealJoints({same}, 3), std::invalid_argument);
  IdealJointSpec unknown = random_joint(JointType::kSpherical, 5, false, false, bodies, rng);
  CHECK_THROWS_AS(IdealJoints({unknown}, 3), std::invalid_argument);
  IdealJointSpec rod = random_joint(JointType::kDistance, 1, false, false, bodies, rng);
  rod.length = 0.0;
  CHECK_THROWS_AS(IdealJoints({rod}, 3), std::invalid_argument);
  IdealJointSpec driven = random_joint(JointType::kFixed, 1, false, true, bodies, rng);
  CHECK_THROWS_AS(IdealJoints({driven}, 3), std::invalid_argument);
}

}  // namespace
}  // namespace flexref::constraint
