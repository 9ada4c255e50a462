#include "studies/observed_order.hpp"

#include <cmath>
#include <cstddef>
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

double distance_order(const std::vector<LevelDistance>& pairs) {
  std::vector<LevelDistance> used;
  for (const LevelDistance& d : pairs) {
    if (usable(d.distance) && d.coarse > d.fine && d.fine > 0.0) used.push_back(d);
  }
  if (used.size() < 2) return kNaN;
  // The residual of the fit at order p, log C eliminated as the mean:
  //   r_i = log d_i − log(h_c^p − h_f^p) − mean, with log(h_c^p − h_f^p) = p log h_c +
  //   log1p(−(h_f/h_c)^p) (no cancellation for small p).
  const auto residual = [&](double p) {
    std::vector<double> y;
    double mean = 0.0;
    for (const LevelDistance& d : used) {
      y.push_back(std::log(d.distance) - p * std::log(d.coarse) -
                  std::log1p(-std::pow(d.fine / d.coarse, p)));
      mean += y.back();
    }
    mean /= static_cast<double>(y.size());
    double sum = 0.0;
    for (const double v : y) sum += (v - mean) * (v - mean);
    return sum;
  };
  // A scan brackets the minimum, golden-section search refines it to 1e-10.
  constexpr double kLow = 0.05, kHigh = 10.0, kScan = 0.01;
  double best = kLow;
  double best_value = residual(kLow);
  for (double p = kLow + kScan; p <= kHigh + 1e-12; p += kScan) {
    const double v = residual(p);
    if (v < best_value) {
      best = p;
      best_value = v;
    }
  }
  if (best <= kLow + 0.5 * kScan || best >= kHigh - 0.5 * kScan) return kNaN;
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = best - kScan;
  double b = best + kScan;
  while (b - a > 1e-10) {
    const double c = b - phi * (b - a);
    const double d = a + phi * (b - a);
    if (residual(c) < residual(d)) {
      b = d;
    } else {
      a = c;
    }
  }
  return 0.5 * (a + b);
}

}  // namespace flexref::studies
