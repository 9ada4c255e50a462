/// \file sparse_lu.cpp
/// See sparse_lu.hpp.
#include "lie/sparse_lu.hpp"

#include <klu.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace flexref::lie {

struct SparseLu::Common {
  klu_common klu;
};

namespace {

klu_symbolic* symbolic_of(void* p) { return static_cast<klu_symbolic*>(p); }
klu_numeric* numeric_of(void* p) { return static_cast<klu_numeric*>(p); }

}  // namespace

SparseLu::SparseLu() : common_(std::make_unique<Common>()) { klu_defaults(&common_->klu); }

SparseLu::~SparseLu() {
  if (numeric_ != nullptr) {
    klu_numeric* numeric = numeric_of(numeric_);
    klu_free_numeric(&numeric, &common_->klu);
  }
  if (symbolic_ != nullptr) {
    klu_symbolic* symbolic = symbolic_of(symbolic_);
    klu_free_symbolic(&symbolic, &common_->klu);
  }
}

void SparseLu::analyze(int n, const int* column_start, const int* row_index) {
  if (numeric_ != nullptr) {
    klu_numeric* numeric = numeric_of(numeric_);
    klu_free_numeric(&numeric, &common_->klu);
    numeric_ = nullptr;
  }
  if (symbolic_ != nullptr) {
    klu_symbolic* symbolic = symbolic_of(symbolic_);
    klu_free_symbolic(&symbolic, &common_->klu);
    symbolic_ = nullptr;
  }
  n_ = n;
  column_start_ = column_start;
  row_index_ = row_index;
  // KLU's arguments are not const-qualified; it does not write them.
  symbolic_ =
      klu_analyze(n, const_cast<int*>(column_start), const_cast<int*>(row_index), &common_->klu);
  if (symbolic_ == nullptr) throw std::runtime_error("KLU could not order the Newton matrix");
}

bool SparseLu::factor(const double* values) {
  auto* x = const_cast<double*>(values);
  auto* p = const_cast<int*>(column_start_);
  auto* i = const_cast<int*>(row_index_);
  if (numeric_ != nullptr) {
    if (klu_refactor(p, i, x, symbolic_of(symbolic_), numeric_of(numeric_), &common_->klu) != 0) {
      // SUNLinSol_KLU's test: the cheap estimate first, the accurate one to confirm.
      const double u23 = std::pow(std::numeric_limits<double>::epsilon(), 2.0 / 3.0);
      klu_rcond(symbolic_of(symbolic_), numeric_of(numeric_), &common_->klu);
      if (!(common_->klu.rcond < u23)) return true;
      klu_condest(p, x, symbolic_of(symbolic_), numeric_of(numeric_), &common_->klu);
      if (!(common_->klu.condest > 1.0 / u23)) return true;
    }
    klu_numeric* numeric = numeric_of(numeric_);
    klu_free_numeric(&numeric, &common_->klu);
    numeric_ = nullptr;
  }
  numeric_ = klu_factor(p, i, x, symbolic_of(symbolic_), &common_->klu);
  return numeric_ != nullptr && common_->klu.status == KLU_OK;
}

void SparseLu::solve(double* x) const {
  klu_solve(symbolic_of(symbolic_), numeric_of(numeric_), n_, 1, x, &common_->klu);
}

}  // namespace flexref::lie
