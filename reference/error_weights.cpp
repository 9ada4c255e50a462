#include "reference/error_weights.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

namespace flexref::reference {

namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

}  // namespace

ErrorWeights::ErrorWeights(int size, double rtol, double atol, double span,
                           std::vector<RotationBlock> rotations, double roundoff)
    : size_(size),
      rtol_(rtol),
      atol_(atol),
      span_(span),
      rotations_(std::move(rotations)),
      roundoff_(roundoff) {}

void ErrorWeights::set_algebraic(int first, double atol) {
  algebraic_first_ = first;
  algebraic_atol_ = atol;
  differential_scale_ =
      first > 0 ? std::sqrt(static_cast<double>(size_) / static_cast<double>(first)) : 1.0;
}

void ErrorWeights::set_joint_rounding(double length_scale) { joint_length_scale_ = length_scale; }

void ErrorWeights::evaluate(const double* y, double mean_step, double* ewt) const {
  const int differential_end = algebraic_first_ >= 0 ? algebraic_first_ : size_;
  for (int i = 0; i < differential_end; ++i) ewt[i] = 1.0 / (rtol_ * std::abs(y[i]) + atol_);
  for (int i = differential_end; i < size_; ++i) {
    ewt[i] = 1.0 / (rtol_ * std::abs(y[i]) + algebraic_atol_);
  }
  // T ≤ 0: no attitude budget to share, SUNDIALS' weights on the rotation too.
  const std::size_t blocks = span_ > 0.0 ? rotations_.size() : 0;
  for (std::size_t r = 0; r < blocks; ++r) {
    const RotationBlock& b = rotations_[r];
    const double* w = y + b.w;
    double squared_speed = w[0] * w[0];
    for (int k = 1; k < b.rates; ++k) squared_speed += w[k] * w[k];
    const double speed = std::sqrt(squared_speed);
    // s = |ω̄| + 1/T; f = min(1, s h̄): the share of the run's attitude budget one step gets.
    const double rate = speed + 1.0 / span_;
    const double share = mean_step > 0.0 ? std::min(1.0, rate * mean_step) : 1.0;
    const double tol_theta = share * (rtol_ + atol_);
    // The joints' rounding turned into attitude: |p| / ℓ (rad per ε) and |v| / ℓ (rad/s per ε).
    double attitude_rounding = 1.0;
    double rate_rounding = 0.0;
    if (joint_length_scale_ > 0.0 && b.p >= 0 && b.v >= 0) {
      const double* p = y + b.p;
      const double* v = y + b.v;
      attitude_rounding =
          std::max(1.0, std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) / joint_length_scale_);
      rate_rounding = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) / joint_length_scale_;
    }
    for (int k = 0; k < b.attitudes; ++k) {
      ewt[b.theta + k] = 1.0 / std::max(tol_theta, roundoff_ * kEpsilon * attitude_rounding);
    }
    for (int k = 0; k < b.rates; ++k) {
      const double floor =
          roundoff_ * kEpsilon * std::max(std::abs(w[k]) + 1.0 / span_, rate_rounding);
      ewt[b.w + k] = 1.0 / std::max(tol_theta / span_, floor);
    }
  }
  if (differential_scale_ != 1.0) {
    for (int i = 0; i < differential_end; ++i) ewt[i] *= differential_scale_;
  }
}

}  // namespace flexref::reference
