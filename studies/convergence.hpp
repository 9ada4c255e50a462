#pragma once
/// \file convergence.hpp
/// The `converge` study (docs/design/studies.md): each scheme at steps h0, h0/2, …, its error
/// against a certified reference in a named metric, pairwise and least-squares observed
/// orders. Only levels that measure the scheme's asymptotic error enter the fit; the others are
/// marked and the table says why: a step above the scene's explicit step limit
/// (core::explicit_step_limit: central differences on a mode or penalty element are unstable
/// there), an error that does not decrease from the previous valid level, an error not at
/// least 100× the reference's estimated error ("uncertified"), or an error at round-off
/// (which also stops the refinement). No order is fitted from fewer than three valid levels
/// (two points always lie on a line: their "order" verifies nothing).
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/step_limit.hpp"
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
  /// "ok", "above step limit", "not decreasing", "uncertified", "round-off", or "failed: why".
  std::string status;
};

struct SchemeSummary {
  std::string scheme;
  int claimed_order = 0;
  double fitted_order = 0.0;  ///< least squares over the "ok" levels (NaN if < 3)
  int fitted_levels = 0;      ///< the "ok" levels
  bool refused() const { return fitted_levels < kMinFittedLevels; }
  /// The fewest valid levels an order is fitted from.
  static constexpr int kMinFittedLevels = 3;
};

struct ConvergenceResult {
  ConvergenceOptions options;
  CertifiedReference reference;
  core::StepLimit step_limit;  ///< the model's explicit step limit (unbounded: rigid only)
  std::vector<ConvergenceLevel> levels;
  std::vector<SchemeSummary> summaries;
  std::vector<std::string> notes;
  /// True when a scheme has no fitted order (fewer than three valid levels): the study
  /// refuses to report an order for it (exit code 4).
  bool refused() const;
};

/// Throws std::invalid_argument, before any work, when a scheme refuses the model (e.g. the
/// coupled model of a flexible body) or a level's step does not fit the output grid
/// (lie::validate_step_grid). run_convergence calls it before the reference.
void check_convergence_inputs(const core::Model& model, const std::vector<double>& output_times,
                              const ConvergenceOptions& options);

/// Classifies the levels of result (errors, steps and "ok"/"failed: …" statuses filled in,
/// schemes × options.levels in order) against result.step_limit and the reference's estimate,
/// computes the pairwise orders, the fitted orders and the notes.
void summarize_convergence(ConvergenceResult& result, const std::vector<int>& claimed_orders);

ConvergenceResult run_convergence(const core::Model& model, const std::vector<double>& output_times,
                                  const ConvergenceOptions& options);

/// The terminal table (errors, pairwise orders, fitted orders, notes).
std::string format_convergence_table(const ConvergenceResult& result);
/// CSV: scheme,h,steps,error,order,cpu_seconds,status.
std::string convergence_csv(const ConvergenceResult& result);

}  // namespace flexref::studies
