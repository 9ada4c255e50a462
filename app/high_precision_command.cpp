/// \file high_precision_command.cpp
/// `flexref reference SCENE --precision extended|quad [--solver odeint|exact]`
/// (docs/precision.md).
#include <iostream>
#include <memory>
#include <stdexcept>

#include "app/exit_codes.hpp"
#include "app/input_checks.hpp"
#include "app/output_files.hpp"
#include "app/reference_command.hpp"
#include "app/scene_metadata.hpp"
#include "io/output_file.hpp"
#include "precision/exact_high_precision.hpp"
#include "precision/high_precision_reference.hpp"
#include "reference/solve_progress.hpp"
#include "studies/progress.hpp"
#include "studies/reference_record.hpp"
#include "studies/study_record.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::app {
namespace {

/// `--solver exact`: the closed form (torque-free body, Lagrange top) evaluated in the
/// precision, with no tolerance; its error estimate (unless --no-estimate) is the distance to
/// an independent numerical solution in the same precision, as for the double exact reference.
int exact_reference_command(const ReferenceOptions& options, precision::Precision p,
                            const scene::Scene& scene) {
  if (options.rtol_given || options.atol >= 0.0 ||
      options.method != studies::ReferenceMethod::kAuto) {
    throw std::invalid_argument("--solver exact takes no --rtol, --atol or --method");
  }
  const std::vector<double> times =
      limited_output_times(scene.end_time, scene.output_step, options.limits);
  check_output_file(options.output, true);
  const precision::HighPrecisionRun run = precision::exact_high_precision(scene.spec, times, p);
  trajectory::ReferenceEstimate estimate;
  if (options.estimate) {
    studies::Progress progress(std::string("reference: exact solution's error estimate (odeint "
                                           "in ") +
                                   precision::to_string(p) + " precision)",
                               0, "");
    reference::SolveProgress solves(1);
    progress.follow(&solves);
    estimate = precision::exact_high_precision_estimate(scene.spec, times, run,
                                                        trajectory::kDefaultMetric, &solves);
  }
  io::write_output_file(options.output, precision::high_precision_csv(run));
  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("integrator")
      .set("kind", "reference")
      .set("solver", "exact")
      .set("method", run.method)
      .set("precision", precision::to_string(p))
      .set("significant_digits", precision::significant_digits(p))
      .set("cpu_seconds", run.cpu_seconds);
  if (options.estimate) {
    record.table("error_estimate")
        .set("metric", estimate.metric)
        .set("estimate", estimate.estimate())
        .set("method", estimate.method);
    studies::add_estimate_checks(record, "error_estimate.check", estimate);
  }
  record.table("columns").set("names", run.columns);
  studies::add_versions(record);
  write_sidecar(record, options.output);
  summary_stream(options.output) << "reference " << scene.name << " with " << run.method << ": "
                                 << run.steps << " output times, " << run.cpu_seconds
                                 << " s; wrote " << options.output << "\n";
  if (options.estimate) {
    summary_stream(options.output) << "estimated error (" << estimate.metric << " ["
                                   << trajectory::metric_unit(estimate.metric)
                                   << "]): " << trajectory::describe_estimate(estimate) << "\n";
  }
  return kExitOk;
}

}  // namespace

int high_precision_reference_command(const ReferenceOptions& options) {
  const precision::Precision p = options.precision;
  const std::string name = precision::to_string(p);
  const core::FlexibleFormulation formulation = options.model;
  const scene::Scene scene = load_scene(options.scene, formulation);
  precision::check_supported(scene.spec, formulation);
  if (options.solver == studies::ReferenceSolver::kExact) {
    return exact_reference_command(options, p, scene);
  }
  if (options.solver != studies::ReferenceSolver::kAuto &&
      options.solver != studies::ReferenceSolver::kOdeint) {
    throw std::invalid_argument(std::string("--solver ") + studies::to_string(options.solver) +
                                ": " + name +
                                " precision references are Odeint's (Bulirsch-Stoer) or the "
                                "exact solution; omit --solver or give odeint or exact");
  }
  if (options.method != studies::ReferenceMethod::kAuto) {
    throw std::invalid_argument("--method: " + name + " precision references take no --method");
  }
  if (options.atol >= 0.0 && options.atol != options.rtol) {
    throw std::invalid_argument("--atol: " + name + " precision references use atol = rtol");
  }
  const double rtol = options.rtol_given ? options.rtol : precision::default_rtol(p);
  const std::vector<double> times =
      limited_output_times(scene.end_time, scene.output_step, options.limits);
  check_output_file(options.output, true);

  precision::HighPrecisionRun run;
  trajectory::CertifiedReference ref;
  {
    studies::Progress progress(std::string("reference: odeint in ") + precision::to_string(p) +
                                   " precision" +
                                   (options.estimate ? " and its error estimate" : ""),
                               0, "");
    reference::SolveProgress solves(options.estimate ? 2 : 1);
    progress.follow(&solves);
    if (options.estimate) {
      ref = precision::certified_high_precision_reference(
          scene.spec, times, p, rtol, trajectory::kDefaultMetric, &run, formulation, 0.0, &solves);
    } else {
      run = precision::solve_high_precision(scene.spec, times, p, rtol, formulation, &solves);
    }
  }
  io::write_output_file(options.output, precision::high_precision_csv(run));

  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("integrator")
      .set("kind", "reference")
      .set("solver", "odeint")
      .set("method", run.method)
      .set("precision", precision::to_string(p))
      .set("significant_digits", precision::significant_digits(p))
      .set("rtol", rtol)
      .set("atol", rtol)
      .set("steps", run.steps)
      .set("rhs_evaluations", run.evaluations)
      .set("cpu_seconds", run.cpu_seconds)
      .set("events", run.events.size());
  if (!run.events.empty()) {
    // Located to the working precision: the times keep every digit (as the CSV's values).
    std::vector<std::string> event_times, kinds;
    for (const precision::HighPrecisionEvent& e : run.events) {
      event_times.push_back(e.time);
      kinds.push_back(e.kind + " " + std::to_string(e.pair + 1));
    }
    record.table("integrator").set("event_times", event_times).set("event_kinds", kinds);
  }
  if (options.estimate) {
    const auto& e = ref.estimate;
    record.table("error_estimate")
        .set("metric", e.metric)
        .set("estimate", e.estimate())
        .set("method", e.method);
    studies::add_estimate_checks(record, "error_estimate.check", e);
  }
  record.table("columns").set("names", run.columns);
  studies::add_versions(record);
  write_sidecar(record, options.output);

  std::ostream& summary = summary_stream(options.output);
  summary << "reference " << scene.name << " with odeint (" << run.method << ", rtol " << rtol
          << "): " << run.steps << " steps, " << run.evaluations << " evaluations, "
          << run.cpu_seconds << " s; wrote " << options.output << "\n";
  if (options.estimate) {
    summary << "estimated error (" << ref.estimate.metric << " ["
            << trajectory::metric_unit(ref.estimate.metric)
            << "]): " << trajectory::describe_estimate(ref.estimate) << "\n";
  }
  return kExitOk;
}

}  // namespace flexref::app
