#pragma once
/// \file reference_command.hpp
/// `flexref reference SCENE -o FILE`: a reference solution by a chosen solver, in double
/// precision or beyond it (docs/precision.md), with its estimated error.
#include <string>

#include "app/default_model.hpp"
#include "app/work_limits.hpp"
#include "core/flexible_formulation.hpp"
#include "precision/precision.hpp"
#include "reference/reference_solver.hpp"
#include "studies/reference_solver_name.hpp"

namespace flexref::app {

struct ReferenceOptions {
  std::string scene;
  core::FlexibleFormulation model = kDefaultFormulation;
  /// "auto": reference::choose_reference_solver (arkode's ESDIRK on a stiff oscillatory scene,
  /// else cvode; never the exact solution, which --solver exact asks for).
  studies::ReferenceSolver solver = studies::ReferenceSolver::kAuto;
  /// cvode: auto|adams|bdf|bdf2; ida: auto|bdf|bdf2; arkode: auto|erk|esdirk
  studies::ReferenceMethod method = studies::ReferenceMethod::kAuto;
  /// ida on ideal joints: its Newton matrix (auto: sparse).
  reference::NewtonMatrix newton_matrix = reference::NewtonMatrix::kAuto;
  reference::Coordinates coordinates = reference::Coordinates::kAuto;
  double rtol = 1e-10;
  bool rtol_given = false;  ///< else extended and quad use precision::default_rtol
  double atol = -1.0;
  bool estimate = true;
  std::string output;
  WorkLimits limits;
  /// double | extended | quad (docs/precision.md)
  flexref::precision::Precision precision = flexref::precision::Precision::kDouble;
};
int reference_command(const ReferenceOptions& options);
/// `reference --precision extended|quad` (app/high_precision_command.cpp).
int high_precision_reference_command(const ReferenceOptions& options);

}  // namespace flexref::app
