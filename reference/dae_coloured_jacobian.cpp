/// \file dae_coloured_jacobian.cpp
/// See dae_coloured_jacobian.hpp.
#include "reference/dae_coloured_jacobian.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

#include "core/body_coupling.hpp"

namespace flexref::reference {

namespace {

/// A half-open range of indices of y.
struct IndexRange {
  int begin = 0;
  int end = 0;
};

/// Adds rows × columns to the per-column row lists.
void add_dae_block(IndexRange rows, IndexRange columns, std::vector<std::vector<int>>& pattern) {
  for (int c = columns.begin; c < columns.end; ++c) {
    for (int r = rows.begin; r < rows.end; ++r) pattern[static_cast<std::size_t>(c)].push_back(r);
  }
}

}  // namespace

DaeColouredJacobian::DaeColouredJacobian(const DaeForm& form) : form_(&form), size_(form.size()) {
  build();
}

bool DaeColouredJacobian::update_pattern() {
  if (form_->active_rows() == rows_built_for_) return false;
  build();
  return true;
}

std::span<const int> DaeColouredJacobian::group(int g) const {
  const auto begin = static_cast<std::size_t>(group_start_[static_cast<std::size_t>(g)]);
  const auto end = static_cast<std::size_t>(group_start_[static_cast<std::size_t>(g) + 1]);
  return std::span<const int>(group_columns_).subspan(begin, end - begin);
}

void DaeColouredJacobian::build() {
  const DaeForm& form = *form_;
  const core::Model& model = form.model();
  rows_built_for_ = form.active_rows();
  std::vector<std::vector<int>> pattern(static_cast<std::size_t>(size_));
  // The bodies' blocks in y.
  std::vector<IndexRange> body;
  int begin = 0;
  for (const DaeForm::Block& k : form.blocks()) {
    body.push_back({begin, k.end});
    begin = k.end;
  }
  // Loads: the bodies an element couples read each other's whole blocks (positions and
  // velocities: a damper's force).
  const std::vector<std::vector<int>> coupling = core::element_coupling(model);
  for (std::size_t i = 0; i < body.size(); ++i) {
    for (const int k : coupling[i])
      add_dae_block(body[i], body[static_cast<std::size_t>(k)], pattern);
  }
  // The worn depths, element by element (the model's order of Model::wear_depth_count()).
  int depth = form.depth_index();
  for (const auto& element : model.elements()) {
    const IndexRange depths{depth, depth + element->wear_depth_count()};
    depth = depths.end;
    if (depths.begin == depths.end) continue;
    add_dae_block(depths, depths, pattern);
    for (const int b : element->coupled_bodies()) {
      add_dae_block(body[static_cast<std::size_t>(b)], depths, pattern);
      add_dae_block(depths, body[static_cast<std::size_t>(b)], pattern);
    }
  }
  // The joints (dae_form.hpp's GGL residual), row active[j] on its bodies a, b: J_r,a (and Φ,
  // Φ_t) read the poses of both ends (a point row's J_r,a a's alone) and no velocity, so body a's
  // equations read λ_j in its velocity-level equations (+ J_aᵀ λ), μ_j in its position-level ones
  // (+ J_aᵀ μ) and both ends' poses (p, θ, q_f) through J_a; λ_j's equation J v + Φ_t = 0 reads
  // both ends' whole blocks, μ_j's Φ = 0 their poses.
  const int m = form.multiplier_count();
  const std::vector<DaeForm::Block>& blocks = form.blocks();
  const auto pose = [&](int b, auto&& add) {
    const DaeForm::Block& k = blocks[static_cast<std::size_t>(b)];
    if (k.p >= 0) add(IndexRange{k.p, k.p + 3});
    if (k.theta >= 0) add(IndexRange{k.theta, k.theta + 4});
    add(IndexRange{k.q, k.q + k.n});
  };
  const auto rates = [&](int b, auto&& add) {
    const DaeForm::Block& k = blocks[static_cast<std::size_t>(b)];
    if (k.v >= 0) add(IndexRange{k.v, k.v + 3});
    if (k.w >= 0) add(IndexRange{k.w, k.w + 3});
    add(IndexRange{k.qd, k.qd + k.n});
  };
  for (int j = 0; j < m; ++j) {
    const int row = rows_built_for_[static_cast<std::size_t>(j)];
    const IndexRange lambda{form.multiplier_index() + j, form.multiplier_index() + j + 1};
    const IndexRange mu{form.multiplier_index() + m + j, form.multiplier_index() + m + j + 1};
    const std::array<int, 2> ends = model.constraints()->row_bodies(row);
    for (const int a : ends) {
      if (a < 0) continue;
      const IndexRange rows_a = body[static_cast<std::size_t>(a)];
      rates(a, [&](IndexRange r) { add_dae_block(r, lambda, pattern); });
      pose(a, [&](IndexRange r) { add_dae_block(r, mu, pattern); });
      add_dae_block(lambda, rows_a, pattern);
      pose(a, [&](IndexRange c) { add_dae_block(mu, c, pattern); });
      for (const int b : ends) {
        // A point row's block on a reads a's pose alone (ConstraintEquations::blocks_read_own_end).
        if (b < 0 || (b != a && model.constraints()->blocks_read_own_end(row))) continue;
        pose(b, [&](IndexRange c) { add_dae_block(rows_a, c, pattern); });
      }
    }
  }
  // The diagonal (the works' alone: c_j).
  works_.clear();
  for (int c = 0; c < size_; ++c) {
    pattern[static_cast<std::size_t>(c)].push_back(c);
    const bool work = form.work_index() >= 0 && c >= form.work_index() &&
                      c < form.work_index() + form.integral_count();
    if (work) works_.push_back(c);
  }
  column_start_.assign(1, 0);
  row_index_.clear();
  for (std::vector<int>& rows : pattern) {
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    row_index_.insert(row_index_.end(), rows.begin(), rows.end());
    column_start_.push_back(static_cast<int>(row_index_.size()));
  }
  // Greedy colouring of the columns in their order: a column takes the first colour no column
  // sharing a row with it has (the rows' columns from the transpose of the pattern).
  std::vector<std::vector<int>> row_columns(static_cast<std::size_t>(size_));
  for (int c = 0; c < size_; ++c) {
    for (int p = column_start_[static_cast<std::size_t>(c)];
         p < column_start_[static_cast<std::size_t>(c) + 1]; ++p) {
      row_columns[static_cast<std::size_t>(row_index_[static_cast<std::size_t>(p)])].push_back(c);
    }
  }
  std::vector<int> colour(static_cast<std::size_t>(size_), -1);
  std::vector<int> forbidden;  // forbidden[k] == c: colour k is taken next to column c
  int colours = 0;
  for (int c = 0; c < size_; ++c) {
    if (std::find(works_.begin(), works_.end(), c) != works_.end()) continue;
    for (int p = column_start_[static_cast<std::size_t>(c)];
         p < column_start_[static_cast<std::size_t>(c) + 1]; ++p) {
      for (const int other :
           row_columns[static_cast<std::size_t>(row_index_[static_cast<std::size_t>(p)])]) {
        const int k = colour[static_cast<std::size_t>(other)];
        if (k >= 0) forbidden[static_cast<std::size_t>(k)] = c;
      }
    }
    int k = 0;
    while (k < colours && forbidden[static_cast<std::size_t>(k)] == c) ++k;
    if (k == colours) {
      ++colours;
      forbidden.push_back(-1);
    }
    colour[static_cast<std::size_t>(c)] = k;
  }
  group_start_.assign(1, 0);
  group_columns_.clear();
  std::size_t widest = 0;
  for (int k = 0; k < colours; ++k) {
    for (int c = 0; c < size_; ++c) {
      if (colour[static_cast<std::size_t>(c)] == k) group_columns_.push_back(c);
    }
    widest =
        std::max(widest, group_columns_.size() - static_cast<std::size_t>(group_start_.back()));
    group_start_.push_back(static_cast<int>(group_columns_.size()));
  }
  increment_.assign(3 * widest, 0.0);
}

bool DaeColouredJacobian::evaluate(const core::LoadContext& context, double c_j, double h,
                                   double* y, double* yp, const double* r, const double* ewt,
                                   double* work, DaeForm::Scratch& scratch,
                                   sunindextype* column_start, sunindextype* row_index,
                                   double* values) const {
  for (std::size_t c = 0; c < column_start_.size(); ++c) column_start[c] = column_start_[c];
  for (std::size_t p = 0; p < row_index_.size(); ++p) row_index[p] = row_index_[p];
  for (const int c : works_) {
    // The work's column holds its diagonal alone (dae_coloured_jacobian.hpp).
    values[column_start_[static_cast<std::size_t>(c)]] = c_j;
  }
  const double srur = std::sqrt(std::numeric_limits<double>::epsilon());
  for (int g = 0; g < group_count(); ++g) {
    const std::span<const int> columns = group(g);
    double* inc = increment_.data();
    double* y_saved = inc + columns.size();
    double* yp_saved = y_saved + columns.size();
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const int j = columns[k];
      y_saved[k] = y[j];
      yp_saved[k] = yp[j];
      double step = std::max(srur * std::max(std::abs(y[j]), std::abs(h * yp[j])), 1.0 / ewt[j]);
      if (h * yp[j] < 0.0) step = -step;
      step = (y[j] + step) - y[j];
      inc[k] = step;
      y[j] += step;
      yp[j] += c_j * step;
    }
    form_->residual(context, y, yp, work, scratch);
    for (std::size_t k = 0; k < columns.size(); ++k) {
      y[columns[k]] = y_saved[k];
      yp[columns[k]] = yp_saved[k];
    }
    for (int i = 0; i < size_; ++i) {
      if (!std::isfinite(work[i])) return false;
    }
    for (std::size_t k = 0; k < columns.size(); ++k) {
      const auto j = static_cast<std::size_t>(columns[k]);
      const double inverse = 1.0 / inc[k];
      for (int p = column_start_[j]; p < column_start_[j + 1]; ++p) {
        const int row = row_index_[static_cast<std::size_t>(p)];
        values[p] = inverse * (work[row] - r[row]);
      }
    }
  }
  return true;
}

}  // namespace flexref::reference
