/// Tests of flexible/inertia_terms: the two-stage evaluation (modal products, then assembly).
/// Its values against the nodal sums are checked through the whole-matrix views in
/// flexible_dynamics_test.cpp; here: the products do not depend on the rigid state (one set
/// serves any attitude and angular velocity), the LTE shortcut equals the evaluation at
/// q_f = q̇_f = 0 exactly, the blocks are exactly symmetric, nothing allocates, sizes are
/// checked.
#include "flexible/inertia_terms.hpp"

#include <catch2/catch.hpp>
#include <random>
#include <stdexcept>

#include "flexible/beam_model.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/random_samples.hpp"

namespace flexref::flexible {
namespace {

using testing::random_vector;

ModalInvariants bending_beam_invariants(int modes) {
  BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.05, -0.02);
  p.elements = 12;
  p.EA = 1e5;
  p.EI_y = 4.0;
  p.EI_z = 3.2;
  p.boundary = BeamBoundary::kClampedFree;
  return make_modal_invariants(make_beam_modal_data(p, modes));
}

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  return rotation::rotation_matrix(Eigen::Vector4d(random_vector(4, rng, 1.0)).normalized());
}

TEST_CASE("modal products serve every attitude and angular velocity", "[flexible][terms]") {
  const ModalInvariants inv = bending_beam_invariants(10);
  std::mt19937 rng(3);
  const Eigen::VectorXd q = random_vector(10, rng, 0.1);
  const Eigen::VectorXd qd = random_vector(10, rng, 1.0);
  InertiaTerms reused = make_inertia_terms(10);
  InertiaTerms fresh = make_inertia_terms(10);
  compute_modal_products(inv, q, qd, reused);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::Matrix3d A = random_rotation(rng);
    const Eigen::Vector3d w = random_vector(3, rng, 2.0);
    assemble_inertia_terms(inv, A, q, w, qd, reused);
    evaluate_inertia_terms(inv, A, q, w, qd, fresh);
    // The same operations on the same products: bitwise equal.
    CHECK(reused.M_rr == fresh.M_rr);
    CHECK(reused.M_rf == fresh.M_rf);
    CHECK(reused.Qv == fresh.Qv);
    CHECK(fresh.M_rr == fresh.M_rr.transpose());
    CHECK(fresh.I_tt == fresh.I_tt.transpose());
    // Not vacuous: the deformation and the spin enter the modal rows of Qv.
    CHECK(fresh.Qv.tail(10).norm() > 1e-3);
  }
}

TEST_CASE("the undeformed products equal the evaluation at zero modal state", "[flexible][terms]") {
  const ModalInvariants inv = bending_beam_invariants(6);
  std::mt19937 rng(5);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(6);
  const Eigen::Matrix3d A = random_rotation(rng);
  const Eigen::Vector3d w = random_vector(3, rng, 2.0);
  InertiaTerms lte = make_inertia_terms(6);
  InertiaTerms at_zero = make_inertia_terms(6);
  // Dirty products first: set_undeformed_products must clear all of them.
  compute_modal_products(inv, random_vector(6, rng, 0.1), random_vector(6, rng, 1.0), lte);
  set_undeformed_products(lte);
  assemble_inertia_terms(inv, A, zero, w, zero, lte);
  evaluate_inertia_terms(inv, A, zero, w, zero, at_zero);
  CHECK(lte.M_rr == at_zero.M_rr);
  CHECK(lte.M_rf == at_zero.M_rf);
  CHECK(lte.Qv == at_zero.Qv);
  CHECK(lte.I_tt == inv.I0);
}

TEST_CASE("inertia terms allocate nothing and check sizes", "[flexible][terms]") {
  const ModalInvariants inv = bending_beam_invariants(8);
  std::mt19937 rng(7);
  const Eigen::VectorXd q = random_vector(8, rng, 0.1);
  const Eigen::VectorXd qd = random_vector(8, rng, 1.0);
  const Eigen::Matrix3d A = random_rotation(rng);
  const Eigen::Vector3d w = random_vector(3, rng, 2.0);
  InertiaTerms terms = make_inertia_terms(8);
  CHECK(testing::count_allocations([&] { evaluate_inertia_terms(inv, A, q, w, qd, terms); }) == 0);
  CHECK(terms.Qv.allFinite());
  const Eigen::VectorXd short_q = Eigen::VectorXd::Zero(7);
  CHECK_THROWS_AS(evaluate_inertia_terms(inv, A, short_q, w, qd, terms), std::invalid_argument);
  CHECK_THROWS_AS(evaluate_inertia_terms(inv, A, q, w, short_q, terms), std::invalid_argument);
  InertiaTerms wrong = make_inertia_terms(7);
  CHECK_THROWS_AS(evaluate_inertia_terms(inv, A, q, w, qd, wrong), std::invalid_argument);
}

}  // namespace
}  // namespace flexref::flexible
