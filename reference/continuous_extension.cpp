#include "reference/continuous_extension.hpp"

#include <cstddef>

namespace flexref::reference {

namespace {

constexpr int kConditions = 2 * ContinuousExtension::kNodes;  // degree 7
/// z_i: each node twice (value and derivative).
constexpr std::array<double, kConditions> kZ{0.0,       0.0,       1.0 / 3.0, 1.0 / 3.0,
                                             2.0 / 3.0, 2.0 / 3.0, 1.0,       1.0};

}  // namespace

ContinuousExtension::ContinuousExtension(int size) { resize(size); }

void ContinuousExtension::resize(int size) {
  size_ = size;
  coefficients_.assign(static_cast<std::size_t>(kConditions * size), 0.0);
}

void ContinuousExtension::fit(double t0, double h, const std::array<const double*, kNodes>& x,
                              const std::array<const double*, kNodes>& f) {
  t0_ = t0;
  h_ = h;
  for (int c = 0; c < size_; ++c) {
    // Divided-difference table in place: d[i] = x[z_i] first, then column by column.
    std::array<double, kConditions> d{};
    for (std::size_t i = 0; i < d.size(); ++i) d[i] = x[i / 2][c];
    // First column: repeated nodes take the derivative dx/ds = h f.
    for (int i = kConditions - 1; i >= 1; --i) {
      const auto u = static_cast<std::size_t>(i);
      d[u] = u % 2 == 1 ? h * f[u / 2][c] : (d[u] - d[u - 1]) / (kZ[u] - kZ[u - 1]);
    }
    for (int order = 2; order < kConditions; ++order) {
      for (int i = kConditions - 1; i >= order; --i) {
        const auto u = static_cast<std::size_t>(i);
        d[u] = (d[u] - d[u - 1]) / (kZ[u] - kZ[u - static_cast<std::size_t>(order)]);
      }
    }
    for (int k = 0; k < kConditions; ++k) {
      coefficients_[static_cast<std::size_t>(c * kConditions + k)] = d[static_cast<std::size_t>(k)];
    }
  }
}

void ContinuousExtension::evaluate(double t, double* out) const {
  const double s = (t - t0_) / h_;
  for (int c = 0; c < size_; ++c) {
    const double* coefficient = coefficients_.data() + static_cast<std::ptrdiff_t>(c * kConditions);
    double p = coefficient[kConditions - 1];
    for (int k = kConditions - 2; k >= 0; --k)
      p = p * (s - kZ[static_cast<std::size_t>(k)]) + coefficient[k];
    out[c] = p;
  }
}

}  // namespace flexref::reference
