/// \file schur_complement_test.cpp
/// The sparse constrained solve (core/schur_complement_tpl.hpp, core/sparse_ldl_tpl.hpp,
/// core/schur_pattern_tpl.hpp) against the same solve written densely here: on bundled
/// mechanisms' rows at perturbed states, with a pseudo-random symmetric positive definite inverse
/// mass per body (not the bodies' own, so that no structure of a real M hides an error), the
/// multipliers, the constrained accelerations, the pivots' extremes and the orientation test's
/// determinant sign must be the dense ones. (Here rather than in tests/core: the mechanisms are
/// scenes.)
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/constrained_solve_tpl.hpp"
#include "scene/build_model.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::constraint {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

/// A bundled mechanism's rows at its initial state moved by a pseudo-random increment (the
/// rows need not hold: the solve does not ask), a random SPD M_b⁻¹ per body, and the dense
/// J, M⁻¹.
struct SchurCase {
  scene::Scene scene;
  core::ConstraintSolve solve;
  std::vector<MatrixXd> inverse_mass;  ///< per body, width × width
  MatrixXd J;                          ///< dense, from an independent evaluation
  MatrixXd Minv;                       ///< dense block-diagonal
};

SchurCase make_case(const std::string& file, unsigned seed) {
  SchurCase c{scene::read_scene(file), {}, {}, {}, {}};
  const core::Model& model = *c.scene.model;
  const core::VelocityLayout& layout = model.velocity_layout();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  core::State state = model.initial_state();
  for (core::BodyState& b : state) {
    b.v_WBr += Eigen::Vector3d(u(rng), u(rng), u(rng));
    b.w_WB_B += Eigen::Vector3d(u(rng), u(rng), u(rng));
    b.p_WBr += 0.01 * Eigen::Vector3d(u(rng), u(rng), u(rng));
  }
  core::Workspace ws = model.make_workspace();
  model.relative_position_violation(0.0, state, ws);  // poses the bodies, evaluates the rows
  c.solve = core::ConstraintSolve(*model.constraints(), layout, model.independent_rows());
  c.solve.rows = ws.constraint.rows;
  // The dense J from an evaluation into dense rows (ConstraintRows::resize).
  core::ConstraintRows dense;
  dense.resize(model.constraints()->row_count(), layout.size());
  model.constraints()->evaluate(0.0, ws.kinematics, layout, dense);
  c.J = dense.J;
  c.Minv = MatrixXd::Zero(layout.size(), layout.size());
  for (int b = 0; b < layout.body_count(); ++b) {
    const int w = layout.width(b);
    MatrixXd R(w, w);
    for (Eigen::Index i = 0; i < R.size(); ++i) R(i) = u(rng);
    // Eigenvalues in [0.5, 0.5 + w·O(1)]: condition ~10, like a body's M.
    const MatrixXd block = R * R.transpose() + 0.5 * MatrixXd::Identity(w, w);
    c.inverse_mass.push_back(block);
    c.Minv.block(layout.offset(b), layout.offset(b), w, w) = block;
  }
  return c;
}

TEST_CASE("sparse Schur complement: λ, accelerations, pivots and orientation are the dense ones",
          "[constraint]") {
  for (const std::string file : {"scenes/andrews_squeezer.toml", "scenes/four_bar.toml",
                                 "scenes/bricard.toml", "scenes/double_pendulum_ideal.toml"}) {
    SchurCase c = make_case(file, 52u);
    const core::Model& model = *c.scene.model;
    const core::VelocityLayout& layout = model.velocity_layout();
    core::ConstraintSolve& s = c.solve;
    const auto apply = [&](int b, const auto& rhs, auto&& out) {
      out = c.inverse_mass[static_cast<std::size_t>(b)] * rhs;
    };
    const auto n = static_cast<Eigen::Index>(layout.size());
    const VectorXd x_free = VectorXd::Random(n);
    s.x = x_free;
    core::ConstraintTracker tracker = model.make_constraint_tracker();
    core::solve_constrained_accelerations(*model.constraints(), layout, apply, 0.0, tracker, s);
    INFO(file << ": " << s.active.size() << " rows of " << c.J.rows() << ", N = " << n);
    // The dense solve of the same rows (the ones the sparse solve enforced).
    MatrixXd J_a(static_cast<Eigen::Index>(s.active.size()), n);
    VectorXd gamma_a(J_a.rows());
    for (std::size_t i = 0; i < s.active.size(); ++i) {
      J_a.row(static_cast<Eigen::Index>(i)) = c.J.row(s.active[i]);
      gamma_a(static_cast<Eigen::Index>(i)) = s.rows.gamma(s.active[i]);
    }
    const MatrixXd A = J_a * c.Minv * J_a.transpose();
    const Eigen::LDLT<MatrixXd> ldlt(A);
    const VectorXd lambda = ldlt.solve(J_a * x_free - gamma_a);
    const VectorXd x = x_free - c.Minv * J_a.transpose() * lambda;
    // Both solve A λ = b backward-stably: |δλ| ≲ κ(A) ε |λ| per solve, κ(A) from A's
    // eigenvalues; 100 covers the few ε each sum of products adds.
    const Eigen::SelfAdjointEigenSolver<MatrixXd> eigen(A, Eigen::EigenvaluesOnly);
    const double kappa = eigen.eigenvalues().maxCoeff() / eigen.eigenvalues().minCoeff();
    const double tolerance = 100.0 * kappa * std::numeric_limits<double>::epsilon();
    INFO("condition of A " << kappa);
    CHECK((s.lambda - lambda).norm() <= tolerance * lambda.norm());
    CHECK((s.x - x).norm() <= tolerance * (x.norm() + x_free.norm()));
    CHECK((s.force + J_a.transpose() * lambda).norm() <=
          tolerance * (J_a.transpose() * lambda).norm());
    // The constrained accelerations satisfy the enforced rows: J_a x = γ_a.
    CHECK((J_a * s.x - gamma_a).norm() <= tolerance * (J_a.norm() * s.x.norm() + gamma_a.norm()));
    // det A = Π D in any symmetric order: the sparse pivots' product is the dense ones'
    // (log-sums: the products of 30 pivots may leave double's range).
    double log_sparse = 0.0, log_dense = 0.0;
    for (Eigen::Index k = 0; k < A.rows(); ++k) {
      log_sparse += std::log(std::abs(s.ldlt.d()(k)));
      log_dense += std::log(std::abs(ldlt.vectorD()(k)));
    }
    CHECK(log_sparse == Approx(log_dense).margin(1e-8 * (1.0 + std::abs(log_dense))));
    CHECK(s.pivot_ratio > 0.0);
    CHECK(s.pivot_ratio <= 1.0);
    // The orientation test's sign against the dense determinant of J_a,accepted M⁻¹ J_aᵀ, for
    // an accepted J equal to the current one and for one with a row's sign flipped (det < 0).
    core::ConstraintJacobian accepted = s.rows.jacobian;
    CHECK(core::kept_orientation(accepted, s));
    const int flipped = s.active[s.active.size() / 2];
    for (int k = 0; k < 2; ++k) {
      if (accepted.slot(flipped, k).body >= 0) accepted.values(flipped, k) *= -1.0;
    }
    MatrixXd J_flipped = J_a;
    J_flipped.row(static_cast<Eigen::Index>(s.active.size() / 2)) *= -1.0;
    const double det_sign =
        Eigen::PartialPivLU<MatrixXd>(J_flipped * c.Minv * J_a.transpose()).determinant();
    REQUIRE(det_sign < 0.0);
    CHECK_FALSE(core::kept_orientation(accepted, s));
  }
}

TEST_CASE("sparse LU: the crossing product's determinant sign for a non-symmetric matrix",
          "[constraint]") {
  // A structurally symmetric non-symmetric matrix (an arrow with a tridiagonal band), its sign of
  // det by the sparse L D W̃ᵀ against the dense LU's, for matrices near SPD and far from it.
  const int n = 9;
  std::vector<int> start{0}, rows;
  for (int k = 0; k < n; ++k) {
    if (k > 0 && k - 1 != 0) rows.push_back(0);
    if (k > 0) rows.push_back(k - 1);
    rows.push_back(k);
    start.push_back(static_cast<int>(rows.size()));
  }
  core::SparseLdlTpl<double> lu;
  lu.analyze(n, start, rows);
  std::mt19937 rng(7u);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int negative = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const double shift = trial < 20 ? 4.0 : 0.3;
    VectorXd upper(static_cast<Eigen::Index>(rows.size())), lower(upper.size());
    MatrixXd C = MatrixXd::Zero(n, n);
    for (int k = 0; k < n; ++k) {
      const auto column = static_cast<std::size_t>(k);
      for (int p = start[column]; p < start[column + 1]; ++p) {
        const int i = rows[static_cast<std::size_t>(p)];
        upper(p) = u(rng) + (i == k ? shift : 0.0);
        lower(p) = i == k ? upper(p) : u(rng);
        C(i, k) = upper(p);
        C(k, i) = lower(p);
      }
    }
    const double det = Eigen::PartialPivLU<MatrixXd>(C).determinant();
    if (!lu.factor_unsymmetric(upper, lower)) continue;
    double sign = 1.0, log_det = 0.0;
    for (int k = 0; k < n; ++k) {
      sign *= lu.d()(k) < 0.0 ? -1.0 : 1.0;
      log_det += std::log(std::abs(lu.d()(k)));
    }
    INFO("trial " << trial << ": det " << det);
    CHECK(sign * det > 0.0);
    // |det| too where the diagonal dominates (no growth without pivoting): the pivots' product,
    // to the round-off of 9 pivots, ~1e-13 relative.
    if (shift > 1.0) CHECK(log_det == Approx(std::log(std::abs(det))).margin(1e-8));
    if (det < 0.0) ++negative;
  }
  CHECK(negative > 0);  // the comparison met both signs
}

}  // namespace
}  // namespace flexref::constraint
