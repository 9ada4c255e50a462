#include "lie/scheme_support.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flexref::lie::detail {

bool starts_on_discontinuity(std::span<const double> discontinuities, double t_n, double h) {
  const double tolerance = 1e-9 * std::max(h, std::abs(t_n));
  const auto it = std::lower_bound(discontinuities.begin(), discontinuities.end(), t_n - tolerance);
  return it != discontinuities.end() && *it <= t_n + tolerance;
}

bool all_finite(const core::State& state) {
  // One sum instead of 13 tests per body: NaN and ±inf propagate through a sum. The sum of
  // finite values can overflow only for entries near 1e308, which are reported as non-finite
  // too — a state that large has already failed.
  double sum = 0.0;
  for (const core::BodyState& s : state) {
    sum += s.p_WBr.sum() + s.theta_WB.sum() + s.v_WBr.sum() + s.w_WB_B.sum();
  }
  return std::isfinite(sum) && sum == sum;
}

std::string newton_failure(const char* scheme, double t_n, double h, double relative_residual,
                           int iterations, int body) {
  std::ostringstream out;
  out.precision(17);
  out << scheme << " Newton did not converge at t = " << t_n << " (step h = " << h << "), residual "
      << relative_residual << " (relative, tolerance " << kNewtonTolerance << ") after "
      << iterations << " iterations, body " << body;
  return out.str();
}

std::string non_finite_failure(const char* scheme, double t_n, double h) {
  std::ostringstream out;
  out.precision(17);
  out << scheme << ": non-finite state in the step from t = " << t_n << " with h = " << h;
  return out.str();
}

}  // namespace flexref::lie::detail
