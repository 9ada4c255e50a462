/// Tests of flexible/flexible_dynamics: the quasi-velocity mass matrix M, the quadratic-velocity
/// vector Qv and the kinetic energy of one flexible body (docs/design/model.md, "Equations of
/// motion, quasi-velocity form"), at random states with fixed seeds:
///   (a) invariant-based M, Qv, T equal the direct nodal sums to round-off;
///   (b) M is exactly symmetric and positive definite;
///   (c) ½ vᵀ M v equals ½ Σ m_k |ṙ_k|² with ṙ_k from eq. 14;
///   (d) the virtual work of the nodal inertia forces, Σ m_k δr_kᵀ r̈_k with r̈_k from eq. 17
///       and δr_k = δR − A ũ_k δπ̄ + A Φ_k δq_f, equals δᵀ (M a − Qv) for random a, δ — the
///       sign-error catcher (and a check that it does catch the usual sign errors);
///   (e) eq. 14 and eq. 17 themselves: ṙ_k, r̈_k along a smooth motion against central
///       differences of r_k(t) = R + A(θ) (x_k + Φ_k q_f).
#include "flexible/flexible_dynamics.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "flexible/beam_model.hpp"
#include "flexible/modal_data.hpp"
#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/floating_point.hpp"
#include "tests/support/random_samples.hpp"

namespace flexref::core {
namespace {

using testing::kEps;
using testing::random_vector;

// N nodes in a box off the origin, masses in [0.1, 2], dense random mode shapes (full m_ff,
// every Cartesian pair of invariants non-zero).
flexible::ModalData random_dense_modal_data(int N, int n, unsigned seed) {
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
    for (Eigen::Index c = 0; c < n; ++c) data.phi(r, c) = 0.3 * normal(rng);
  }
  data.stiffness = Eigen::VectorXd::Constant(n, 10.0);
  data.damping_ratio = Eigen::VectorXd::Zero(n);
  return data;
}

flexible::ModalData clamped_beam_data() {
  flexible::BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.05, -0.02);
  p.elements = 20;
  p.EA = 1e5;
  p.EI_y = 4.0;
  p.EI_z = 3.2;
  p.boundary = flexible::BeamBoundary::kClampedFree;
  return make_beam_modal_data(p, 6);
}

Eigen::Vector3d random_vector3(std::mt19937& rng, double size) {
  return random_vector(3, rng, size);
}

struct State {
  Eigen::Matrix3d A;
  Eigen::VectorXd q, qd;
  Eigen::Vector3d Rd, w;
};

State random_state(int n, std::mt19937& rng, double q_size) {
  State s;
  s.A = rotation::rotation_matrix(rotation::exp_quaternion(random_vector3(rng, 2.0)));
  s.q = random_vector(n, rng, q_size);
  s.qd = random_vector(n, rng, 1.0);
  s.Rd = random_vector3(rng, 1.0);
  s.w = random_vector3(rng, 1.5);
  return s;
}

// Bound on Σ|terms| of any entry of M, Qv (and, with |δ|, |a|, of the virtual work): every
// term is m_k times at most two position-like factors (|ū_k| ≤ U, ‖Φ_k‖ ≤ P, entries of A ≤ 1)
// and at most two velocity factors (|ω̄|, ‖Φ_k‖ |q̇|: coefficient ≤ 2), so
// m (1 + U + P)² (1 + |ω̄| + |q̇|)² bounds it.
double term_magnitude(const flexible::ModalData& data, const State& s) {
  double U = 0.0, P = 0.0;
  for (int k = 0; k < data.node_count(); ++k) {
    P = std::max(P, data.mode_rows(k).norm());
    U = std::max(U, data.p_BoNode_B.col(k).norm() + data.mode_rows(k).norm() * s.q.norm());
  }
  const double v = 1.0 + s.w.norm() + s.qd.norm() + s.Rd.norm();
  return data.mass.sum() * (1.0 + U + P) * (1.0 + U + P) * v * v;
}

// Round-off between two evaluations of the same sums: each entry is a sum over the N nodes
// (nodal) or over ≤ 9 n² mode pairs of invariants that are themselves N-term sums; recursive
// summation of T terms errs by ≤ T ε Σ|terms| (Higham, "Accuracy and stability of numerical
// algorithms", §4.2), so 10 (N + 9 n²) ε scale bounds the difference with a margin of 10 for
// the few flops per term.
double evaluation_roundoff(const flexible::ModalData& data, double scale) {
  const double n = data.mode_count();
  return 10.0 * (data.node_count() + 9.0 * n * n) * kEps * scale;
}

// ū_k, and r̈_k from eq. 17 written out (not via L_k):
// r̈ = R̈ + A [α̅ × ū + ω̄ × (ω̄ × ū) + 2 ω̄ × Φ q̇ + Φ q̈].
Eigen::Vector3d node_acceleration(const flexible::ModalData& data, int k, const State& s,
                                  const Eigen::Vector3d& Rdd, const Eigen::Vector3d& alpha,
                                  const Eigen::VectorXd& qdd) {
  const auto Phi = data.mode_rows(k);
  const Eigen::Vector3d u = data.p_BoNode_B.col(k) + Phi * s.q;
  return Rdd +
         s.A * (alpha.cross(u) + s.w.cross(s.w.cross(u)) + 2.0 * s.w.cross(Phi * s.qd) + Phi * qdd);
}

void check_against_nodes(const flexible::ModalData& data, unsigned seed, double q_size,
                         bool collinear = false) {
  const flexible::ModalInvariants inv = make_modal_invariants(data);
  const int n = data.mode_count();
  std::mt19937 rng(seed);
  Eigen::MatrixXd M(6 + n, 6 + n), M_nodes(6 + n, 6 + n);
  Eigen::VectorXd Qv(6 + n), Qv_nodes(6 + n);
  for (int trial = 0; trial < 20; ++trial) {
    const State s = random_state(n, rng, q_size);
    INFO("trial " << trial);
    const double tol = evaluation_roundoff(data, term_magnitude(data, s));

    // (a) invariants against the nodal sums.
    flexible_mass_matrix(inv, s.A, s.q, M);
    flexible_mass_matrix_by_nodes(data, s.A, s.q, M_nodes);
    CHECK((M - M_nodes).cwiseAbs().maxCoeff() <= tol);
    flexible_quadratic_velocity(inv, s.A, s.q, s.w, s.qd, Qv);
    flexible_quadratic_velocity_by_nodes(data, s.A, s.q, s.w, s.qd, Qv_nodes);
    CHECK((Qv - Qv_nodes).cwiseAbs().maxCoeff() <= tol);

    // (b) exactly symmetric (transposed copies), positive definite.
    CHECK(M == M.transpose());
    if (collinear) {
      // The beam's material points lie on one straight line (rotary inertia neglected), and
      // its bending modes in the xy and xz planes have the same shapes (uniform clamped beam):
      // spinning the deformed beam about its axis is a rigid spin plus a modal rate, and moves
      // no node. M is then only semi-definite: smallest eigenvalue 0 to the round-off of an
      // eigen-solve, (6 + n) tol. At q_f = 0 the null vector is the rigid spin ω̄ = e_x,
      // Ṙ = −A (e_x × p) (p on the line).
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
      CHECK(std::abs(eig.eigenvalues().minCoeff()) <= (6.0 + n) * tol);
      CHECK(eig.eigenvalues()(1) > 1e3 * (6.0 + n) * tol);  // only one null direction
      Eigen::MatrixXd M0(6 + n, 6 + n);
      flexible_mass_matrix(inv, s.A, Eigen::VectorXd::Zero(n), M0);
      const Eigen::Vector3d p = data.p_BoNode_B.col(0);
      Eigen::VectorXd spin = Eigen::VectorXd::Zero(6 + n);
      spin.head<3>() = -s.A * Eigen::Vector3d::UnitX().cross(p);
      spin(3) = 1.0;
      CHECK((M0 * spin).cwiseAbs().maxCoeff() <= tol * (1.0 + p.norm()));
    } else {
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
      CHECK(eig.eigenvalues().minCoeff() > 0.0);
      CHECK(Eigen::LLT<Eigen::MatrixXd>(M).info() == Eigen::Success);
    }

    // (c) ½ vᵀ M v = ½ Σ m |ṙ|², and the block evaluation of T.
    Eigen::VectorXd v(6 + n);
    v << s.Rd, s.w, s.qd;
    const double T_M = 0.5 * v.dot(M * v);
    const double T_nodes = flexible_kinetic_energy_by_nodes(data, s.A, s.q, s.Rd, s.w, s.qd);
    const double T_inv = flexible_kinetic_energy(inv, s.A, s.q, s.Rd, s.w, s.qd);
    // T is a sum of the same kind of terms as M's entries times two velocities ((6 + n)² of
    // them in vᵀMv): the bound of M's entries times (6 + n)² covers it.
    const double tol_T = tol * (6.0 + n) * (6.0 + n);
    CHECK(std::abs(T_M - T_nodes) <= tol_T);
    CHECK(std::abs(T_inv - T_nodes) <= tol_T);

    // (d) virtual work of the nodal inertia forces = δᵀ (M a − Qv).
    const Eigen::Vector3d Rdd = random_vector3(rng, 1.0);
    const Eigen::Vector3d alpha = random_vector3(rng, 1.0);
    const Eigen::VectorXd qdd = random_vector(n, rng, 1.0);
    const Eigen::Vector3d dR = random_vector3(rng, 1.0);
    const Eigen::Vector3d dpi = random_vector3(rng, 1.0);
    const Eigen::VectorXd dq = random_vector(n, rng, 1.0);
    double work_nodes = 0.0;
    Eigen::Vector3d coriolis_theta = Eigen::Vector3d::Zero();  // Σ m ũ ω̄̃ Φ q̇ (for (d'))
    for (int k = 0; k < data.node_count(); ++k) {
      const auto Phi = data.mode_rows(k);
      const Eigen::Vector3d u = data.p_BoNode_B.col(k) + Phi * s.q;
      const Eigen::Vector3d dr =
          dR - s.A * u.cross(dpi) + s.A * (Phi * dq);  // δR − A ũ δπ̄ + A Φ δq
      work_nodes += data.mass(k) * dr.dot(node_acceleration(data, k, s, Rdd, alpha, qdd));
      coriolis_theta += data.mass(k) * u.cross(s.w.cross(Phi * s.qd));
    }
    Eigen::VectorXd a(6 + n), delta(6 + n);
    a << Rdd, alpha, qdd;
    delta << dR, dpi, dq;
    const double work = delta.dot(M * a - Qv);
    // Terms of Σ|·| ≤ term_magnitude·(1 + |a|)·|δ| per entry, (6 + n) entries of δ.
    const double tol_work = tol * (1.0 + a.norm()) * delta.norm() * (6.0 + n);
    CHECK(std::abs(work - work_nodes) <= tol_work);

    // (d') the check catches the usual sign errors: by a margin of > 10³ over its tolerance.
    Eigen::MatrixXd M_wrong = M;  // s̃_t Aᵀ with the other sign (in both off-diagonal blocks)
    M_wrong.block<3, 3>(0, 3) *= -1.0;
    M_wrong.block<3, 3>(3, 0) *= -1.0;
    CHECK(std::abs(delta.dot(M_wrong * a - Qv) - work_nodes) > 1e3 * tol_work);
    Eigen::VectorXd Qv_wrong = Qv;  // + 2 Σ m ũ ω̄̃ Φ q̇ instead of −
    Qv_wrong.segment<3>(3) += 4.0 * coriolis_theta;
    CHECK(std::abs(delta.dot(M * a - Qv_wrong) - work_nodes) > 1e3 * tol_work);
    Qv_wrong = Qv;  // + ω̄̃ Ī_θθ ω̄ instead of −
    Qv_wrong.segment<3>(3) += 2.0 * s.w.cross(M.block<3, 3>(3, 3) * s.w);
    CHECK(std::abs(delta.dot(M * a - Qv_wrong) - work_nodes) > 1e3 * tol_work);
  }
}

TEST_CASE("flexible M, Qv, T: invariants = nodal sums, SPD, energy, virtual work (random data)",
          "[core][flexible]") {
  // 5 nodes, 3 modes (the brief's small case) and a larger generic body.
  check_against_nodes(random_dense_modal_data(5, 3, 11), 101, 0.5);
  check_against_nodes(random_dense_modal_data(40, 7, 12), 102, 0.5);
}

TEST_CASE("flexible M, Qv, T: invariants = nodal sums on a 20-element beam", "[core][flexible]") {
  // Unit modal mass on a 1 kg beam: |Φ| ≈ 1 m, q ≈ 0.3 deflects the beam by ≈ 0.3 L.
  check_against_nodes(clamped_beam_data(), 103, 0.3, /*collinear=*/true);
}

TEST_CASE("flexible M and Qv of a single node by hand", "[core][flexible]") {
  // m = 2 at x = (1, 0, 0), Φ = (0, 1, 0), A = I, q = 0: ū = (1, 0, 0), s_t = (2, 0, 0),
  // Ī_θθ = 2 diag(0, 1, 1), Ī_θf = 2 ũ Φ = (0, 0, 2), m_ff = 2, S = (0, 2, 0).
  flexible::ModalData data;
  data.mass = Eigen::VectorXd::Constant(1, 2.0);
  data.p_BoNode_B = Eigen::Vector3d(1.0, 0.0, 0.0);
  data.phi = Eigen::Vector3d(0.0, 1.0, 0.0);
  data.stiffness = Eigen::VectorXd::Constant(1, 8.0);
  data.damping_ratio = Eigen::VectorXd::Zero(1);
  const flexible::ModalInvariants inv = make_modal_invariants(data);
  Eigen::MatrixXd M(7, 7);
  flexible_mass_matrix(inv, Eigen::Matrix3d::Identity(), Eigen::VectorXd::Zero(1), M);
  Eigen::MatrixXd expected(7, 7);
  // −A s̃_t = −hat(2,0,0): rows (0,0,0), (0,0,2), (0,−2,0).
  expected << 2, 0, 0, 0, 0, 0, 0,  //
      0, 2, 0, 0, 0, 2, 2,          //
      0, 0, 2, 0, -2, 0, 0,         //
      0, 0, 0, 0, 0, 0, 0,          //
      0, 0, -2, 0, 2, 0, 0,         //
      0, 2, 0, 0, 0, 2, 2,          //
      0, 2, 0, 0, 0, 2, 2;
  CHECK((M - expected).cwiseAbs().maxCoeff() == 0.0);
  // Spin ω̄ = (0, 0, 1): ω̄̃ω̄̃ū = (−1, 0, 0) (centripetal acceleration, inward), so
  // Qv_R = −A ω̄̃ω̄̃ s_t = (2, 0, 0) (the centrifugal force points outward, +x);
  // Qv_f = −m Φᵀ ω̄̃ω̄̃ū = 0 (Φ ⟂ x); Qv_θ = −ω̄̃ Ī_θθ ω̄ = −ω̄ × (0, 0, 2) = 0.
  Eigen::VectorXd Qv(7);
  flexible_quadratic_velocity(inv, Eigen::Matrix3d::Identity(), Eigen::VectorXd::Zero(1),
                              Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::VectorXd::Zero(1), Qv);
  Eigen::VectorXd Qv_expected = Eigen::VectorXd::Zero(7);
  Qv_expected(0) = 2.0;
  CHECK((Qv - Qv_expected).cwiseAbs().maxCoeff() <= 10.0 * kEps);
}

TEST_CASE("flexible M and Qv: wrong sizes throw, T allocates nothing", "[core][flexible]") {
  const flexible::ModalData data = random_dense_modal_data(5, 3, 21);
  const flexible::ModalInvariants inv = make_modal_invariants(data);
  std::mt19937 rng(22);
  const State s = random_state(3, rng, 0.5);
  Eigen::MatrixXd M(9, 9), M_bad(9, 8);
  Eigen::VectorXd Qv(9), Qv_bad(8);
  CHECK_THROWS_AS(flexible_mass_matrix(inv, s.A, s.q, M_bad), std::invalid_argument);
  CHECK_THROWS_AS(flexible_mass_matrix(inv, s.A, Eigen::VectorXd::Zero(2), M),
                  std::invalid_argument);
  CHECK_THROWS_AS(flexible_quadratic_velocity(inv, s.A, s.q, s.w, s.qd, Qv_bad),
                  std::invalid_argument);
  CHECK_THROWS_AS(flexible_quadratic_velocity(inv, s.A, s.q, s.w, Eigen::VectorXd::Zero(4), Qv),
                  std::invalid_argument);
  // The whole-matrix views allocate their scratch; the evaluation the Model uses
  // (flexible/inertia_terms.hpp) does not (tests/flexible/inertia_terms_test.cpp), nor does T.
  double T = 0.0;
  CHECK(testing::count_allocations(
            [&] { T = flexible_kinetic_energy(inv, s.A, s.q, s.Rd, s.w, s.qd); }) == 0);
  CHECK(T > 0.0);
}

// (e) A smooth motion with closed-form derivatives:
//   R(t) = c0 + c1 sin t + c2 cos 2t,  q(t) = q0 + q1 sin 1.3t + q2 t²/2,
//   θ(t) = θ0 ⊗ exp(t ω1) ⊗ exp(t²/2 ω2)  (quaternion exponentials),
// so A(t) = A0 E1(t) E2(t) with E1 = exp(t ω̃1), E2 = exp(t²/2 ω̃2), Ȧ = A (E2ᵀ ω1 + t ω2)~:
//   ω̄(t) = E2ᵀ ω1 + t ω2,   α̅(t) = ω2 − (t ω2) × (E2ᵀ ω1)   (Ė2ᵀ = −(t ω̃2) E2ᵀ).
struct Motion {
  Eigen::Vector3d c0, c1, c2, w1, w2;
  rotation::EulerParameters theta0;
  Eigen::VectorXd q0, q1, q2;

  rotation::EulerParameters theta(double t) const {
    return rotation::quaternion_multiply(
        rotation::quaternion_multiply(theta0, rotation::exp_quaternion(t * w1)),
        rotation::exp_quaternion(0.5 * t * t * w2));
  }
  Eigen::Matrix3d A(double t) const { return rotation::rotation_matrix(theta(t)); }
  Eigen::Vector3d R(double t) const { return c0 + c1 * std::sin(t) + c2 * std::cos(2.0 * t); }
  Eigen::Vector3d Rd(double t) const { return c1 * std::cos(t) - 2.0 * c2 * std::sin(2.0 * t); }
  Eigen::Vector3d Rdd(double t) const { return -c1 * std::sin(t) - 4.0 * c2 * std::cos(2.0 * t); }
  Eigen::VectorXd q(double t) const { return q0 + q1 * std::sin(1.3 * t) + 0.5 * t * t * q2; }
  Eigen::VectorXd qd(double t) const { return 1.3 * q1 * std::cos(1.3 * t) + t * q2; }
  Eigen::VectorXd qdd(double t) const { return -1.69 * q1 * std::sin(1.3 * t) + q2; }
  Eigen::Vector3d w(double t) const {
    return rotation::exp_so3(0.5 * t * t * w2).transpose() * w1 + t * w2;
  }
  Eigen::Vector3d alpha(double t) const {
    return w2 - (t * w2).cross(rotation::exp_so3(0.5 * t * t * w2).transpose() * w1);
  }
};

TEST_CASE("eq. 14 and eq. 17 against central differences of r_k(t)", "[core][flexible]") {
  const flexible::ModalData data = random_dense_modal_data(5, 3, 31);
  std::mt19937 rng(32);
  Motion m;
  m.c0 = random_vector3(rng, 1.0);
  m.c1 = random_vector3(rng, 1.0);
  m.c2 = random_vector3(rng, 1.0);
  m.w1 = random_vector3(rng, 1.0);
  m.w2 = random_vector3(rng, 1.0);
  m.theta0 = rotation::exp_quaternion(random_vector3(rng, 2.0));
  m.q0 = random_vector(3, rng, 0.5);
  m.q1 = random_vector(3, rng, 0.5);
  m.q2 = random_vector(3, rng, 0.5);
  const double t = 0.7;
  const auto r = [&](int k, double time) -> Eigen::Vector3d {
    return m.R(time) + m.A(time) * (data.p_BoNode_B.col(k) + data.mode_rows(k) * m.q(time));
  };
  State s;
  s.A = m.A(t);
  s.q = m.q(t);
  s.qd = m.qd(t);
  s.Rd = m.Rd(t);
  s.w = m.w(t);

  // The rotation conventions the closed form relies on (so a failure below is diagnosable).
  CHECK((m.A(t) - rotation::rotation_matrix(m.theta0) * rotation::exp_so3(t * m.w1) *
                      rotation::exp_so3(0.5 * t * t * m.w2))
            .cwiseAbs()
            .maxCoeff() <= 1e-14);  // a few ε per product of 3 rotations

  // Central differences: first derivative with h1 = 1e-5 errs by h1²/6 |r'''| + ε|r|/h1 ≤
  // 1.7e-11·|r'''| + 2.2e-10 (|r| ≤ 10); second with h2 = 2e-4 by h2²/12 |r''''| + 4ε|r|/h2² ≤
  // 3.3e-9·|r''''| + 2.2e-7. With |r'''|, |r''''| ≤ 10³ (|ω̄| ≲ 3 rad/s, lever arms ≲ 5 m, unit
  // rates) the bounds are 2e-8 and 3.6e-6: tolerances 1e-7 and 1e-5.
  const double h1 = 1e-5, h2 = 2e-4;
  // ω̄ = 2 Ḡ θ̇ (design's definition) agrees with the closed form.
  const rotation::EulerParameters theta_dot = (m.theta(t + h1) - m.theta(t - h1)) / (2.0 * h1);
  CHECK((2.0 * rotation::g_bar_matrix(m.theta(t)) * theta_dot - s.w).cwiseAbs().maxCoeff() <= 1e-7);
  // α̅ = ω̄̇ agrees with the closed form.
  CHECK(((m.w(t + h1) - m.w(t - h1)) / (2.0 * h1) - m.alpha(t)).cwiseAbs().maxCoeff() <= 1e-7);

  for (int k = 0; k < data.node_count(); ++k) {
    INFO("node " << k);
    const Eigen::Vector3d u = data.p_BoNode_B.col(k) + data.mode_rows(k) * s.q;
    const Eigen::Vector3d rd_eq14 = s.Rd + s.A * (s.w.cross(u) + data.mode_rows(k) * s.qd);
    const Eigen::Vector3d rd_fd = (r(k, t + h1) - r(k, t - h1)) / (2.0 * h1);
    CHECK((rd_eq14 - rd_fd).cwiseAbs().maxCoeff() <= 1e-7);
    const Eigen::Vector3d rdd_eq17 = node_acceleration(data, k, s, m.Rdd(t), m.alpha(t), m.qdd(t));
    const Eigen::Vector3d rdd_fd = (r(k, t + h2) - 2.0 * r(k, t) + r(k, t - h2)) / (h2 * h2);
    CHECK((rdd_eq17 - rdd_fd).cwiseAbs().maxCoeff() <= 1e-5);
  }
}

}  // namespace
}  // namespace flexref::core
