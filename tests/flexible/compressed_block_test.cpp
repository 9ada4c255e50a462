/// Tests of flexible/compressed_block_tpl.hpp: the block of a matrix's nonzero rows and columns
/// multiplies as the matrix does (plain, transposed, symmetric), for a full, a sparse and an
/// all-zero pattern, in double and long double; a beam's pair matrices compress (the bending
/// families share no direction); the modal products through the blocks equal the dense ones;
/// nothing allocates.
#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <random>
#include <stdexcept>

#include "flexible/beam_model.hpp"
#include "flexible/compressed_block_tpl.hpp"
#include "flexible/inertia_terms.hpp"
#include "flexible/modal_data.hpp"
#include "tests/support/allocation_counting.hpp"

namespace flexref::flexible {
namespace {

template <typename S>
using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <typename S>
using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;

/// An n×n matrix with normal entries on the rows and columns `keep` draws (each row and column
/// kept with probability p), zero elsewhere; symmetric on request (then rows = columns).
template <typename S>
Matrix<S> patterned(int n, double p, bool symmetric, std::mt19937& rng) {
  std::bernoulli_distribution keep(p);
  std::normal_distribution<double> normal;
  std::vector<bool> row(static_cast<std::size_t>(n)), col(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) row[static_cast<std::size_t>(i)] = keep(rng);
  for (int j = 0; j < n; ++j)
    col[static_cast<std::size_t>(j)] = symmetric ? row[static_cast<std::size_t>(j)] : keep(rng);
  Matrix<S> P = Matrix<S>::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (row[static_cast<std::size_t>(i)] && col[static_cast<std::size_t>(j)])
        P(i, j) = S(normal(rng));
    }
  }
  if (symmetric) P = (S(0.5) * (P + P.transpose())).eval();
  return P;
}

template <typename S>
void check_products(const Matrix<S>& P, bool symmetric, std::mt19937& rng) {
  const auto n = P.rows();
  const CompressedBlockTpl<S> c = compress_block_tpl<S>(P);
  // Every kept row and column has a nonzero entry; every dropped one is zero.
  for (Eigen::Index i = 0; i < n; ++i) {
    const bool row_kept = std::find(c.rows.begin(), c.rows.end(), i) != c.rows.end();
    const bool col_kept = std::find(c.cols.begin(), c.cols.end(), i) != c.cols.end();
    CHECK(row_kept == (P.row(i).array() != S(0)).any());
    CHECK(col_kept == (P.col(i).array() != S(0)).any());
  }
  CHECK(c.dimension == n);
  std::normal_distribution<double> normal;
  Vector<S> x(n);
  for (Eigen::Index i = 0; i < n; ++i) x(i) = S(normal(rng));
  BlockProductScratchTpl<S> scratch{Vector<S>::Zero(n), Vector<S>::Zero(n)};
  Vector<S> u = Vector<S>::Constant(n, S(7));  // stale values must be overwritten
  // The block sums the dense product's nonzero terms (Eigen may group the partial sums
  // differently): agreement to the round-off of n terms of size |x|·|P| ≤ ~10 each.
  const S tol = S(64) * std::numeric_limits<S>::epsilon() * S(n) * S(10);
  multiply_block_tpl<S>(c, x, u, scratch);
  CHECK((u - P * x).template lpNorm<Eigen::Infinity>() <= tol);
  multiply_block_tpl<S>(c, x, u, scratch, true);
  CHECK((u - P.transpose() * x).template lpNorm<Eigen::Infinity>() <= tol);
  if (symmetric) {
    u.setConstant(S(7));
    multiply_block_tpl<S>(c, x, u, scratch, false, true);
    CHECK((u - P * x).template lpNorm<Eigen::Infinity>() <= tol);
  }
  // The check can fail: a non-symmetric pattern's transposed product is another vector.
  if (!symmetric && c.size() > 0) {
    multiply_block_tpl<S>(c, x, u, scratch);
    CHECK((u - P.transpose() * x).template lpNorm<Eigen::Infinity>() > tol);
  }
  CHECK(testing::count_allocations([&] {
          multiply_block_tpl<S>(c, x, u, scratch);
          multiply_block_tpl<S>(c, x, u, scratch, true);
          if (symmetric) multiply_block_tpl<S>(c, x, u, scratch, false, true);
        }) == 0);
}

TEMPLATE_TEST_CASE("a compressed block multiplies as its matrix", "[compressed_block]", double,
                   long double) {
  std::mt19937 rng(20261126);
  for (int trial = 0; trial < 20; ++trial) {
    for (const double p : {1.0, 0.5, 0.2}) {
      for (const bool symmetric : {false, true}) {
        check_products<TestType>(patterned<TestType>(23, p, symmetric, rng), symmetric, rng);
      }
    }
  }
  const Matrix<TestType> zero = Matrix<TestType>::Zero(9, 9);
  const CompressedBlockTpl<TestType> c = compress_block_tpl<TestType>(zero);
  CHECK(c.size() == 0);
  CHECK_FALSE(c.full);
  check_products<TestType>(zero, true, rng);
}

ModalInvariants two_family_beam(int modes) {
  BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.0, 0.0);
  p.elements = 16;
  p.EA = 1e5;
  p.EI_y = 4.0;
  p.EI_z = 3.2;
  p.boundary = BeamBoundary::kClampedFree;
  BeamModeFilter bending;
  bending.axial = false;
  return make_modal_invariants(make_beam_modal_data(p, modes, bending));
}

/// The modal products through the blocks equal the dense ones (P_ab q for the nine pairs,
/// G_a q̇ = (P_bc − P_cb) q̇), every G_a that is not zero by the data checked nonzero.
void check_products_against_dense(const ModalInvariants& inv) {
  const int n = inv.mode_count;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  Eigen::VectorXd q(n), qd(n);
  for (int i = 0; i < n; ++i) {
    q(i) = 1e-2 * normal(rng);
    qd(i) = 1e-1 * normal(rng);
  }
  InertiaTerms t = make_inertia_terms(n);
  compute_modal_products(inv, q, qd, t);
  const double scale_q = q.lpNorm<Eigen::Infinity>(), scale_qd = qd.lpNorm<Eigen::Infinity>();
  // Sums of n products of entries ≤ 1 (mass-normalized modes): round-off ≤ n ε |q|; 100 n ε.
  const double tol = 100.0 * n * 2.2e-16;
  for (int k = 0; k < 9; ++k) {
    const Eigen::VectorXd dense = inv.phi_phi[static_cast<std::size_t>(k)] * q;
    CHECK((t.P_q.col(k) - dense).lpNorm<Eigen::Infinity>() <= tol * scale_q);
  }
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::MatrixXd& G = inv.phi_cross_phi[static_cast<std::size_t>(axis)];
    const Eigen::VectorXd dense = G * qd;
    CHECK((t.G_qd.col(axis) - dense).lpNorm<Eigen::Infinity>() <= tol * scale_qd);
    // A swapped transpose flips g_a's sign: it must not be zero for the check to see that.
    if (G.lpNorm<Eigen::Infinity>() > 0.0) {
      CHECK(t.G_qd.col(axis).lpNorm<Eigen::Infinity>() > 1e3 * tol * scale_qd);
    }
  }
}

TEST_CASE("a beam's bending families compress its pair matrices", "[compressed_block]") {
  const int n = 12;
  const ModalInvariants inv = two_family_beam(n);
  const auto blocks = [&](int a, int b) {
    return inv.phi_phi_blocks[static_cast<std::size_t>(detail::pair_index(a, b))];
  };
  // Along x, bending modes have no x component: P_xx, P_xy, P_xz are zero.
  CHECK(blocks(0, 0).size() == 0);
  CHECK(blocks(0, 1).size() == 0);
  CHECK(blocks(0, 2).size() == 0);
  // P_yy lives on the a bending-xy modes, P_zz on the b bending-xz ones, P_yz on their product:
  // a² + b² + ab entries, not 3n².
  const auto a = static_cast<Eigen::Index>(blocks(1, 1).rows.size());
  const auto b = static_cast<Eigen::Index>(blocks(2, 2).rows.size());
  CHECK(a > 0);
  CHECK(b > 0);
  CHECK(a + b == n);
  CHECK(blocks(1, 2).rows == blocks(1, 1).rows);
  CHECK(blocks(1, 2).cols == blocks(2, 2).cols);
  CHECK(blocks(1, 1).size() + blocks(2, 2).size() + blocks(1, 2).size() == a * a + b * b + a * b);

  check_products_against_dense(inv);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(n, 1e-3),
                        qd = Eigen::VectorXd::Constant(n, 1e-2);
  InertiaTerms t = make_inertia_terms(n);
  CHECK(testing::count_allocations([&] { compute_modal_products(inv, q, qd, t); }) == 0);
  // Invariants assembled without their blocks are refused, not multiplied as zero.
  ModalInvariants by_hand = inv;
  by_hand.phi_phi_blocks = {};
  CHECK_THROWS_AS(compute_modal_products(by_hand, q, qd, t), std::invalid_argument);
}

TEST_CASE("the compressed products equal the dense ones on a beam with axial modes",
          "[compressed_block]") {
  // Axial modes move along x: P_xy and P_xz couple them to a bending family (blocks that are
  // neither empty nor full), and all three G_a are nonzero — each branch of the cyclic triples
  // (stored pair (b, c) and (c, b)) is checked against the dense product.
  BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.0, 0.0);
  p.elements = 16;
  p.EA = 40.0;  // soft enough that axial modes are among the lowest 12
  p.EI_y = 4.0;
  p.EI_z = 3.2;
  p.boundary = BeamBoundary::kClampedFree;
  const ModalInvariants inv = make_modal_invariants(make_beam_modal_data(p, 12));
  const auto& P_xz = inv.phi_phi_blocks[static_cast<std::size_t>(detail::pair_index(0, 2))];
  CHECK(P_xz.size() > 0);
  CHECK_FALSE(P_xz.full);
  for (const auto& G : inv.phi_cross_phi) CHECK(G.lpNorm<Eigen::Infinity>() > 0.0);
  check_products_against_dense(inv);
}

}  // namespace
}  // namespace flexref::flexible
