/// \file small_cholesky_test.cpp
/// The small dense Cholesky kernels (constraint/small_cholesky.hpp) against their definitions:
/// L Lᵀ reproduces A, the substitutions invert L and Lᵀ, the row form equals the column form on
/// each row; the tree-like zero pattern the factorization skips; and the index of the first
/// pivot that is not positive.
#include "constraint/small_cholesky.hpp"

#include <catch2/catch.hpp>
#include <limits>
#include <random>

namespace flexref::constraint {
namespace {

/// A random symmetric positive definite n × n matrix B Bᵀ + n I; with `blocks`, entries between
/// indices of different parity zeroed first (two uncoupled branches, as a tree's M_r has).
Eigen::MatrixXd spd_matrix(Eigen::Index n, bool blocks, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::MatrixXd B(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) {
      B(i, j) = blocks && (i + j) % 2 != 0 ? 0.0 : unit(rng);
    }
  }
  return B * B.transpose() + static_cast<double>(n) * Eigen::MatrixXd::Identity(n, n);
}

}  // namespace

TEST_CASE("small_cholesky: L Lᵀ = A, the substitutions solve A x = b", "[reduced]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (const bool blocks : {false, true}) {
    for (Eigen::Index n = 1; n <= 9; ++n) {
      INFO("n = " << n << (blocks ? ", two uncoupled branches" : ""));
      const Eigen::MatrixXd A = spd_matrix(n, blocks, rng);
      Eigen::MatrixXd N = A;
      N.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);  // never read
      Eigen::VectorXd inverse(n), diagonal(n);
      REQUIRE(cholesky_in_place(N, inverse.data(), diagonal.data()) == -1);
      CHECK(N.triangularView<Eigen::Upper>().toDenseMatrix().isZero(0.0));
      const Eigen::MatrixXd L = N + Eigen::MatrixXd(diagonal.asDiagonal());
      CHECK((inverse.cwiseProduct(diagonal).array() - 1.0).abs().maxCoeff() <= 1e-15);
      // Backward stable: |L Lᵀ − A| ≲ n ε |A|; 1e-14 |A| leaves a margin over n ε = 2e-15.
      CHECK((L * L.transpose() - A).cwiseAbs().maxCoeff() <= 1e-14 * A.cwiseAbs().maxCoeff());
      Eigen::VectorXd b(n);
      for (Eigen::Index i = 0; i < n; ++i) b(i) = unit(rng);
      Eigen::VectorXd y = b, x = b;
      forward_substitute(N, inverse.data(), y.data());
      // Forward substitution is backward stable as well: 1e-14 |b| over n ε |L| |y| ≲ 2e-15 |b|.
      CHECK((L * y - b).cwiseAbs().maxCoeff() <= 1e-14 * b.cwiseAbs().maxCoeff());
      forward_substitute(N, inverse.data(), x.data());
      back_substitute(N, inverse.data(), x.data());
      // cond(A) ≤ (max eig)/(n) with eig ≥ n: a few units; residual within 1e-13 |b|.
      CHECK((A * x - b).cwiseAbs().maxCoeff() <= 1e-13 * b.cwiseAbs().maxCoeff());
      Eigen::MatrixXd X(3, n);
      for (Eigen::Index r = 0; r < 3; ++r) {
        for (Eigen::Index i = 0; i < n; ++i) X(r, i) = unit(rng);
      }
      Eigen::MatrixXd Y = X;
      forward_substitute_rows(N, inverse.data(), Y);
      for (Eigen::Index r = 0; r < 3; ++r) {
        Eigen::VectorXd row = X.row(r).transpose();
        forward_substitute(N, inverse.data(), row.data());
        CHECK((Y.row(r).transpose() - row).cwiseAbs().maxCoeff() <=
              1e-14 * row.cwiseAbs().maxCoeff());
      }
    }
  }
}

TEST_CASE("small_cholesky: the first pivot that is not positive is named", "[reduced]") {
  // diag(4, 1, 1) with A(2,1) = A(1,2) = 2: the third pivot is 1 − 2² = −3; a NaN in the
  // second column stops at the second.
  Eigen::MatrixXd A{{4.0, 0.0, 0.0}, {0.0, 1.0, 2.0}, {0.0, 2.0, 1.0}};
  Eigen::VectorXd inverse(3);
  Eigen::MatrixXd N = A;
  CHECK(cholesky_in_place(N, inverse.data()) == 2);
  N = A;
  N(1, 1) = std::numeric_limits<double>::quiet_NaN();
  CHECK(cholesky_in_place(N, inverse.data()) == 1);
}

}  // namespace flexref::constraint
