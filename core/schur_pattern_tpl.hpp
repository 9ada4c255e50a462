#pragma once
/// \file schur_pattern_tpl.hpp
/// The sparsity of the Schur complement A = J_a M⁻¹ J_aᵀ for one set of active rows, and of the
/// orientation test's crossing product J_a,accepted M⁻¹ J_aᵀ, which has the same pattern
/// (docs/decisions.md, "Constrained systems at scale"): M is block-diagonal by body, so entry
/// (i, j) is non-zero only where rows i and j act on a common body, and it is the sum over those
/// bodies of J_i,b · (M_b⁻¹ J_j,bᵀ). Built once per row set (allocating: setup and the rare
/// evaluations that choose rows again): a fill-reducing order of the rows (approximate minimum
/// degree, Amestoy, Davis & Duff 1996, Eigen's AMDOrdering), A's upper triangle in that order as
/// a compressed-column pattern for core/sparse_ldl_tpl.hpp, and per entry the block products
/// that make it.
#include <Eigen/Core>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>
#include <vector>

#include "core/block_dot_tpl.hpp"
#include "core/constraint_jacobian_tpl.hpp"

namespace flexref::core {

struct SchurPattern {
  /// One product of a row block by another's: values at [a, a + width) of one row times
  /// [b, b + width) of the other (the same body's columns).
  struct Product {
    int a = 0;
    int b = 0;
    int width = 0;
  };
  std::vector<int> rows;          ///< the active rows the pattern is for (indices into J)
  std::vector<int> order;         ///< pivot k → active index
  std::vector<int> position;      ///< active index → pivot
  std::vector<int> column_start;  ///< upper triangle in pivot order: column k's entries
  std::vector<int> row_index;     ///< each entry's pivot row (≤ its column)
  /// Entry p's products: those at product_start[p] .. product_start[p + 1], each J_row(i) block
  /// at a times Y_row(k) block at b for entry (i, k) (i its row, k its column, pivots).
  std::vector<int> product_start;
  std::vector<Product> products;

  bool valid = false;  ///< built (for `rows`)

  /// Whether the pattern is for `active`.
  bool is_for(const std::vector<int>& active) const { return valid && rows == active; }

  /// The pattern for `active` rows of J's pattern. Allocates.
  template <typename S>
  void build(const std::vector<int>& active, const ConstraintJacobianTpl<S>& J) {
    rows = active;
    valid = true;
    const int m = static_cast<int>(active.size());
    int bodies = 0;
    for (int r : active) {
      for (int k = 0; k < 2; ++k) bodies = std::max(bodies, J.slot(r, k).body + 1);
    }
    // The active rows on each body, then each row's neighbours (rows sharing a body).
    std::vector<std::vector<int>> on_body(static_cast<std::size_t>(bodies));
    for (int i = 0; i < m; ++i) {
      for (int k = 0; k < 2; ++k) {
        const int b = J.slot(active[static_cast<std::size_t>(i)], k).body;
        if (b >= 0) on_body[static_cast<std::size_t>(b)].push_back(i);
      }
    }
    std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(m));
    std::vector<int> mark(static_cast<std::size_t>(m), -1);
    std::vector<Eigen::Triplet<double, int>> entries;
    for (int i = 0; i < m; ++i) {
      auto& list = neighbours[static_cast<std::size_t>(i)];
      mark[static_cast<std::size_t>(i)] = i;
      list.push_back(i);
      for (int k = 0; k < 2; ++k) {
        const int b = J.slot(active[static_cast<std::size_t>(i)], k).body;
        if (b < 0) continue;
        for (int j : on_body[static_cast<std::size_t>(b)]) {
          if (mark[static_cast<std::size_t>(j)] == i) continue;
          mark[static_cast<std::size_t>(j)] = i;
          list.push_back(j);
        }
      }
      for (int j : list) entries.emplace_back(j, i, 1.0);
    }
    order.assign(static_cast<std::size_t>(m), 0);
    position.assign(static_cast<std::size_t>(m), 0);
    if (m > 0) {
      Eigen::SparseMatrix<double, Eigen::ColMajor, int> graph(m, m);
      graph.setFromTriplets(entries.begin(), entries.end());
      Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> permutation;
      Eigen::AMDOrdering<int>()(graph, permutation);
      for (int k = 0; k < m; ++k) {
        order[static_cast<std::size_t>(k)] = permutation.indices()(k);
        position[static_cast<std::size_t>(permutation.indices()(k))] = k;
      }
    }
    column_start.assign(1, 0);
    row_index.clear();
    product_start.assign(1, 0);
    products.clear();
    std::vector<int> column;
    for (int k = 0; k < m; ++k) {
      const int i = order[static_cast<std::size_t>(k)];
      column.clear();
      for (int j : neighbours[static_cast<std::size_t>(i)]) {
        if (position[static_cast<std::size_t>(j)] <= k)
          column.push_back(position[static_cast<std::size_t>(j)]);
      }
      std::sort(column.begin(), column.end());
      for (int pivot_row : column) {
        row_index.push_back(pivot_row);
        const int row_i =
            active[static_cast<std::size_t>(order[static_cast<std::size_t>(pivot_row)])];
        const int row_k = active[static_cast<std::size_t>(i)];
        for (int ka = 0; ka < 2; ++ka) {
          const auto& sa = J.slot(row_i, ka);
          if (sa.body < 0) continue;
          for (int kb = 0; kb < 2; ++kb) {
            const auto& sb = J.slot(row_k, kb);
            if (sb.body == sa.body) products.push_back({sa.start, sb.start, sa.width});
          }
        }
        product_start.push_back(static_cast<int>(products.size()));
      }
      column_start.push_back(static_cast<int>(row_index.size()));
    }
  }

  int nonzeros() const { return static_cast<int>(row_index.size()); }

  /// Entry p of X_a M⁻¹ J_aᵀ for rows X with J's pattern (values x), y the values of
  /// Y = M⁻¹ J_aᵀ by the same pattern: upper (x_i · y_k) or, with `transposed`, lower (x_k ·
  /// y_i) for entry (i, k).
  template <typename Vector>
  auto entry(int p, const Vector& x, const Vector& y, bool transposed) const {
    using S = typename Vector::Scalar;
    S sum(0);
    for (int q = product_start[static_cast<std::size_t>(p)];
         q < product_start[static_cast<std::size_t>(p) + 1]; ++q) {
      const Product& product = products[static_cast<std::size_t>(q)];
      const int first = transposed ? product.b : product.a;
      const int second = transposed ? product.a : product.b;
      sum += block_dot<S>(x.data() + first, y.data() + second, product.width);
    }
    return sum;
  }

  /// Both entries p of X_a M⁻¹ J_aᵀ (entry's upper and lower) in one pass over its products.
  template <typename Vector>
  void entries(int p, const Vector& x, const Vector& y, typename Vector::Scalar& upper,
               typename Vector::Scalar& lower) const {
    using S = typename Vector::Scalar;
    upper = S(0);
    lower = S(0);
    for (int q = product_start[static_cast<std::size_t>(p)];
         q < product_start[static_cast<std::size_t>(p) + 1]; ++q) {
      const Product& product = products[static_cast<std::size_t>(q)];
      upper += block_dot<S>(x.data() + product.a, y.data() + product.b, product.width);
      lower += block_dot<S>(x.data() + product.b, y.data() + product.a, product.width);
    }
  }
};

}  // namespace flexref::core
