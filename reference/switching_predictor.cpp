#include "reference/switching_predictor.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace flexref::reference {

SwitchingPredictor::SwitchingPredictor(const OdeForm& form)
    : form_(&form),
      x_probe_(static_cast<std::size_t>(form.size())),
      xdot_probe_(x_probe_.size()),
      g_mid_(static_cast<std::size_t>(form.model().switching_function_count())),
      g_end_(g_mid_.size()) {}

double SwitchingPredictor::first_zero(double g0, double b, double c) {
  if (g0 == 0.0) return 0.0;
  if (c == 0.0) return b != 0.0 && -g0 / b > 0.0 ? -g0 / b : 0.0;
  const double discriminant = b * b - 4.0 * c * g0;
  if (discriminant < 0.0) return 0.0;
  // Stable roots: q = −½ (b + sign(b) √D), s = q / c and g0 / q.
  const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
  double best = 0.0;
  for (const double s : {q / c, q != 0.0 ? g0 / q : 0.0}) {
    if (s > 0.0 && std::isfinite(s) && (best == 0.0 || s < best)) best = s;
  }
  return best;
}

void SwitchingPredictor::switching_at(double t, double t_segment, OdeForm::Scratch& scratch,
                                      std::vector<double>& g) const {
  form_->unpack(t, x_probe_.data(), scratch.state);
  form_->model().switching_functions(core::LoadContext{t, t_segment}, scratch.state,
                                     scratch.workspace, g);
}

double SwitchingPredictor::cap(double t, const double* x, const double* xdot,
                               std::span<const double> g0, double h, double t_segment,
                               const Rhs& rhs, OdeForm::Scratch& scratch) {
  if (g0.empty() || !(h > 0.0)) return h;
  const std::size_t n = x_probe_.size();
  const double epsilon = 1e-7 * h;
  for (std::size_t i = 0; i < n; ++i) x_probe_[i] = x[i] + epsilon * xdot[i];
  if (!rhs(t + epsilon, x_probe_.data(), xdot_probe_.data())) return h;
  // ẍ = (ẋ(x + ε ẋ) − ẋ) / ε into xdot_probe_.
  for (std::size_t i = 0; i < n; ++i) xdot_probe_[i] = (xdot_probe_[i] - xdot[i]) / epsilon;
  const auto predict = [&](double tau, std::vector<double>& g) {
    for (std::size_t i = 0; i < n; ++i) {
      x_probe_[i] = x[i] + tau * xdot[i] + 0.5 * tau * tau * xdot_probe_[i];
    }
    switching_at(t + tau, t_segment, scratch, g);
  };
  predict(0.5 * h, g_mid_);
  predict(h, g_end_);
  double cap = h;
  for (std::size_t k = 0; k < g0.size(); ++k) {
    // q(s) = g0 + b s + c s² through s = 0, ½, 1.
    const double c = 2.0 * (g_end_[k] - 2.0 * g_mid_[k] + g0[k]);
    const double b = g_end_[k] - g0[k] - c;
    const double s_zero = first_zero(g0[k], b, c);
    if (s_zero > 0.0 && s_zero <= 1.0 && std::isfinite(b) && std::isfinite(c)) {
      cap = std::min(cap, 1.1 * s_zero * h);
    }
  }
  return cap;
}

}  // namespace flexref::reference
