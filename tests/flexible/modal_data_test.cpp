/// Tests of core/modal_data: validation of user data, the modal mass matrix and its
/// dependence check, natural frequencies and damping, and — the key requirement for
/// these quantities — the invariant-based s_t(q_f), Ī_θθ(q_f), Ī_θf(q_f) against the direct
/// nodal sums at random states (fixed seeds), for generic data with a non-diagonal m_ff and for
/// beams of 20 and 200 elements.
#include "flexible/modal_data.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

#include "flexible/beam_model.hpp"
#include "rotation/so3.hpp"
#include "tests/support/floating_point.hpp"
#include "tests/support/random_samples.hpp"

namespace flexref::core {
namespace {

using Catch::Matchers::Contains;

using testing::kEps;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// N nodes scattered in a box away from the origin, masses in [0.1, 2], dense random mode
// shapes (so m_ff is full and every Cartesian pair of invariants is non-zero).
flexible::ModalData random_modal_data(int N, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> mass(0.1, 2.0);
  std::uniform_real_distribution<double> coordinate(-1.0, 3.0);
  std::normal_distribution<double> normal;
  flexible::ModalData data;
  data.mass.resize(N);
  data.p_BoNode_B.resize(3, N);
  data.phi.resize(3 * N, n);
  for (int k = 0; k < N; ++k) {
    data.mass(k) = mass(rng);
    for (int a = 0; a < 3; ++a) data.p_BoNode_B(a, k) = coordinate(rng);
  }
  for (Eigen::Index r = 0; r < data.phi.rows(); ++r) {
    for (Eigen::Index c = 0; c < n; ++c) data.phi(r, c) = 0.1 * normal(rng);
  }
  data.stiffness.resize(n);
  data.damping_ratio.resize(n);
  for (int i = 0; i < n; ++i) {
    data.stiffness(i) = 10.0 * (i + 1);
    data.damping_ratio(i) = 0.01 * i;
  }
  return data;
}

// Round-off bound for comparing two evaluations of the same sums. Each entry is, in either
// evaluation, a sum over the N nodes and over at most n² mode pairs of products whose
// magnitudes add up to at most `scale` (below); recursive summation of T terms errs by at most
// about T ε Σ|terms| (Higham, "Accuracy and stability of numerical algorithms", §4.2), so
// 10 (N + n²) ε scale bounds the difference with a margin for the few flops per term.
double invariant_roundoff(const flexible::ModalData& data, double scale) {
  const double n = data.mode_count();
  return 10.0 * (data.node_count() + n * n) * kEps * scale;
}

// Σ m_k (|x_k| + ‖Φ_k‖ |q|)^p ‖Φ_k‖^r: bounds Σ|terms| of s_t (p = 1), Ī_θθ (p = 2) and
// Ī_θf (p = 1, r = 1).
double invariant_magnitude(const flexible::ModalData& data, const Eigen::VectorXd& q, int p,
                           int r) {
  double sum = 0.0;
  for (int k = 0; k < data.node_count(); ++k) {
    const double phi = data.mode_rows(k).norm();
    const double u = data.p_BoNode_B.col(k).norm() + phi * q.norm();
    sum += data.mass(k) * std::pow(u, p) * std::pow(phi, r);
  }
  return sum;
}

void check_against_direct_sums(const flexible::ModalData& data, unsigned seed, double q_size) {
  const flexible::ModalInvariants inv = make_modal_invariants(data);
  const int n = data.mode_count();
  std::mt19937 rng(seed);
  for (int sample = 0; sample < 10; ++sample) {
    // Sample 0 is the undeformed state q_f = 0.
    const Eigen::VectorXd q =
        sample == 0 ? Eigen::VectorXd::Zero(n) : testing::random_vector(n, rng, q_size);
    INFO("sample " << sample << ", |q| = " << q.norm());
    const Eigen::Vector3d s = first_moment(inv, q);
    const Eigen::Vector3d s_direct = first_moment_direct(data, q);
    INFO("s_t " << s.transpose() << " direct " << s_direct.transpose());
    CHECK((s - s_direct).cwiseAbs().maxCoeff() <
          invariant_roundoff(data, invariant_magnitude(data, q, 1, 0)));

    const Eigen::Matrix3d I = inertia_theta_theta(inv, q);
    const Eigen::Matrix3d I_direct = inertia_theta_theta_direct(data, q);
    INFO("I_theta_theta\n" << I << "\ndirect\n" << I_direct);
    // ũᵀũ = |u|² I − u uᵀ: the entries add up to at most 2 Σ m |u|².
    CHECK((I - I_direct).cwiseAbs().maxCoeff() <
          invariant_roundoff(data, 2.0 * invariant_magnitude(data, q, 2, 0)));

    const Eigen::Matrix3Xd G = inertia_theta_f(inv, q);
    const Eigen::Matrix3Xd G_direct = inertia_theta_f_direct(data, q);
    INFO("I_theta_f\n" << G << "\ndirect\n" << G_direct);
    CHECK((G - G_direct).cwiseAbs().maxCoeff() <
          invariant_roundoff(data, 2.0 * invariant_magnitude(data, q, 1, 1)));
  }
  // The invariants themselves against their definitions.
  CHECK((inv.m_ff - modal_mass_matrix(data)).cwiseAbs().maxCoeff() <
        invariant_roundoff(data, inv.m_ff.diagonal().sum()));
  CHECK(
      (inv.I0 - inertia_theta_theta_direct(data, Eigen::VectorXd::Zero(n))).cwiseAbs().maxCoeff() <
      invariant_roundoff(data, inv.I0.trace()));
}

TEST_CASE("invariant-based inertia equals the direct nodal sums: generic data", "[core][modal]") {
  // Displacements Φq of the size of the node positions, so the quadratic terms matter.
  check_against_direct_sums(random_modal_data(50, 7, 11), 101, 3.0);
  check_against_direct_sums(random_modal_data(3, 1, 12), 102, 3.0);
  check_against_direct_sums(random_modal_data(2, 4, 13), 103, 3.0);  // 4 modes on 6 DOF
}

TEST_CASE("invariant-based inertia equals the direct nodal sums: beams of 20 and 200 elements",
          "[core][modal]") {
  for (const int elements : {20, 200}) {
    for (const flexible::BeamBoundary boundary :
         {flexible::BeamBoundary::kClampedFree, flexible::BeamBoundary::kFreeFree}) {
      flexible::BeamParameters p;
      p.origin = Eigen::Vector3d(0.1, 0.05, -0.02);
      p.length = 1.0;
      p.elements = elements;
      p.EA = 1e5;
      p.EI_y = 4.0;
      p.EI_z = 3.2;
      p.rho_A = 1.0;
      p.boundary = boundary;
      // 10 modes: bending in both planes and (200 elements, free-free) axial ones.
      const flexible::ModalData data = make_beam_modal_data(p, 10);
      INFO("elements " << elements);
      // Unit modal mass on a 1 kg beam: |Φ| ≈ 1 m, so q ≈ 0.3 deflects the beam by ≈ 0.3 L.
      check_against_direct_sums(data, 200 + static_cast<unsigned>(elements), 0.3);
    }
  }
}

TEST_CASE("a single node and mode, by hand", "[core][modal]") {
  // m = 2 at x = (1, 0, 0), Φ = (0, 1, 0): ū = (1, q, 0).
  flexible::ModalData data;
  data.mass = Eigen::VectorXd::Constant(1, 2.0);
  data.p_BoNode_B = Eigen::Vector3d(1.0, 0.0, 0.0);
  data.phi = Eigen::Vector3d(0.0, 1.0, 0.0);
  data.stiffness = Eigen::VectorXd::Constant(1, 8.0);
  data.damping_ratio = Eigen::VectorXd::Constant(1, 0.05);
  const flexible::ModalInvariants inv = make_modal_invariants(data);
  CHECK(inv.mass == 2.0);
  CHECK(inv.s0 == Eigen::Vector3d(2.0, 0.0, 0.0));
  CHECK(inv.S.col(0) == Eigen::Vector3d(0.0, 2.0, 0.0));
  CHECK(inv.m_ff(0, 0) == 2.0);
  CHECK(inv.I0 == Eigen::Vector3d(0.0, 2.0, 2.0).asDiagonal().toDenseMatrix());
  CHECK(inv.I_theta_f0.col(0) == Eigen::Vector3d(0.0, 0.0, 2.0));  // m x × Φ
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, 0.5);
  // s_t = m ū = (2, 1, 0); Ī_θθ = m (|ū|² I − ū ūᵀ) with |ū|² = 1.25;
  // Ī_θf = m ū × Φ = 2 (1, 0.5, 0) × (0, 1, 0) = (0, 0, 2).
  CHECK(first_moment(inv, q) == Eigen::Vector3d(2.0, 1.0, 0.0));
  Eigen::Matrix3d I_expected;
  I_expected << 2.0 * 1.25 - 2.0, -1.0, 0.0,  //
      -1.0, 2.0 * 1.25 - 0.5, 0.0,            //
      0.0, 0.0, 2.0 * 1.25;
  CHECK((inertia_theta_theta(inv, q) - I_expected).cwiseAbs().maxCoeff() < 4 * kEps);
  CHECK(inertia_theta_f(inv, q).col(0) == Eigen::Vector3d(0.0, 0.0, 2.0));
  // ω = √(K/μ) = 2; d = 2 ζ ω μ = 2 · 0.05 · 2 · 2 = 0.4.
  CHECK(natural_frequencies(data)(0) == Approx(2.0).epsilon(4 * kEps));
  CHECK(modal_damping(data)(0) == Approx(0.4).epsilon(4 * kEps));
}

TEST_CASE("inertia_theta_f writes into a block and checks sizes", "[core][modal]") {
  const flexible::ModalData data = random_modal_data(10, 3, 21);
  const flexible::ModalInvariants inv = make_modal_invariants(data);
  const Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(3, -1.0, 2.0);
  Eigen::MatrixXd mass_matrix = Eigen::MatrixXd::Zero(9, 9);
  inertia_theta_f(inv, q, mass_matrix.block(3, 6, 3, 3));
  CHECK(mass_matrix.block(3, 6, 3, 3) == Eigen::MatrixXd(inertia_theta_f(inv, q)));
  CHECK(mass_matrix.block(0, 0, 3, 9).isZero(0.0));
  Eigen::MatrixXd wrong(3, 2);
  CHECK_THROWS_AS(inertia_theta_f(inv, q, wrong), std::invalid_argument);
  CHECK_THROWS_AS(first_moment(inv, Eigen::VectorXd::Zero(2)), std::invalid_argument);
  CHECK_THROWS_AS(inertia_theta_theta(inv, Eigen::VectorXd::Zero(4)), std::invalid_argument);
  CHECK_THROWS_AS(first_moment_direct(data, Eigen::VectorXd::Zero(2)), std::invalid_argument);
}

TEST_CASE("natural frequencies of a non-diagonal modal mass matrix", "[core][modal]") {
  const flexible::ModalData data = random_modal_data(20, 4, 31);
  const Eigen::MatrixXd m_ff = modal_mass_matrix(data);
  REQUIRE(std::abs(m_ff(0, 1)) > 1e-3 * m_ff(0, 0));  // really non-diagonal
  const Eigen::VectorXd omega = natural_frequencies(data);
  const Eigen::MatrixXd K = data.stiffness.asDiagonal();
  for (int i = 0; i < 4; ++i) {
    if (i > 0) CHECK(omega(i) >= omega(i - 1));
    // K − ω² m_ff is singular: its smallest singular value relative to the largest is at
    // the eigen-solver's rounding, ≈ n ε·cond(m_ff) (cond ≈ 10 here); 1e-12 leaves margin.
    const Eigen::MatrixXd A = K - omega(i) * omega(i) * m_ff;
    const Eigen::VectorXd sv = A.jacobiSvd().singularValues();
    CHECK(sv(3) < 1e-12 * (K.norm() + omega(i) * omega(i) * m_ff.norm()));
  }
}

TEST_CASE("first_dependent_mode finds the first mode in the span of the previous ones",
          "[core][modal]") {
  CHECK(flexible::first_dependent_mode(Eigen::MatrixXd::Identity(3, 3)) == -1);
  CHECK(flexible::first_dependent_mode(Eigen::MatrixXd(0, 0)) == -1);
  // Modes (1, 0), (0, 1), (1, 1) in a 2-D space: the third is dependent.
  Eigen::Matrix<double, 2, 3> phi;
  phi << 1, 0, 1, 0, 1, 1;
  CHECK(flexible::first_dependent_mode(phi.transpose() * phi) == 2);
  // A mode within an angle 1e-6 of another (sin² = 1e-12 < 1e-10): dependent.
  phi << 1, 1, 0, 0, 1e-6, 1;
  CHECK(flexible::first_dependent_mode(phi.transpose() * phi) == 1);
  // A zero mode.
  Eigen::Matrix2d zero = Eigen::Matrix2d::Zero();
  zero(0, 0) = 1.0;
  CHECK(flexible::first_dependent_mode(zero) == 1);
}

// validate() throws std::invalid_argument whose message contains `fragment`.
void require_invalid(const flexible::ModalData& data, const std::string& fragment) {
  try {
    data.validate();
  } catch (const std::invalid_argument& e) {
    CHECK_THAT(std::string(e.what()), Contains(fragment));
    return;
  }
  FAIL("validate() accepted data that should mention: " << fragment);
}

TEST_CASE("validate names each class of bad data", "[core][modal]") {
  const flexible::ModalData good = random_modal_data(4, 2, 41);
  REQUIRE_NOTHROW(good.validate());
  flexible::ModalData d = good;
  d.mass.resize(0);
  d.p_BoNode_B.resize(3, 0);
  d.phi.resize(0, 2);
  require_invalid(d, "no nodes");
  d = good;
  d.p_BoNode_B.conservativeResize(3, 3);
  require_invalid(d, "4 nodal masses but 3 node positions");
  d = good;
  d.phi.conservativeResize(11, 2);
  require_invalid(d, "11 rows, expected 3 × 4 nodes = 12");
  d = good;
  d.stiffness.resize(3);
  require_invalid(d, "2 modes but 3 modal stiffnesses");
  d = good;
  d.damping_ratio.resize(0);
  require_invalid(d, "damping ratios");
  d = good;
  d.node_names = {"a", "b"};
  require_invalid(d, "node names");
  d = good;
  d.mode_names = {"x"};
  require_invalid(d, "mode names");
  d = good;
  d.mass(2) = 0.0;
  require_invalid(d, "node 3 has mass 0");
  d = good;
  d.mass(1) = -1.0;
  require_invalid(d, "node 2 has mass -1");
  d = good;
  d.mass(0) = kNaN;
  require_invalid(d, "node 1 has mass nan");
  d = good;
  d.p_BoNode_B(1, 3) = std::numeric_limits<double>::infinity();
  require_invalid(d, "node 4 has a non-finite position");
  d = good;
  d.phi(7, 1) = kNaN;  // row 7: node 3, y
  require_invalid(d, "mode 2 has a non-finite displacement at node 3");
  d = good;
  d.stiffness(0) = -1.0;
  require_invalid(d, "mode 1 has stiffness -1");
  d = good;
  d.stiffness(1) = kNaN;
  require_invalid(d, "mode 2 has stiffness nan");
  d = good;
  d.damping_ratio(1) = -0.1;
  require_invalid(d, "mode 2 has damping ratio -0.1");
  d = good;
  d.node_names = {"a", "b", "", "d"};
  require_invalid(d, "node 3 has an empty name");
  d = good;
  d.node_names = {"a", "b", "c", "b"};
  require_invalid(d, "duplicate node name 'b'");
  d = good;
  d.phi.col(1) = 2.0 * d.phi.col(0);
  require_invalid(d, "mode 2 is (numerically) a linear combination");
  d = good;
  d.phi.col(0).setZero();
  d.mode_names = {"first", "second"};
  require_invalid(d, "mode 1 ('first') has no displacement at any node");
  // Zero stiffness (a mechanism) and zero modes are allowed.
  d = good;
  d.stiffness(0) = 0.0;
  CHECK_NOTHROW(d.validate());
  d = good;
  d.phi.resize(12, 0);
  d.stiffness.resize(0);
  d.damping_ratio.resize(0);
  CHECK_NOTHROW(d.validate());
  CHECK_THROWS_AS(make_modal_invariants(flexible::ModalData{}), std::invalid_argument);
}

}  // namespace
}  // namespace flexref::core
