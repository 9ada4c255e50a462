#include "reference/integral_weights.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace flexref::reference {

void scale_integral_weights(const IntegralComponents& integrals, long steps, double rtol,
                            double atol, const double* y, std::span<double> weights) {
  const double n = static_cast<double>(std::max(1L, steps));
  constexpr double kRoundoff = 100.0 * std::numeric_limits<double>::epsilon();
  for (int i = integrals.first; i < integrals.first + integrals.count; ++i) {
    const double size = std::abs(y[i]);
    // (rtol |y_i| + atol)/n, not below 100 round-offs of the value
    weights[static_cast<std::size_t>(i)] =
        1.0 / std::max((rtol * size + atol) / n, kRoundoff * size);
  }
}

IntegralBase::IntegralBase(IntegralComponents works)
    : works_(works), base_(static_cast<std::size_t>(works.count), 0.0) {}

void IntegralBase::start(std::span<const double> values, double* y) {
  for (std::size_t j = 0; j < base_.size(); ++j) {
    base_[j] = values[j];
    y[works_.first + static_cast<int>(j)] = 0.0;
  }
}

void IntegralBase::rebase(double* y) {
  for (std::size_t j = 0; j < base_.size(); ++j) {
    double& increment = y[works_.first + static_cast<int>(j)];
    base_[j] += increment;
    increment = 0.0;
  }
}

void IntegralBase::values(const double* y, std::span<double> out) const {
  for (std::size_t j = 0; j < base_.size(); ++j) {
    out[j] = base_[j] + y[works_.first + static_cast<int>(j)];
  }
}

}  // namespace flexref::reference
