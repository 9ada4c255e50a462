#include "studies/high_precision_references.hpp"

#include <stdexcept>
#include <utility>

#include "precision/high_precision_reference.hpp"
#include "precision/reference_budget.hpp"
#include "reference/solve_progress.hpp"
#include "studies/progress.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::studies {
namespace {

/// The metrics an extended or quad reference measures (its run keeps rotations and points).
bool measurable(const std::string& metric) {
  return metric == trajectory::kDefaultMetric || metric == "rotation+points" ||
         metric == "rotation" || metric == "points";
}

}  // namespace

StudyReferences::StudyReferences(const scene::Scene& scene, const std::vector<double>& times,
                                 std::string metric, ReferenceSolver reference_solver,
                                 std::string study)
    : scene_(scene),
      times_(times),
      metric_(std::move(metric)),
      reference_solver_(reference_solver),
      study_(std::move(study)) {}

std::shared_ptr<const trajectory::CertifiedReference> StudyReferences::compute(
    ReferencePrecision wanted) const {
  return solve(wanted, 0.0);
}

std::shared_ptr<const trajectory::CertifiedReference> StudyReferences::solve(
    ReferencePrecision wanted, double budget_seconds) const {
  const std::string name = to_string(wanted);
  const precision::Precision p = precision::parse_precision(name);
  precision::check_supported(scene_.spec, scene_.model->formulation());
  if (!measurable(metric_)) {
    throw std::invalid_argument("--metric " + metric_ + ": " + name +
                                " precision references measure relative, rotation+points, "
                                "rotation or points");
  }
  if (reference_solver_ != ReferenceSolver::kAuto) {
    throw std::invalid_argument("--reference-solver: a " + name +
                                " precision reference is Odeint's; omit --reference-solver");
  }
  Progress progress(
      study_ + ": reference (odeint, " + name + " precision, with its error estimate)", 0, "");
  reference::SolveProgress solves(2);
  progress.follow(&solves);
  return std::make_shared<const trajectory::CertifiedReference>(
      precision::certified_high_precision_reference(
          scene_.spec, times_, p, precision::default_rtol(p), metric_, nullptr,
          scene_.model->formulation(), budget_seconds, &solves));
}

bool StudyReferences::quad_possible() const {
  if (reference_solver_ != ReferenceSolver::kAuto || !measurable(metric_)) return false;
  try {
    precision::check_supported(scene_.spec, scene_.model->formulation());
  } catch (const std::invalid_argument&) {
    return false;
  }
  return true;
}

std::shared_ptr<const trajectory::CertifiedReference> StudyReferences::quad_within_budget(
    double budget_seconds, std::string& refused) const {
  try {
    return solve(ReferencePrecision::kQuad, budget_seconds);
  } catch (const precision::BudgetExceeded& e) {
    refused = std::string(e.what()) +
              " (--reference-budget): the study keeps the double reference; give "
              "--reference-precision quad to compute it anyway, a larger --reference-budget or a "
              "shorter end_time";
    return nullptr;
  }
}

}  // namespace flexref::studies
