#pragma once
/// \file compressed_block_tpl.hpp
/// A modal invariant matrix stored as the dense block its nonzero rows and columns span, for
/// any scalar type S. Mode families that do not share a displacement direction make most of
/// the pair matrices P_ab = Σ m_k Φ_k,aᵀ Φ_k,b exactly zero or zero outside one family's rows
/// and columns: a beam's bending-xy modes have no x or z component, so P_xx = P_xy = 0 and P_yy
/// lives on the xy family alone (docs/precision.md, "Many modes"). The products u = P x and
/// u = Pᵀ x then cost |rows|·|cols| instead of n² — the difference between hours and minutes
/// for a 64-mode body in software binary128, where every multiply-add is a library call.
/// A block that spans every row and column is the matrix itself (no gather, no scatter).
#include <Eigen/Core>
#include <vector>

namespace flexref::flexible {

template <typename S>
struct CompressedBlockTpl {
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;

  std::vector<Eigen::Index> rows;  ///< the rows with a nonzero entry, ascending
  std::vector<Eigen::Index> cols;  ///< the columns with a nonzero entry, ascending
  Matrix block;                    ///< P(rows, cols)
  bool full = false;               ///< rows and cols are all of 0..n−1: block = P
  Eigen::Index dimension = -1;     ///< n, the compressed matrix's order (−1: never built)

  Eigen::Index size() const { return block.size(); }
};

/// The block of P's nonzero rows and columns (an entry is zero when it compares equal to 0).
template <typename S>
CompressedBlockTpl<S> compress_block_tpl(
    const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>& P) {
  CompressedBlockTpl<S> c;
  c.dimension = P.rows();
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    if ((P.row(i).array() != S(0)).any()) c.rows.push_back(i);
  }
  for (Eigen::Index j = 0; j < P.cols(); ++j) {
    if ((P.col(j).array() != S(0)).any()) c.cols.push_back(j);
  }
  c.full = static_cast<Eigen::Index>(c.rows.size()) == P.rows() &&
           static_cast<Eigen::Index>(c.cols.size()) == P.cols();
  c.block.resize(static_cast<Eigen::Index>(c.rows.size()),
                 static_cast<Eigen::Index>(c.cols.size()));
  for (std::size_t i = 0; i < c.rows.size(); ++i) {
    for (std::size_t j = 0; j < c.cols.size(); ++j) {
      c.block(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = P(c.rows[i], c.cols[j]);
    }
  }
  return c;
}

/// Scratch of the gathered products, sized n once (no allocation in a product).
template <typename S>
struct BlockProductScratchTpl {
  Eigen::Matrix<S, Eigen::Dynamic, 1> gathered;
  Eigen::Matrix<S, Eigen::Dynamic, 1> product;
};

/// u = P x (transpose: u = Pᵀ x; symmetric: the block is exactly symmetric and only its lower
/// triangle is read). u and x have n entries; u is overwritten, its entries outside the block's
/// rows (columns) set to zero.
template <typename S, typename In, typename Out>
void multiply_block_tpl(const CompressedBlockTpl<S>& P, const In& x, Out&& u,
                        BlockProductScratchTpl<S>& scratch, bool transpose = false,
                        bool symmetric = false) {
  // Symmetric: P is, so its pattern is too (rows = cols) and the block is square and symmetric.
  eigen_assert(!symmetric || P.rows == P.cols);
  // The one product of the block (plain, transposed or symmetric) on gathered or whole vectors.
  const auto product = [&](const auto& from, auto&& to) {
    if (symmetric) {
      to.noalias() = P.block.template selfadjointView<Eigen::Lower>() * from;
    } else if (transpose) {
      to.noalias() = P.block.transpose() * from;
    } else {
      to.noalias() = P.block * from;
    }
  };
  if (P.full) {
    product(x, u);
    return;
  }
  const std::vector<Eigen::Index>& in = transpose ? P.rows : P.cols;
  const std::vector<Eigen::Index>& out = transpose ? P.cols : P.rows;
  const auto n_in = static_cast<Eigen::Index>(in.size());
  const auto n_out = static_cast<Eigen::Index>(out.size());
  u.setZero();
  if (n_in == 0 || n_out == 0) return;
  for (Eigen::Index j = 0; j < n_in; ++j) scratch.gathered(j) = x(in[static_cast<std::size_t>(j)]);
  auto xg = scratch.gathered.head(n_in);
  auto ug = scratch.product.head(n_out);
  product(xg, ug);
  for (Eigen::Index i = 0; i < n_out; ++i) u(out[static_cast<std::size_t>(i)]) = ug(i);
}

}  // namespace flexref::flexible
