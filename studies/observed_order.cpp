#include "studies/observed_order.hpp"

#include <cmath>
#include <limits>

#include "studies/missing_value.hpp"

namespace flexref::studies {
namespace {
bool usable(double e) { return std::isfinite(e) && e > 0.0; }
}  // namespace

std::vector<double> pairwise_orders(const std::vector<double>& steps,
                                    const std::vector<double>& errors) {
  std::vector<double> p;
  for (std::size_t i = 0; i + 1 < errors.size(); ++i) {
    if (!usable(errors[i]) || !usable(errors[i + 1])) {
      p.push_back(kNaN);
    } else {
      p.push_back(std::log(errors[i] / errors[i + 1]) / std::log(steps[i] / steps[i + 1]));
    }
  }
  return p;
}

double least_squares_order(const std::vector<double>& steps, const std::vector<double>& errors,
                           const std::vector<bool>& use) {
  double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < errors.size(); ++i) {
    if (!use[i] || !usable(errors[i])) continue;
    const double x = std::log(steps[i]);
    const double y = std::log(errors[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++n;
  }
  if (n < 2) return kNaN;
  const double dn = static_cast<double>(n);
  return (dn * sxy - sx * sy) / (dn * sxx - sx * sx);
}

}  // namespace flexref::studies
