#pragma once

/// \file figure_command.hpp
/// `flexref figure STUDY.toml --out DIR`: the paper's trajectory figures (studies/
/// trajectory_figure.hpp) from a study file (docs/design/studies.md, "Reproducing the paper's
/// figures"; studies/paper/*.toml).

#include <string>

#include "app/work_limits.hpp"
#include "studies/reference_precision.hpp"

namespace flexref::app {

struct FigureCommandOptions {
  std::string study;  ///< the study file (TOML)
  std::string out_dir = "out/figure";
  int jobs = 0;  ///< 0: all cores
  WorkLimits limits;
  /// auto | double | extended | quad (docs/precision.md): "auto" repeats the figure against a quad
  /// reference when the double one cannot certify a curve and the scene allows it.
  studies::ReferencePrecision reference_precision = studies::ReferencePrecision::kAuto;
  /// auto's wall-time bound on the quad reference, s (0: none; docs/precision.md, "Cost guard").
  double reference_budget = kDefaultReferenceBudget;
};

int figure_command(const FigureCommandOptions& options);

}  // namespace flexref::app
