/// Tests of flexible/mass_matrix_solve: the O(n²) structured solves agree with a dense solve of
/// the whole (6+n)² system (the former evaluation: Cholesky of the unknown rows of M, or block
/// forward substitution for LTE) to rounding, for free (no known rows), pivot (3) and
/// prescribed (6) bodies, on random dense modal data (full m_ff) and on a beam; they allocate
/// nothing; a singular rigid block gives NaN, not garbage.
#include "flexible/mass_matrix_solve.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "flexible/beam_model.hpp"
#include "flexible/flexible_dynamics.hpp"
#include "flexible/inertia_terms.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/floating_point.hpp"
#include "tests/support/random_samples.hpp"

namespace flexref::flexible {
namespace {

using testing::kEps;
using testing::random_vector;

/// N nodes in a box off the origin (inertia about every axis), dense random mode shapes.
ModalData random_undamped_modal_data(int N, int n, unsigned seed) {
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
  data.stiffness = Eigen::VectorXd::Constant(n, 10.0);
  data.damping_ratio = Eigen::VectorXd::Zero(n);
  return data;
}

/// A 20-element clamped-free beam (24 modes) with a hub's worth of inertia added to J0 (the
/// beam's points are collinear: without a hub M is singular about the beam's axis).
ModalInvariants beam_with_hub_invariants() {
  BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.0, 0.0);
  p.elements = 20;
  p.EA = 1e5;
  p.EI_y = 4.0;
  p.EI_z = 3.2;
  p.boundary = BeamBoundary::kClampedFree;
  ModalInvariants inv = make_modal_invariants(make_beam_modal_data(p, 24));
  inv.mass += 10.0;
  inv.J0 += 0.25 * Eigen::Matrix3d::Identity();
  inv.I0 = inv.J0.trace() * Eigen::Matrix3d::Identity() - inv.J0;
  return inv;
}

struct System {
  Eigen::MatrixXd M;  ///< the dense (6+n)² mass matrix (coupled) at the state
  Eigen::VectorXd b;
  InertiaTerms terms;
};

System random_system(const ModalInvariants& inv, std::mt19937& rng) {
  const int n = inv.mode_count;
  System s;
  const Eigen::Matrix3d A =
      rotation::rotation_matrix(Eigen::Vector4d(random_vector(4, rng, 1.0)).normalized());
  const Eigen::VectorXd q = random_vector(n, rng, 0.1);
  const Eigen::VectorXd qd = random_vector(n, rng, 1.0);
  const Eigen::Vector3d w = random_vector(3, rng, 1.0);
  s.terms = make_inertia_terms(n);
  evaluate_inertia_terms(inv, A, q, w, qd, s.terms);
  s.M.resize(6 + n, 6 + n);
  flexible_mass_matrix(inv, A, q, s.M);
  s.b = random_vector(6 + n, rng, 10.0);
  return s;
}

/// The dense solution of rows [known, 6+n) with x's known entries given: Cholesky of the
/// unknown block (the former Model evaluation).
Eigen::VectorXd dense_coupled(const System& s, int known, const Eigen::VectorXd& x_known) {
  const Eigen::Index m = s.M.rows() - known;
  Eigen::VectorXd x = x_known;
  const Eigen::VectorXd rhs = s.b.tail(m) - s.M.bottomLeftCorner(m, known) * x_known.head(known);
  x.tail(m) = Eigen::LLT<Eigen::MatrixXd>(s.M.bottomRightCorner(m, m)).solve(rhs);
  return x;
}

/// Forward-error bound of two backward-stable solves of the unknown block U (dimension d):
/// each solves a system perturbed by |δU| ≤ c ε ‖U‖, c = 3d (Cholesky, Higham Thm. 10.4, plus
/// the substitutions), with a right-hand side b_u − M_uk x_k rounded by ε (|b| + ‖M‖ |x|); so
/// |δx| ≤ |U⁻¹| |δr| ≤ c ε (|b| + ‖M‖ |x|) / λ_min(U) each, twice that between the two.
double solve_tolerance(const System& s, int known, const Eigen::VectorXd& x) {
  const Eigen::Index m = s.M.rows() - known;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> unknown(s.M.bottomRightCorner(m, m));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> whole(s.M);
  const double c = 3.0 * static_cast<double>(m);
  return 2.0 * c * kEps * (s.b.norm() + whole.eigenvalues().cwiseAbs().maxCoeff() * x.norm()) /
         unknown.eigenvalues().minCoeff();
}

void check_coupled(const ModalInvariants& inv, unsigned seed) {
  std::mt19937 rng(seed);
  const ModalMassFactor factor(inv);
  MassSolveScratch scratch = make_mass_solve_scratch(inv.mode_count);
  for (int trial = 0; trial < 5; ++trial) {
    const System s = random_system(inv, rng);
    for (int known : {0, 3, 6}) {
      INFO("trial " << trial << ", known rows " << known);
      Eigen::VectorXd x = Eigen::VectorXd::Zero(s.b.size());
      x.head(known) = random_vector(known, rng, 1.0);
      const Eigen::VectorXd expected = dense_coupled(s, known, x);
      flexible::solve_coupled(factor, s.terms, known, s.b, scratch, x);
      const double tol = solve_tolerance(s, known, expected);
      CHECK((x - expected).norm() <= tol);
      // Not vacuous: the solution is O(1) and the tolerance is round-off.
      CHECK(expected.norm() > 1e-2);
      CHECK(tol < 1e-8 * expected.norm());
      // The known entries are untouched.
      CHECK(x.head(known) == expected.head(known));
    }
  }
}

TEST_CASE("the structured coupled solve equals the dense Cholesky solve", "[flexible][solve]") {
  check_coupled(make_modal_invariants(random_undamped_modal_data(12, 5, 1)), 11);
  check_coupled(make_modal_invariants(random_undamped_modal_data(60, 17, 2)), 12);
  check_coupled(beam_with_hub_invariants(), 13);
}

TEST_CASE("m_ff's factor groups the modes that do not couple", "[flexible][solve]") {
  // Dense random modes couple all with all: one group, the identity order. The beam's axial,
  // bending-xy and bending-xz modes share no direction: three groups, m_ff block diagonal in
  // the permuted order. Either way m_ff⁻¹ v and the pair L⁻¹ P, Pᵀ L⁻ᵀ equal the dense
  // Cholesky solve: both are backward stable on m_ff (cond ≈ 1 for mass-normalized modes), so
  // 100 n ε relative.
  std::mt19937 rng(17);
  const ModalInvariants dense = make_modal_invariants(random_undamped_modal_data(30, 9, 4));
  const ModalInvariants beam = beam_with_hub_invariants();
  CHECK(ModalMassFactor(dense).group_count() == 1);
  CHECK(ModalMassFactor(beam).group_count() == 3);
  // The beam's permutation is not its own inverse (a cycle longer than 2), so swapping P and Pᵀ
  // in both substitutions would break m_ff x = b below.
  const ModalMassFactor beam_factor(beam);
  const std::vector<Eigen::Index>& order = beam_factor.order();
  bool involution = true;
  for (std::size_t k = 0; k < order.size(); ++k) {
    involution =
        involution && order[static_cast<std::size_t>(order[k])] == static_cast<Eigen::Index>(k);
  }
  CHECK_FALSE(involution);
  for (const ModalInvariants* inv : {&dense, &beam}) {
    const ModalMassFactor factor(*inv);
    const Eigen::Index n = inv->mode_count;
    const Eigen::VectorXd b = random_vector(n, rng, 1.0);
    const Eigen::VectorXd expected = inv->m_ff.llt().solve(b);
    Eigen::VectorXd x = b;
    factor.solve_in_place(x);
    CHECK((x - expected).norm() <= 100.0 * static_cast<double>(n) * kEps * expected.norm());
    // ‖L⁻¹ P b‖² = bᵀ m_ff⁻¹ b: the forward half alone is a factor of m_ff's inverse.
    Eigen::VectorXd y = b;
    factor.forward_in_place(y);
    CHECK(std::abs(y.squaredNorm() - b.dot(expected)) <=
          100.0 * static_cast<double>(n) * kEps * b.dot(expected));
    // Pᵀ L⁻ᵀ undoes L⁻¹ P's permutation: a sign or order error in either breaks m_ff x = b.
    CHECK((inv->m_ff * x - b).norm() <= 100.0 * static_cast<double>(n) * kEps * b.norm());
    CHECK(testing::count_allocations([&] { factor.solve_in_place(x); }) == 0);
  }
}

TEST_CASE("the structured LTE and modal-row solves equal dense substitution", "[flexible][solve]") {
  const ModalInvariants inv = make_modal_invariants(random_undamped_modal_data(30, 9, 3));
  const int n = inv.mode_count;
  const ModalMassFactor factor(inv);
  MassSolveScratch scratch = make_mass_solve_scratch(n);
  std::mt19937 rng(31);
  for (int trial = 0; trial < 5; ++trial) {
    System s = random_system(inv, rng);
    // LTE: the rigid rows without M_rf (block lower triangular), solved by a dense LU.
    Eigen::MatrixXd M_lte = s.M;
    M_lte.topRightCorner(6, n).setZero();
    for (int known : {0, 3, 6}) {
      INFO("trial " << trial << ", known rows " << known);
      Eigen::VectorXd x = Eigen::VectorXd::Zero(6 + n);
      x.head(known) = random_vector(known, rng, 1.0);
      const Eigen::Index m = 6 + n - known;
      Eigen::VectorXd expected = x;
      expected.tail(m) = M_lte.bottomRightCorner(m, m).partialPivLu().solve(
          s.b.tail(m) - M_lte.bottomLeftCorner(m, known) * x.head(known));
      solve_lte(factor, s.terms, known, s.b, scratch, x);
      CHECK((x - expected).norm() <= solve_tolerance(s, known, expected));
      CHECK(expected.norm() > 1e-2);
    }
    // Modal rows with all six rigid accelerations given.
    Eigen::VectorXd x = Eigen::VectorXd::Zero(6 + n);
    x.head<6>() = random_vector(6, rng, 1.0);
    Eigen::VectorXd expected = x;
    expected.tail(n) = s.M.bottomRightCorner(n, n).llt().solve(
        s.b.tail(n) - s.M.bottomLeftCorner(n, 6) * x.head<6>());
    solve_modal_rows(factor, s.terms, s.b, scratch, x);
    CHECK((x - expected).norm() <= solve_tolerance(s, 6, expected));
  }
}

TEST_CASE("the structured solves allocate nothing and check sizes", "[flexible][solve]") {
  const ModalInvariants inv = make_modal_invariants(random_undamped_modal_data(20, 8, 4));
  const ModalMassFactor factor(inv);
  MassSolveScratch scratch = make_mass_solve_scratch(8);
  std::mt19937 rng(41);
  const System s = random_system(inv, rng);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(14);
  for (int known : {0, 3, 6}) {
    CHECK(testing::count_allocations(
              [&] { solve_coupled(factor, s.terms, known, s.b, scratch, x); }) == 0);
    CHECK(testing::count_allocations([&] { solve_lte(factor, s.terms, known, s.b, scratch, x); }) ==
          0);
  }
  CHECK(testing::count_allocations([&] { solve_modal_rows(factor, s.terms, s.b, scratch, x); }) ==
        0);
  CHECK(x.allFinite());
  Eigen::VectorXd x_bad = Eigen::VectorXd::Zero(13);
  CHECK_THROWS_AS(solve_coupled(factor, s.terms, 0, s.b, scratch, x_bad), std::invalid_argument);
  CHECK_THROWS_AS(solve_coupled(factor, s.terms, 7, s.b, scratch, x), std::invalid_argument);
}

TEST_CASE("a singular rigid block gives NaN accelerations", "[flexible][solve]") {
  // No inertia about body x (the rotation row 3 of M_rr and its coupling zeroed): the Schur
  // complement has a zero pivot. The former dense evaluation returned unchecked garbage.
  const ModalInvariants inv = make_modal_invariants(random_undamped_modal_data(20, 4, 5));
  const ModalMassFactor factor(inv);
  MassSolveScratch scratch = make_mass_solve_scratch(4);
  std::mt19937 rng(51);
  System s = random_system(inv, rng);
  s.terms.M_rr.row(3).setZero();
  s.terms.M_rr.col(3).setZero();
  s.terms.M_rf.row(3).setZero();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(10);
  solve_coupled(factor, s.terms, 3, s.b, scratch, x);
  CHECK(std::isnan(x(3)));
  CHECK(x.head<3>() == Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace flexref::flexible
