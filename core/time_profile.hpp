#pragma once
/// \file time_profile.hpp
/// Scalar time laws that multiply a load: constant, sin² pulse, rectangular pulse, harmonic.
///
/// Piecewise laws are evaluated with two times: t, where the smooth branch is evaluated, and
/// t_segment, a time strictly inside the integration step or solver interval that decides
/// which branch is active. An integrator evaluating at the end of a step that ends on a switch
/// passes a t_segment inside that step and so gets the left limit; the next step gets the
/// right limit. This is how every integrator stops at load discontinuities without ever
/// evaluating the "wrong side" of a jump (docs/design/schemes.md, "Reference integrators").
#include <boost/math/constants/constants.hpp>
#include <cmath>
#include <vector>

namespace flexref::core {

class TimeProfile {
 public:
  enum class Shape { kConstant, kSin2Pulse, kRectangularPulse, kHarmonic };

  /// f(t) = 1.
  static TimeProfile constant();
  /// f(t) = sin²(π (t − start)/duration) for start ≤ t < start + duration, else 0 (C¹ at ends).
  static TimeProfile sin2_pulse(double start, double duration);
  /// f(t) = 1 for start ≤ t < start + duration, else 0 (jumps at both ends).
  static TimeProfile rectangular_pulse(double start, double duration);

  /// f(t) = sin(2π frequency t + phase), frequency > 0 in Hz, phase in rad: smooth, no switch
  /// (the stand-in for flow-induced excitation of docs/contact.md, "Gap support").
  static TimeProfile harmonic(double frequency, double phase);

  /// Value at t on the branch active at t_segment.
  double value(double t, double t_segment) const { return value_in(t, t_segment); }
  /// value() in the scalar type S (double; long double and float128 in the extended/quad
  /// models of precision/): the same laws, written once, the branch chosen in double by
  /// t_segment.
  template <typename S>
  S value_in(const S& t, double t_segment) const;
  /// Times where the law or one of its first derivatives jumps.
  void append_discontinuities(std::vector<double>& times) const;
  /// The time from which the law is 0 for good: a pulse's end, +∞ for the constant and the
  /// harmonic law.
  double end() const;

  Shape shape() const { return shape_; }
  double start() const { return start_; }
  double duration() const { return duration_; }
  double frequency() const { return frequency_; }
  double phase() const { return phase_; }

 private:
  TimeProfile(Shape shape, double start, double duration);
  bool active(double t_segment) const;

  Shape shape_;
  double start_;
  double duration_;
  double frequency_ = 0.0;
  double phase_ = 0.0;
};

template <typename S>
S TimeProfile::value_in(const S& t, double t_segment) const {
  using std::sin;
  const S pi = boost::math::constants::pi<S>();
  switch (shape_) {
    case Shape::kConstant:
      return S(1);
    case Shape::kSin2Pulse: {
      if (!active(t_segment)) return S(0);
      const S s = sin(pi * (t - S(start_)) / S(duration_));
      return s * s;
    }
    case Shape::kRectangularPulse:
      return active(t_segment) ? S(1) : S(0);
    case Shape::kHarmonic:
      return sin(S(2) * pi * S(frequency_) * t + S(phase_));
  }
  return S(0);
}

}  // namespace flexref::core
