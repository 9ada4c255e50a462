#pragma once
/// \file sparse_lu.hpp
/// A sparse LU of a square matrix in compressed sparse columns, by SuiteSparse's KLU (Davis &
/// Palamadai Natarajan 2010; Debian's libsuitesparse-dev): the ordering (AMD on the blocks of
/// its block triangular form) once per pattern (analyze), a factorization with partial pivoting
/// at the first factor of a pattern, and then refactorizations with the same pivots
/// (klu_refactor: no allocation), redone with fresh pivots when the cheap estimate of the
/// reciprocal condition number falls below u^(2/3) and the accurate one confirms it (SUNDIALS'
/// SUNLinSol_KLU rule, sunlinsol_klu.c of SUNDIALS 6.4). Solves in place, allocating nothing.
#include <memory>

namespace flexref::lie {

class SparseLu {
 public:
  SparseLu();
  ~SparseLu();
  SparseLu(const SparseLu&) = delete;
  SparseLu& operator=(const SparseLu&) = delete;

  /// Orders the pattern (n columns, column starts and row indices as Eigen's compressed
  /// SparseMatrix<double, ColMajor, int> holds them); the arrays must outlive the factors and
  /// keep this pattern. Throws std::runtime_error when KLU cannot order it.
  void analyze(int n, const int* column_start, const int* row_index);
  bool analyzed() const { return symbolic_ != nullptr; }
  /// Factors the values of the analyzed pattern; false when the matrix is singular (or not
  /// finite). Allocates only at the first factorization of a pattern and where the pivots
  /// are chosen again.
  bool factor(const double* values);
  /// x ← A⁻¹ x for the last factored A.
  void solve(double* x) const;

 private:
  struct Common;
  std::unique_ptr<Common> common_;
  void* symbolic_ = nullptr;
  void* numeric_ = nullptr;
  int n_ = 0;
  const int* column_start_ = nullptr;
  const int* row_index_ = nullptr;
};

}  // namespace flexref::lie
