#include "core/time_profile.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace flexref::core {

TimeProfile::TimeProfile(Shape shape, double start, double duration)
    : shape_(shape), start_(start), duration_(duration) {
  if (shape != Shape::kConstant && shape != Shape::kHarmonic &&
      !(duration > 0.0 && std::isfinite(duration))) {
    throw std::invalid_argument("pulse duration must be positive and finite");
  }
  if (!std::isfinite(start)) throw std::invalid_argument("pulse start must be finite");
}

TimeProfile TimeProfile::constant() { return TimeProfile(Shape::kConstant, 0.0, 0.0); }

TimeProfile TimeProfile::sin2_pulse(double start, double duration) {
  return TimeProfile(Shape::kSin2Pulse, start, duration);
}

TimeProfile TimeProfile::rectangular_pulse(double start, double duration) {
  return TimeProfile(Shape::kRectangularPulse, start, duration);
}

TimeProfile TimeProfile::harmonic(double frequency, double phase) {
  if (!(frequency > 0.0 && std::isfinite(frequency))) {
    throw std::invalid_argument("harmonic frequency must be positive and finite");
  }
  if (!std::isfinite(phase)) throw std::invalid_argument("harmonic phase must be finite");
  TimeProfile p(Shape::kHarmonic, 0.0, 0.0);
  p.frequency_ = frequency;
  p.phase_ = phase;
  return p;
}

bool TimeProfile::active(double t_segment) const {
  return t_segment >= start_ && t_segment < start_ + duration_;
}

void TimeProfile::append_discontinuities(std::vector<double>& times) const {
  if (shape_ == Shape::kConstant || shape_ == Shape::kHarmonic) return;
  // sin² is C¹ at its ends (its second derivative jumps by 2π²/duration²); the rectangular
  // pulse jumps. Both ends are switches every integrator must step on.
  times.push_back(start_);
  times.push_back(start_ + duration_);
}

double TimeProfile::end() const {
  if (shape_ == Shape::kConstant || shape_ == Shape::kHarmonic) {
    return std::numeric_limits<double>::infinity();
  }
  return start_ + duration_;
}

}  // namespace flexref::core
