#pragma once
/// \file accuracy_check.hpp
/// The accuracy check of a study's reference runs (lte-map, modes): each run is repeated at a
/// tighter tolerance, rtol / estimate_factor, and the distance between the two estimates the
/// run's own error, as a certified reference's checks do (trajectory/certified_reference.hpp, 100×
/// tighter). `--estimate-factor F` means the same in every command: the check is F times tighter.
#include <string>

namespace flexref::trajectory {

/// Relative tolerances below this are round-off limited in double precision: a check there is
/// not more accurate than the run (certified_reference.hpp clamps its checks at it).
inline constexpr double kTightestRtol = 1e-14;

/// The check's tolerance: rtol / estimate_factor.
inline double accuracy_check_rtol(double rtol, double estimate_factor) {
  return rtol / estimate_factor;
}

/// Throws std::invalid_argument, naming the study, when the check's tolerance falls below
/// kTightestRtol (e.g. --rtol 1e-14 with --estimate-factor 10): such a check is no more accurate
/// than the run and its distance would not estimate the run's error.
void check_accuracy_check_rtol(const std::string& study, double rtol, double estimate_factor);

}  // namespace flexref::trajectory
