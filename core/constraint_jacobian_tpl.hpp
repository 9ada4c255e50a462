#pragma once
/// \file constraint_jacobian_tpl.hpp
/// The joints' Jacobian J (m × N) stored by its non-zero blocks, in any scalar type S
/// (docs/decisions.md, "Constrained systems at scale"): a row of J acts on at most two bodies
/// (core/constraint_equations.hpp), so row r holds one block per distinct body it acts on,
/// [offset(b), offset(b) + width(b)) of the stacked velocities (core/velocity_layout.hpp), and
/// nothing else. The pattern is fixed by the rows' bodies and the layout: it is built once
/// (`build`, allocating) and every evaluation only overwrites the blocks' values, so that J v,
/// Jᵀ λ and the Schur complement J M⁻¹ Jᵀ cost O(m) instead of O(m N).
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <vector>

#include "core/block_dot_tpl.hpp"
#include "core/velocity_layout.hpp"

namespace flexref::core {

template <typename S>
class ConstraintJacobianTpl {
 public:
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  using Matrix = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
  using Block = Eigen::Map<Vector>;
  using ConstBlock = Eigen::Map<const Vector>;

  /// One body block of a row: the body, its first column (the layout's offset), its width and
  /// where its values start.
  struct Slot {
    int body = -1;
    int offset = 0;
    int width = 0;
    int start = 0;
  };

  /// The pattern of rows whose bodies row_bodies(r) gives (−1: the ground, no columns; a body
  /// named twice counts once), on `layout`, values zero. Allocates.
  template <typename RowBodies>
  void build(int rows, const VelocityLayout& layout, RowBodies&& row_bodies) {
    rows_ = rows;
    columns_ = layout.size();
    slots_.assign(static_cast<std::size_t>(2 * rows), Slot{});
    int start = 0;
    for (int r = 0; r < rows; ++r) {
      const std::array<int, 2> bodies = row_bodies(r);
      for (int k = 0; k < 2; ++k) {
        const int b = bodies[static_cast<std::size_t>(k)];
        if (b < 0 || (k == 1 && b == bodies[0])) continue;
        Slot& slot = slots_[static_cast<std::size_t>(2 * r + k)];
        slot.body = b;
        slot.offset = layout.offset(b);
        slot.width = layout.width(b);
        slot.start = start;
        start += slot.width;
      }
    }
    values_ = Vector::Zero(start);
  }

  bool built() const { return rows_ >= 0; }
  int rows() const { return rows_; }
  int cols() const { return columns_; }
  /// Slot k (0, 1) of row r; body −1: none.
  const Slot& slot(int r, int k) const { return slots_[static_cast<std::size_t>(2 * r + k)]; }
  /// Row r's values on slot k.
  Block values(int r, int k) {
    const Slot& s = slot(r, k);
    return Block(values_.data() + s.start, s.width);
  }
  ConstBlock values(int r, int k) const {
    const Slot& s = slot(r, k);
    return ConstBlock(values_.data() + s.start, s.width);
  }
  /// Row r's values on body b's columns (b must be one of the row's bodies).
  Block block(int r, int b) { return values(r, slot(r, 0).body == b ? 0 : 1); }
  /// All values, block after block (the storage other matrices of the same pattern share).
  Vector& all_values() { return values_; }
  const Vector& all_values() const { return values_; }
  void set_zero() { values_.setZero(); }

  /// J_r · x (x stacked like the velocities).
  template <typename X>
  S row_dot(int r, const X& x) const {
    S sum = S(0);
    for (int k = 0; k < 2; ++k) {
      const Slot& s = slot(r, k);
      if (s.body >= 0) sum += block_dot<S>(values_.data() + s.start, x.data() + s.offset, s.width);
    }
    return sum;
  }
  /// out += c J_rᵀ (out stacked like the velocities).
  template <typename Out>
  void add_row_transpose(int r, const S& c, Out&& out) const {
    for (int k = 0; k < 2; ++k) {
      const Slot& s = slot(r, k);
      if (s.body < 0) continue;
      if (s.width == 6) {
        // A rigid body's block, at a size known to the compiler (block_dot_tpl.hpp).
        out.template segment<6>(s.offset) +=
            c * Eigen::Map<const Eigen::Matrix<S, 6, 1>>(values_.data() + s.start);
      } else {
        out.segment(s.offset, s.width) += c * values(r, k);
      }
    }
  }
  /// |J_r|².
  S row_squared_norm(int r) const {
    S sum = S(0);
    for (int k = 0; k < 2; ++k) {
      if (slot(r, k).body >= 0) sum += values(r, k).squaredNorm();
    }
    return sum;
  }
  /// out = J x (all rows).
  template <typename X, typename Out>
  void multiply(const X& x, Out&& out) const {
    for (int r = 0; r < rows_; ++r) out(r) = row_dot(r, x);
  }
  /// The dense m × N matrix (for rare paths and outputs: allocates).
  Matrix dense() const {
    Matrix J = Matrix::Zero(rows_, columns_);
    scatter(J);
    return J;
  }
  /// Writes the blocks into a dense m × N matrix whose other entries are zero already.
  void scatter(Matrix& J) const {
    for (int r = 0; r < rows_; ++r) {
      for (int k = 0; k < 2; ++k) {
        const Slot& s = slot(r, k);
        if (s.body >= 0) J.row(r).segment(s.offset, s.width) = values(r, k).transpose();
      }
    }
  }
  /// Same pattern and values.
  bool operator==(const ConstraintJacobianTpl& other) const {
    if (rows_ != other.rows_ || columns_ != other.columns_ ||
        values_.size() != other.values_.size())
      return false;
    for (std::size_t i = 0; i < slots_.size(); ++i) {
      if (slots_[i].body != other.slots_[i].body || slots_[i].start != other.slots_[i].start) {
        return false;
      }
    }
    return values_ == other.values_;
  }

 private:
  int rows_ = -1;
  int columns_ = 0;
  std::vector<Slot> slots_;
  Vector values_;
};

using ConstraintJacobian = ConstraintJacobianTpl<double>;

}  // namespace flexref::core
