#include "studies/reference_policy.hpp"

#include <sstream>
#include <utility>

namespace flexref::studies {

PolicyOutcome<ConvergenceResult> run_convergence_under_policy(
    const core::Model& model, const std::vector<double>& output_times, ConvergenceOptions options,
    ReferencePrecision wanted, double budget_seconds, const HighPrecisionReferences& references) {
  PolicyStudy<ConvergenceResult> study;
  study.run = [&](std::shared_ptr<const trajectory::CertifiedReference> reference,
                  ReferencePrecision) {
    options.given_reference = std::move(reference);
    return run_convergence(model, output_times, options);
  };
  study.uncertified = [](const ConvergenceResult& result) {
    int uncertified = 0;
    for (const ConvergenceLevel& level : result.levels) {
      uncertified += level.status == "uncertified" ? 1 : 0;
    }
    if (uncertified == 0) return std::string();
    std::ostringstream note;
    note << "the double reference (estimated error " << result.reference.estimate.estimate()
         << ") could not certify " << uncertified << " level(s)";
    return note.str();
  };
  PolicyOutcome<ConvergenceResult> out =
      run_with_reference_policy(wanted, budget_seconds, references, study);
  if (!out.note.empty()) out.result.notes.insert(out.result.notes.begin(), out.note);
  return out;
}

PolicyOutcome<WorkPrecisionResult> run_work_precision_under_policy(
    const core::Model& model, const std::vector<double>& output_times, WorkPrecisionOptions options,
    ReferencePrecision wanted, double budget_seconds, const HighPrecisionReferences& references) {
  PolicyStudy<WorkPrecisionResult> study;
  study.run = [&](std::shared_ptr<const trajectory::CertifiedReference> reference,
                  ReferencePrecision) {
    options.given_reference = std::move(reference);
    return run_work_precision(model, output_times, options);
  };
  study.uncertified = [](const WorkPrecisionResult& result) {
    int uncertified = 0;
    for (const WorkPrecisionRun& run : result.runs) {
      uncertified += run.status == "uncertified" ? 1 : 0;
    }
    if (uncertified == 0) return std::string();
    std::ostringstream note;
    note << "the double reference (estimated error " << result.reference.estimate.estimate()
         << ") could not certify " << uncertified << " run(s)";
    return note.str();
  };
  PolicyOutcome<WorkPrecisionResult> out =
      run_with_reference_policy(wanted, budget_seconds, references, study);
  if (!out.note.empty()) out.result.notes.insert(out.result.notes.begin(), out.note);
  return out;
}

}  // namespace flexref::studies
