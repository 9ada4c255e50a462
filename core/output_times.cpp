#include "core/output_times.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace flexref::core {

std::vector<double> output_times(double end_time, double output_step) {
  if (!(end_time > 0.0) || !std::isfinite(end_time)) {
    throw std::invalid_argument("end time must be positive and finite");
  }
  if (!(output_step > 0.0) || !std::isfinite(output_step)) {
    throw std::invalid_argument("output step must be positive and finite");
  }
  std::vector<double> times;
  const double n_exact = end_time / output_step;
  // 1e9 rows would be tens of gigabytes of CSV: certainly a typing error.
  if (!(n_exact <= 1e9)) throw std::invalid_argument("more than 1e9 output times");
  // Accept the last grid point when it lies within 1e-9 steps of the end time.
  const auto n = static_cast<long>(std::floor(n_exact + 1e-9));
  times.reserve(static_cast<std::size_t>(n + 2));
  for (long k = 0; k <= n; ++k) times.push_back(static_cast<double>(k) * output_step);
  if (std::abs(times.back() - end_time) > 1e-9 * output_step) {
    times.push_back(end_time);
  } else {
    times.back() = end_time;
  }
  return times;
}

double smallest_resolved_step(double t) {
  return 1e6 * std::numeric_limits<double>::epsilon() * std::abs(t);
}

bool is_multiple_of(double t, double h) {
  const double ratio = t / h;
  return std::abs(ratio - std::round(ratio)) <= 1e-9 * std::max(1.0, std::abs(ratio));
}

}  // namespace flexref::core
