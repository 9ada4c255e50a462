#include "reference/exact_solution.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include "core/gravity.hpp"
#include "reference/exact_heavy_top.hpp"
#include "reference/exact_pendulum.hpp"
#include "reference/exact_torque_free.hpp"

namespace flexref::reference {
namespace {

// Principal values equal to 1e-12 relative count as equal: scene inertias are decimal
// numbers, so a symmetric body typed as such is symmetric to the last digit; 1e-12 also
// absorbs the parallel-axis shift's rounding.
constexpr double kSymmetryTolerance = 1e-12;

struct Principal {
  Eigen::Vector3d moments;
  Eigen::Matrix3d R_BP;  ///< columns: principal axes in the body frame, det +1
};

Principal principal_axes(const Eigen::Matrix3d& inertia) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  Principal p{eig.eigenvalues(), eig.eigenvectors()};
  if (p.R_BP.determinant() < 0.0) p.R_BP.col(2) *= -1.0;
  return p;
}

const core::UniformGravity* only_gravity(const core::Model& model) {
  if (model.elements().size() != 1) return nullptr;
  return dynamic_cast<const core::UniformGravity*>(model.elements()[0].get());
}

}  // namespace

ExactSolutionKind classify_exact_solution(const core::Model& model) {
  if (model.num_bodies() != 1) return {"", "exact solutions exist for one body only"};
  if (model.has_constraints()) {
    // The closed forms are for a free or a pivot body: a body on ideal joints (a driven slide
    // included) moves as its joints say, which they do not know.
    return {"", "the body is on ideal joints (the exact solutions are for a free or a pivot body)"};
  }
  const core::Body& body = model.body(0);
  if (body.is_flexible()) {
    return {"", "no exact solution for a flexible body (its references are the solvers)"};
  }
  if (body.is_prescribed()) return {"", "a prescribed rigid body has no dynamics to solve"};
  if (body.is_free()) {
    if (!model.elements().empty()) return {"", "the free body is loaded"};
    return {"torque_free", ""};
  }
  const core::UniformGravity* gravity = only_gravity(model);
  if (gravity == nullptr) return {"", "a pivot body needs gravity as its only load"};
  const Eigen::Vector3d c_B = body.p_BrBcm_B();
  if (c_B.norm() == 0.0) return {"", "the centre of mass is at the pivot"};
  const core::BodyState s0 = model.initial_state()[0];
  if (s0.w_WB_B.norm() == 0.0) {
    const Eigen::Vector3d axis_W =
        (rotation::rotation_matrix(s0.theta_WB) * c_B).cross(gravity->g_W());
    if (axis_W.norm() <= 1e-12 * c_B.norm() * gravity->g_W().norm()) {
      return {"", "released at rest in equilibrium"};
    }
    const Eigen::Vector3d n_B =
        rotation::rotation_matrix(s0.theta_WB).transpose() * axis_W.normalized();
    const Eigen::Vector3d In = body.I_Br_B() * n_B;
    if ((In - n_B.dot(In) * n_B).norm() > kSymmetryTolerance * In.norm()) {
      return {"", "the swing axis is not a principal axis (the motion is not planar)"};
    }
    return {"pendulum", ""};
  }
  // Lagrange top: two equal principal moments about the pivot, centre of mass on the third.
  const Principal p = principal_axes(body.I_Br_B());
  const Eigen::Vector3d& j = p.moments;
  int axis = -1;
  if (std::abs(j(0) - j(1)) <= kSymmetryTolerance * j.maxCoeff()) axis = 2;
  if (std::abs(j(1) - j(2)) <= kSymmetryTolerance * j.maxCoeff()) axis = 0;
  if (axis < 0) return {"", "the pivot body is not symmetric (no Lagrange top)"};
  const Eigen::Vector3d a_B = p.R_BP.col(axis);
  if (a_B.cross(c_B).norm() > 1e-12 * c_B.norm()) {
    return {"", "the centre of mass is off the symmetry axis"};
  }
  return {"heavy_top", ""};
}

ReferenceRun solve_exact(const core::Model& model, const std::vector<double>& output_times) {
  const ExactSolutionKind kind = classify_exact_solution(model);
  if (kind.kind.empty())
    throw std::invalid_argument("no exact solution for this scene: " + kind.reason);
  const core::Body& body = model.body(0);
  const core::BodyState s0 = model.initial_state()[0];
  ReferenceRun run;
  run.solver = "exact";
  run.method = "analytic";
  run.method_reason = "closed form (" + kind.kind + ")";
  const std::clock_t start = std::clock();
  auto record = [&](double t, const rotation::EulerParameters& theta, const Eigen::Vector3d& w_B) {
    core::BodyState s = s0;
    s.theta_WB = theta;
    s.w_WB_B = w_B;
    if (body.is_free()) s.p_WBr = s0.p_WBr + (t - output_times.front()) * s0.v_WBr;
    run.trajectory.times.push_back(t);
    run.trajectory.states.push_back({s});
  };
  const double t0 = output_times.front();
  if (kind.kind == "torque_free") {
    // Solve in the principal frame P of the inertia: θ_WP = θ_WB ⊗ q_BP, ω_P = R_BPᵀ ω_B.
    const Principal p = principal_axes(body.I_Br_B());
    const rotation::EulerParameters q_BP = rotation::euler_parameters_from_matrix(p.R_BP);
    const TorqueFreeExact exact(p.moments, rotation::quaternion_multiply(s0.theta_WB, q_BP),
                                p.R_BP.transpose() * s0.w_WB_B);
    const rotation::EulerParameters q_PB = rotation::quaternion_conjugate(q_BP);
    for (double t : output_times) {
      const RigidAttitude a = exact.at(t - t0);
      record(t, rotation::quaternion_multiply(a.theta, q_PB).normalized(), p.R_BP * a.w_B);
    }
  } else {
    const core::UniformGravity* gravity = only_gravity(model);
    const Eigen::Vector3d c_B = body.p_BrBcm_B();
    if (kind.kind == "pendulum") {
      const PendulumExact exact(body.mass(), c_B, body.I_Br_B(), gravity->g_W(), s0.theta_WB);
      for (double t : output_times) {
        const RigidAttitude a = exact.at(t - t0);
        record(t, a.theta, a.w_B);
      }
    } else {
      const Principal p = principal_axes(body.I_Br_B());
      const int axis =
          std::abs(p.moments(0) - p.moments(1)) <= kSymmetryTolerance * p.moments.maxCoeff() ? 2
                                                                                             : 0;
      const double j_axial = p.moments(axis);
      const double j_perp = p.moments(axis == 2 ? 0 : 1);
      const HeavyTopExact exact(body.mass(), c_B.norm(), c_B.normalized(), j_perp, j_axial,
                                gravity->g_W(), s0.theta_WB, s0.w_WB_B);
      for (double t : output_times) {
        const RigidAttitude a = exact.at(t - t0);
        record(t, a.theta, a.w_B);
      }
    }
  }
  run.stats.cpu_seconds = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  run.stats.steps = static_cast<long>(output_times.size());
  return run;
}

}  // namespace flexref::reference
