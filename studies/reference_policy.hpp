#pragma once
/// \file reference_policy.hpp
/// Which reference a study measures against (docs/precision.md): the precision asked for
/// (`--reference-precision`, Python's `precision=`), and "auto"'s retry — when the double
/// reference leaves a level, run or curve uncertified and the scene allows it, the study runs
/// again against a quad-precision reference, within a wall-time budget (the cost guard). One
/// function for the commands `converge`, `work-precision`, `figure` and the Python module.
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "core/model.hpp"
#include "studies/convergence.hpp"
#include "studies/reference_precision.hpp"
#include "studies/work_precision.hpp"
#include "trajectory/certified_reference.hpp"

namespace flexref::studies {

/// The default wall-time budget of "auto"'s quad reference (docs/precision.md, "Cost guard"),
/// s: 10 minutes, two orders above what the bundled studies' quad references take (book_toss:
/// seconds) and far below the hours of a stiff many-mode body (flexible_spinner_64).
inline constexpr double kDefaultReferenceBudget = 600.0;

/// The references beyond double of one study (the scene, its output times, the metric, the
/// --reference-solver), computed by the layer that has the extended/quad model
/// (studies/high_precision_references.hpp). Studies see only this interface.
class HighPrecisionReferences {
 public:
  virtual ~HighPrecisionReferences() = default;
  /// The certified reference in `precision` (extended or quad), computed without a budget;
  /// throws std::invalid_argument when the scene, the metric or the reference solver rule it
  /// out.
  virtual std::shared_ptr<const trajectory::CertifiedReference> compute(
      ReferencePrecision precision) const = 0;
  /// Whether "auto" may switch to a quad reference: the scene is one the extended/quad model
  /// carries, the metric one it measures, and no reference solver was named.
  virtual bool quad_possible() const = 0;
  /// "auto"'s quad reference within budget_seconds of wall time (0: no bound): nullptr, with
  /// `refused` saying why and what to do, when its projected time is over the budget.
  virtual std::shared_ptr<const trajectory::CertifiedReference> quad_within_budget(
      double budget_seconds, std::string& refused) const = 0;
};

/// A study's outcome under the reference policy.
template <class Result>
struct PolicyOutcome {
  Result result;
  ReferencePrecision precision_used = ReferencePrecision::kDouble;
  /// Why "auto" retried, or why it could not ("the double reference (estimated error 3.2e-09)
  /// could not certify 2 level(s): the study was repeated with ..."); empty when it did not.
  std::string note;
  /// Why "auto" kept the double reference (the budget), empty when it did not.
  std::string refused;
};

/// How the policy sees one study.
template <class Result>
struct PolicyStudy {
  /// Runs the study against `reference` (nullptr: the study's own double reference) in
  /// `precision`, the precision of that reference (for the tables).
  std::function<Result(std::shared_ptr<const trajectory::CertifiedReference> reference,
                       ReferencePrecision precision)>
      run;
  /// Empty when the double reference certified everything; else the note's start, what it
  /// left uncertified ("the double reference (estimated error 3.2e-09) could not certify 2
  /// level(s)").
  std::function<std::string(const Result&)> uncertified;
  /// The note's end when the quad reference replaced it.
  std::string repeated = "the study was repeated with a quad-precision reference";
};

/// Runs `study` under the reference policy: a given extended or quad precision computes that
/// reference first (refusals before any scheme runs) and runs once; "double" runs once on the
/// study's own reference; "auto" runs on it and, when `uncertified` says so and
/// references.quad_possible(), computes the quad reference within budget_seconds and runs
/// again (or keeps the double one and says why).
template <class Result>
PolicyOutcome<Result> run_with_reference_policy(ReferencePrecision wanted, double budget_seconds,
                                                const HighPrecisionReferences& references,
                                                const PolicyStudy<Result>& study) {
  PolicyOutcome<Result> out;
  if (wanted == ReferencePrecision::kExtended || wanted == ReferencePrecision::kQuad) {
    out.result = study.run(references.compute(wanted), wanted);
    out.precision_used = wanted;
    return out;
  }
  out.result = study.run(nullptr, ReferencePrecision::kDouble);
  if (wanted != ReferencePrecision::kAuto) return out;
  const std::string uncertified = study.uncertified(out.result);
  if (uncertified.empty() || !references.quad_possible()) return out;
  const std::shared_ptr<const trajectory::CertifiedReference> quad =
      references.quad_within_budget(budget_seconds, out.refused);
  if (quad) {
    out.result = study.run(quad, ReferencePrecision::kQuad);
    out.precision_used = ReferencePrecision::kQuad;
    out.note = uncertified + ": " + study.repeated + " (docs/precision.md)";
  } else {
    out.note = uncertified + "; " + out.refused;
  }
  return out;
}

/// The convergence study under the policy (`converge`, Python's flexref.converge): the note,
/// when there is one, first among the result's notes. options.given_reference is replaced.
PolicyOutcome<ConvergenceResult> run_convergence_under_policy(
    const core::Model& model, const std::vector<double>& output_times, ConvergenceOptions options,
    ReferencePrecision wanted, double budget_seconds, const HighPrecisionReferences& references);

/// The work-precision study under the policy (`work-precision`, Python's
/// flexref.work_precision), as run_convergence_under_policy.
PolicyOutcome<WorkPrecisionResult> run_work_precision_under_policy(
    const core::Model& model, const std::vector<double>& output_times, WorkPrecisionOptions options,
    ReferencePrecision wanted, double budget_seconds, const HighPrecisionReferences& references);

}  // namespace flexref::studies
