#pragma once
/// \file work_limits.hpp
/// The command line's work limits: the largest output and step counts a command accepts.

#include "studies/reference_policy.hpp"

namespace flexref::app {

/// Work limits (docs/decisions.md, "Command line"): one scheme run of more steps, or a
/// trajectory of more output rows, is refused before any work unless the limit is raised
/// explicitly (--max-steps, --max-rows). 1e7 steps is ~10 s to minutes of CPU for the bundled
/// scenes; 1e6 rows of ~30 columns is ~0.5 GB of CSV.
struct WorkLimits {
  double max_steps = 1e7;
  double max_rows = 1e6;
};

/// The default --reference-budget (docs/precision.md, "Cost guard"): the reference policy's.
using studies::kDefaultReferenceBudget;

}  // namespace flexref::app
