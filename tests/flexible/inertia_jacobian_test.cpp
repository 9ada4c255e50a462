/// Tests of flexible/inertia_jacobian: the analytic ∂R/∂[π̄, ω̄, q_f, q̇_f] of the inertial,
/// elastic and damping residual R = M x − Qv + [0; 0; K q_f + D q̇_f] against central
/// differences of R evaluated by the direct nodal sums (flexible_mass_matrix_by_nodes,
/// flexible_quadratic_velocity_by_nodes: independent of the invariants), for the coupled and
/// the LTE model, on random dense modal data (every invariant non-zero) and on a beam; the
/// check fails on a wrong sign; nothing allocates.
#include "flexible/inertia_jacobian.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "flexible/beam_model.hpp"
#include "flexible/flexible_dynamics.hpp"
#include "flexible/inertia_terms.hpp"
#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/floating_point.hpp"
#include "tests/support/random_geometric_stiffness.hpp"
#include "tests/support/random_samples.hpp"

namespace flexref::flexible {
namespace {

using testing::kEps;
using testing::random_vector;

/// N nodes in a box off the origin, dense random mode shapes, random K, ζ.
ModalData random_damped_modal_data(int N, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> mass(0.1, 2.0);
  std::uniform_real_distribution<double> coordinate(-1.0, 3.0);
  ModalData data;
  data.mass.resize(N);
  data.p_BoNode_B.resize(3, N);
  for (int k = 0; k < N; ++k) {
    data.mass(k) = mass(rng);
    for (int a = 0; a < 3; ++a) data.p_BoNode_B(a, k) = coordinate(rng);
  }
  data.phi = 0.3 * Eigen::MatrixXd(random_vector(3 * N * n, rng, 1.0).reshaped(3 * N, n));
  data.stiffness = random_vector(n, rng, 10.0).cwiseAbs();
  data.damping_ratio = Eigen::VectorXd::Constant(n, 0.05);
  return data;
}

/// `geometric`: with the beam's geometric stiffness (flexible/geometric_stiffness.hpp).
ModalData damped_beam_data(bool geometric = false) {
  BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.05, -0.02);
  p.elements = 8;
  p.EA = 1e5;
  p.EI_y = 4.0;
  p.EI_z = 3.2;
  p.boundary = BeamBoundary::kClampedFree;
  ModalData data = make_beam_modal_data(p, 6, {}, BeamModeNormalization::kUnitModalMass, geometric);
  data.damping_ratio = Eigen::VectorXd::Constant(6, 0.02);
  return data;
}

/// The tangent state [π̄ offset from A, ω̄, q_f, q̇_f].
struct Point {
  Eigen::Matrix3d A;
  Eigen::Vector3d w;
  Eigen::VectorXd q, qd;
};

Point perturbed(const Point& p, Eigen::Index column, double h) {
  Point out = p;
  const Eigen::Index n = p.q.size();
  if (column < 3) {
    out.A = p.A * rotation::exp_so3(h * Eigen::Vector3d::Unit(column));  // A → A exp(h ẽ_k)
  } else if (column < 6) {
    out.w(column - 3) += h;
  } else if (column < 6 + n) {
    out.q(column - 6) += h;
  } else {
    out.qd(column - 6 - n) += h;
  }
  return out;
}

/// R by the nodal sums; *scale receives Σ of the magnitudes summed into each entry (max over
/// the entries), the scale of its rounding.
Eigen::VectorXd residual_by_nodes(const ModalData& data, bool coupled, const Point& p,
                                  const Eigen::VectorXd& x, double* scale = nullptr) {
  const Eigen::Index n = data.mode_count();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd M(6 + n, 6 + n);
  Eigen::VectorXd Qv(6 + n);
  flexible_mass_matrix_by_nodes(data, p.A, coupled ? p.q : zero, M);
  if (!coupled) M.topRightCorner(6, n).setZero();
  flexible_quadratic_velocity_by_nodes(data, p.A, coupled ? p.q : zero, p.w, coupled ? p.qd : zero,
                                       Qv);
  const Eigen::VectorXd K = data.stiffness;
  const Eigen::VectorXd D = modal_damping(data);
  Eigen::VectorXd R = M * x - Qv;
  R.tail(n) += K.cwiseProduct(p.q) + D.cwiseProduct(p.qd);
  if (scale != nullptr) {
    Eigen::VectorXd s = M.cwiseAbs() * x.cwiseAbs() + Qv.cwiseAbs();
    s.tail(n) += K.cwiseProduct(p.q).cwiseAbs() + D.cwiseProduct(p.qd).cwiseAbs();
    *scale = s.maxCoeff();
  }
  return R;
}

/// R = M x − Qv + [0; 0; K q + D q̇] by the invariants (with geometric stiffening: the nodal
/// sums do not know the foreshortening; the terms themselves are checked by the conservation
/// laws of tests/core/geometric_stiffening_test.cpp).
Eigen::VectorXd residual_by_invariants(const ModalData& data, const ModalInvariants& inv,
                                       const Point& p, const Eigen::VectorXd& x) {
  const int n = data.mode_count();
  InertiaTerms t = make_inertia_terms(n);
  evaluate_inertia_terms(inv, p.A, p.q, p.w, p.qd, t);
  Eigen::VectorXd R = -t.Qv;
  R.head<6>() += t.M_rr * x.head<6>() + t.M_rf * x.tail(n);
  R.tail(n) += t.M_rf.transpose() * x.head<6>() + inv.m_ff * x.tail(n);
  R.tail(n) += data.stiffness.cwiseProduct(p.q) + modal_damping(data).cwiseProduct(p.qd);
  return R;
}

/// Checks every column of the analytic Jacobian against Richardson-extrapolated central
/// differences E = (4 D(h/2) − D(h)) / 3 of the nodal residual. Per column, the bound is
/// |D(h) − D(h/2)| (= ¾ c h² + O(h⁴): it bounds E's O(h⁴) truncation error while c h² ≫ h⁴,
/// i.e. for h small against the state's scale, here 1e-3 against O(1)) plus E's rounding,
/// 3 ε_R / h, with ε_R = 10 N ε S the rounding of one nodal residual (N-term sums of
/// magnitude S, Higham §4.2, times 10 for the flops per term). Returns the largest ratio of
/// error to bound (≤ 1 passes); `wrong` flips the sign of the named column before comparing.
/// Data with geometric stiffening (coupled only) are differenced by the invariants
/// (residual_by_invariants), whose rounding adds n² ε per entry (O(n²) products).
double worst_ratio(const ModalData& data, bool coupled, unsigned seed, Eigen::Index wrong = -1) {
  const ModalInvariants inv = make_modal_invariants(data);
  const int n = data.mode_count();
  std::mt19937 rng(seed);
  Point p;
  p.A = rotation::rotation_matrix(Eigen::Vector4d(random_vector(4, rng, 1.0)).normalized());
  p.w = random_vector(3, rng, 1.5);
  p.q = random_vector(n, rng, 0.2);
  p.qd = random_vector(n, rng, 1.0);
  const Eigen::VectorXd x = random_vector(6 + n, rng, 2.0);
  InertiaTerms terms = make_inertia_terms(n);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  if (coupled) {
    evaluate_inertia_terms(inv, p.A, p.q, p.w, p.qd, terms);
  } else {
    set_undeformed_products(terms);
    assemble_inertia_terms(inv, p.A, zero, p.w, zero, terms);
  }
  InertiaJacobianScratch scratch = make_inertia_jacobian_scratch(n);
  Eigen::MatrixXd J(6 + n, 6 + 2 * n);
  inertia_residual_jacobian(inv, terms, coupled, p.q, p.w, p.qd, x, data.stiffness,
                            modal_damping(data), scratch, J);
  if (wrong >= 0) J.col(wrong) *= -1.0;

  double S = 0.0;
  residual_by_nodes(data, coupled, p, x, &S);
  const double h = 1e-3;
  const bool geometric = data.geometric.has_value();
  const double eps_R = 10.0 * (data.node_count() + (geometric ? n * n : 0)) * kEps * S;
  const auto residual = [&](const Point& at) {
    return geometric ? residual_by_invariants(data, inv, at, x)
                     : residual_by_nodes(data, coupled, at, x);
  };
  double worst = 0.0;
  for (Eigen::Index c = 0; c < J.cols(); ++c) {
    const auto D = [&](double step) {
      return Eigen::VectorXd((residual(perturbed(p, c, step)) - residual(perturbed(p, c, -step))) /
                             (2.0 * step));
    };
    const Eigen::VectorXd D1 = D(h), D2 = D(h / 2.0);
    const Eigen::VectorXd E = (4.0 * D2 - D1) / 3.0;
    const double bound = (D1 - D2).cwiseAbs().maxCoeff() + 3.0 * eps_R / h;
    // The bound is a small fraction of the column (not vacuous): 1e-4 relative at most.
    CHECK(bound <= 1e-4 * (E.cwiseAbs().maxCoeff() + S));
    worst = std::max(worst, (J.col(c) - E).cwiseAbs().maxCoeff() / bound);
  }
  return worst;
}

TEST_CASE("the inertial residual's Jacobian equals differences of the nodal sums",
          "[flexible][jacobian]") {
  for (const bool coupled : {true, false}) {
    INFO((coupled ? "coupled" : "lte"));
    CHECK(worst_ratio(random_damped_modal_data(7, 3, 1), coupled, 11) <= 1.0);
    CHECK(worst_ratio(random_damped_modal_data(25, 6, 2), coupled, 12) <= 1.0);
    CHECK(worst_ratio(damped_beam_data(), coupled, 13) <= 1.0);
  }
}

TEST_CASE("the Jacobian check catches a wrong sign in any column block", "[flexible][jacobian]") {
  // One column of each block (π̄, ω̄, q_f, q̇_f) with its sign flipped fails by a wide margin.
  const ModalData data = random_damped_modal_data(7, 3, 1);
  for (const Eigen::Index column : {1, 4, 7, 10}) {
    INFO("column " << column);
    CHECK(worst_ratio(data, true, 11, column) > 100.0);
  }
}

ModalData stiffened_random_data(int N, int n, unsigned seed) {
  ModalData data = random_damped_modal_data(N, n, seed);
  std::mt19937 rng(seed + 1000);
  data.geometric = testing::random_geometric_stiffness(n, rng);
  return data;
}

TEST_CASE("with geometric stiffening the Jacobian equals differences of the residual",
          "[flexible][jacobian][geometric]") {
  CHECK(worst_ratio(stiffened_random_data(7, 3, 1), true, 21) <= 1.0);
  CHECK(worst_ratio(stiffened_random_data(25, 6, 2), true, 22) <= 1.0);
  CHECK(worst_ratio(damped_beam_data(true), true, 23) <= 1.0);
  // A wrong sign in any column block is caught.
  const ModalData data = stiffened_random_data(7, 3, 1);
  for (const Eigen::Index column : {1, 4, 7, 10}) {
    INFO("column " << column);
    CHECK(worst_ratio(data, true, 21, column) > 100.0);
  }
}

TEST_CASE("the inertial residual's Jacobian allocates nothing and checks sizes",
          "[flexible][jacobian]") {
  const ModalData data = random_damped_modal_data(10, 4, 3);
  const ModalInvariants inv = make_modal_invariants(data);
  std::mt19937 rng(31);
  const Eigen::VectorXd q = random_vector(4, rng, 0.1), qd = random_vector(4, rng, 1.0);
  const Eigen::Vector3d w = random_vector(3, rng, 1.0);
  const Eigen::VectorXd x = random_vector(10, rng, 1.0);
  InertiaTerms terms = make_inertia_terms(4);
  evaluate_inertia_terms(inv, Eigen::Matrix3d::Identity(), q, w, qd, terms);
  InertiaJacobianScratch scratch = make_inertia_jacobian_scratch(4);
  Eigen::MatrixXd J(10, 14);
  const Eigen::VectorXd K = data.stiffness, D = modal_damping(data);
  CHECK(testing::count_allocations([&] {
          inertia_residual_jacobian(inv, terms, true, q, w, qd, x, K, D, scratch, J);
        }) == 0);
  // With geometric stiffening: the terms and the Jacobian allocate nothing either.
  const ModalData stiff = stiffened_random_data(10, 4, 3);
  const ModalInvariants inv_stiff = make_modal_invariants(stiff);
  CHECK(testing::count_allocations([&] {
          evaluate_inertia_terms(inv_stiff, Eigen::Matrix3d::Identity(), q, w, qd, terms);
          inertia_residual_jacobian(inv_stiff, terms, true, q, w, qd, x, K, D, scratch, J);
        }) == 0);
  CHECK(J.allFinite());
  Eigen::MatrixXd J_bad(10, 13);
  CHECK_THROWS_AS(inertia_residual_jacobian(inv, terms, true, q, w, qd, x, K, D, scratch, J_bad),
                  std::invalid_argument);
}

}  // namespace
}  // namespace flexref::flexible
