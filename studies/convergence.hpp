#pragma once
/// \file convergence.hpp
/// The `converge` study (docs/design/studies.md): each scheme at steps h0, h0/2, …, its error
/// against a certified reference in a named metric, pairwise and least-squares observed
/// orders. Levels whose error is not at least 100× the reference's estimated error are
/// "uncertified" and left out of the fit; levels at round-off stop the refinement; both are
/// said in the table.
#include <string>
#include <vector>

#include "core/model.hpp"
#include "lie/stepper.hpp"
#include "studies/certified_reference.hpp"

namespace flexref::studies {

struct ConvergenceOptions {
  std::vector<std::string> schemes = lie::scheme_names();
  double h0 = 1e-2;
  int levels = 6;
  std::string metric = "rotation+points";
  std::string reference_solver = "auto";
  double reference_rtol = 1e-12;
  int jobs = 1;
  bool progress = false;  ///< progress line on stderr
};

struct ConvergenceLevel {
  std::string scheme;
  double h = 0.0;
  long steps = 0;
  double error = 0.0;
  double order = 0.0;  ///< pairwise order against the previous level (NaN for the first)
  double cpu_seconds = 0.0;
  std::string status;  ///< "ok", "uncertified", "round-off", or "failed: why"
};

struct SchemeSummary {
  std::string scheme;
  int claimed_order = 0;
  double fitted_order = 0.0;  ///< least squares over the "ok" levels (NaN if < 2)
  int fitted_levels = 0;
};

struct ConvergenceResult {
  ConvergenceOptions options;
  CertifiedReference reference;
  std::vector<ConvergenceLevel> levels;
  std::vector<SchemeSummary> summaries;
  std::vector<std::string> notes;
};

ConvergenceResult run_convergence(const core::Model& model, const std::vector<double>& output_times,
                                  const ConvergenceOptions& options);

/// The terminal table (errors, pairwise orders, fitted orders, notes).
std::string format_convergence_table(const ConvergenceResult& result);
/// CSV: scheme,h,steps,error,order,cpu_seconds,status.
std::string convergence_csv(const ConvergenceResult& result);

}  // namespace flexref::studies
