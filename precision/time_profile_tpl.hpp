#pragma once
/// \file time_profile_tpl.hpp
/// A load's time profile (core/time_profile.hpp) evaluated in the precision of precision/'s
/// models. Internal to precision/.
#include <boost/math/constants/constants.hpp>
#include <cmath>

#include "core/time_profile.hpp"

namespace flexref::precision {

/// core::TimeProfile::value in precision S (the same laws; the branch is chosen in double by
/// t_segment, as there).
template <typename S>
S profile_value(const core::TimeProfile& p, S t, double t_segment) {
  using std::sin;
  const bool active = t_segment >= p.start() && t_segment < p.start() + p.duration();
  const S pi = boost::math::constants::pi<S>();
  switch (p.shape()) {
    case core::TimeProfile::Shape::kConstant:
      return S(1);
    case core::TimeProfile::Shape::kSin2Pulse: {
      if (!active) return S(0);
      const S s = sin(pi * (t - S(p.start())) / S(p.duration()));
      return s * s;
    }
    case core::TimeProfile::Shape::kRectangularPulse:
      return active ? S(1) : S(0);
    case core::TimeProfile::Shape::kHarmonic:
      return sin(S(2) * pi * S(p.frequency()) * t + S(p.phase()));
  }
  return S(0);
}

}  // namespace flexref::precision
