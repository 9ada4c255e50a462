#pragma once
/// \file dae_coloured_jacobian.hpp
/// IDA's iteration matrix G = ∂F/∂y + c_j ∂F/∂y' on the DAE form (reference/dae_form.hpp) in
/// compressed sparse columns, by column-grouped difference quotients (Curtis, Powell & Reid
/// 1974): columns that share no row of the pattern are perturbed together, one residual per
/// group instead of one per column.
///
/// The pattern is what the GGL residual reads, in the order of the form's y
/// (reference/form_layout.hpp): body i's block (p, θ, v, ω̄, q, v_q: dense within the body)
/// reads the blocks of the bodies a force element couples with it (core::element_coupling);
/// for each row in force acting on it, the other end's pose (p, θ, q: J_i reads poses, no
/// velocity; not for a point row, whose J_i reads i's pose alone), the row's λ in its
/// velocity-level rows (+ J_iᵀλ) and μ in its position-level rows
/// (+ J_iᵀμ); λ's row J v + Φ_t reads both ends' blocks, μ's row Φ both ends' poses
/// (docs/decisions.md, "IDA's joint terms by what the residual reads"); an element's worn depths
/// are read by the element's bodies and their rates read those bodies and the element's depths. The
/// works W (W_d and the extra integrals) are read by nothing; their rows Ẇ − P read every state but
/// are kept to their diagonal, ∂F_W/∂W + c_j ∂F_W/∂W' = c_j, set exactly and not differenced: G is
/// block lower triangular in (state, W), so the state's Newton corrections are those of the full G,
/// and a work's correction lags the state's by one iteration (a dense row would put every column in
/// a group of its own). A chain of N bodies needs a number of groups independent of N (32 on a
/// chain of rods).
///
/// Each column's increment is IDA's own (idaLsDenseDQJac, SUNDIALS 6.4):
///   inc_j = max(√u · max(|y_j|, |h y'_j|), 1/ewt_j), with the sign of h y'_j, rounded to
///   (y_j + inc_j) − y_j,
/// so each entry is the quotient IDA's dense difference quotient forms, from a residual where
/// the other columns of the group are perturbed too, which the entry's row does not read.
#include <sundials/sundials_types.h>

#include <span>
#include <vector>

#include "reference/dae_form.hpp"

namespace flexref::reference {

class DaeColouredJacobian {
 public:
  /// The pattern and its column groups at the form's rows in force (active_rows()). The form
  /// must outlive this.
  explicit DaeColouredJacobian(const DaeForm& form);

  /// Builds the pattern and groups again when the form's rows in force changed since (a row
  /// switch); returns true when it did (allocates then only).
  bool update_pattern();

  int size() const { return size_; }
  long nonzeros() const { return static_cast<long>(row_index_.size()); }
  int group_count() const { return static_cast<int>(group_start_.size()) - 1; }
  std::span<const int> group(int g) const;
  const std::vector<int>& column_start() const { return column_start_; }
  const std::vector<int>& row_index() const { return row_index_; }

  /// G at (t, y, y') with the residual `r` there, IDA's current step h and error weights ewt,
  /// into the CSC arrays (size()+1 column starts, nonzeros() row indices and values). y and yp
  /// are perturbed and restored bit for bit; `work` holds size() entries. Returns false when a
  /// residual was not finite (IDA then retries with a smaller step). Allocates nothing.
  bool evaluate(const core::LoadContext& context, double c_j, double h, double* y, double* yp,
                const double* r, const double* ewt, double* work, DaeForm::Scratch& scratch,
                sunindextype* column_start, sunindextype* row_index, double* values) const;

 private:
  void build();

  const DaeForm* form_;
  int size_ = 0;
  std::vector<int> rows_built_for_;  ///< the form's active rows the pattern is for
  std::vector<int> column_start_;    ///< CSC, size_ + 1
  std::vector<int> row_index_;       ///< CSC, sorted within each column
  std::vector<int> group_start_;     ///< groups of columns, into group_columns_
  std::vector<int> group_columns_;
  std::vector<int> works_;  ///< the works' columns: G = c_j on the diagonal, not differenced
  mutable std::vector<double> increment_;  ///< per column of the group being differenced
};

}  // namespace flexref::reference
