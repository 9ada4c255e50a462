#include "app/reference_command.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/help_text.hpp"
#include "app/input_checks.hpp"
#include "app/output_files.hpp"
#include "app/scene_metadata.hpp"
#include "core/output_times.hpp"
#include "reference/method_choice.hpp"
#include "reference/solve_progress.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "studies/progress.hpp"
#include "studies/reference_record.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {
namespace {

/// --method for the solver: CVODE's (auto, adams, bdf, bdf2), IDA's order cap (auto, bdf,
/// bdf2), ARKODE's (auto, erk, esdirk); another solver takes only auto. Throws
/// std::invalid_argument naming the option.
void set_method(studies::ReferenceSolver solver, studies::ReferenceMethod method,
                reference::SolverOptions& options) {
  using studies::ReferenceMethod;
  const auto refuse = [&](const std::string& accepted) {
    throw std::invalid_argument(std::string("--method ") + studies::to_string(method) + ": " +
                                studies::to_string(solver) + " takes " + accepted);
  };
  const auto one_of = [method](std::initializer_list<ReferenceMethod> accepted) {
    return std::find(accepted.begin(), accepted.end(), method) != accepted.end();
  };
  if (solver == studies::ReferenceSolver::kCvode) {
    if (!one_of({ReferenceMethod::kAuto, ReferenceMethod::kAdams, ReferenceMethod::kBdf,
                 ReferenceMethod::kBdf2})) {
      refuse("auto, adams, bdf or bdf2");
    }
    options.cvode_method = reference::parse_cvode_method(studies::to_string(method));
  } else if (solver == studies::ReferenceSolver::kIda) {
    if (!one_of({ReferenceMethod::kAuto, ReferenceMethod::kBdf, ReferenceMethod::kBdf2})) {
      refuse("auto, bdf or bdf2");
    }
    options.cvode_method = reference::parse_cvode_method(studies::to_string(method));
  } else if (solver == studies::ReferenceSolver::kArkode) {
    if (!one_of({ReferenceMethod::kAuto, ReferenceMethod::kErk, ReferenceMethod::kEsdirk})) {
      refuse("auto, erk or esdirk");
    }
    options.arkode_method = reference::parse_arkode_method(studies::to_string(method));
  } else if (method != ReferenceMethod::kAuto) {
    refuse("no --method");
  }
}

}  // namespace

int reference_command(const ReferenceOptions& options) {
  if (options.precision != precision::Precision::kDouble) {
    return high_precision_reference_command(options);
  }
  if (options.rtol < 1e-15) {
    throw std::invalid_argument("--rtol " + number_text(options.rtol) +
                                ": double precision takes rtol >= 1e-15 (--precision extended or "
                                "quad for tighter references)");
  }
  const scene::Scene scene = load_scene(options.scene, options.model);
  const core::Model& model = *scene.model;
  const std::vector<double> times =
      limited_output_times(scene.end_time, scene.output_step, options.limits);
  studies::ReferenceSolver chosen = reference_solver_for(model, options.solver, "--solver");
  std::string solver_reason = "chosen with --solver";
  if (chosen == studies::ReferenceSolver::kAuto) {
    const reference::ReferenceSolverChoice choice =
        reference::choose_reference_solver(model, reference::mean_output_spacing(times));
    chosen = studies::parse_reference_solver(choice.solver);
    solver_reason = choice.reason;
  }
  const std::string solver = studies::to_string(chosen);
  check_output_file(options.output, true);
  reference::SolverOptions solver_options;
  solver_options.rtol = options.rtol;
  solver_options.atol = options.atol;
  set_method(chosen, options.method, solver_options);
  if (options.newton_matrix != reference::NewtonMatrix::kAuto &&
      chosen != studies::ReferenceSolver::kIda) {
    throw std::invalid_argument(std::string("--newton-matrix: ") + studies::to_string(chosen) +
                                " takes none (ida only)");
  }
  solver_options.newton_matrix = options.newton_matrix;
  if (options.coordinates != reference::Coordinates::kAuto &&
      chosen != studies::ReferenceSolver::kCvode) {
    throw std::invalid_argument(std::string("--coordinates: ") + studies::to_string(chosen) +
                                " takes none (cvode only)");
  }
  solver_options.coordinates = options.coordinates;

  trajectory::CertifiedReference ref;
  {
    studies::Progress progress(
        "reference: " + solver + (options.estimate ? " and its error estimate" : ""), 0, "");
    reference::SolveProgress solves(
        options.estimate ? trajectory::reference_solve_count(model, solver) : 1);
    solver_options.progress = &solves;
    progress.follow(&solves);
    if (options.estimate) {
      ref = trajectory::certified_reference(model, times, solver, solver_options,
                                            trajectory::kDefaultMetric);
    } else {
      ref.run = reference::solve_reference(solver, model, times, solver_options);
      ref.table = trajectory::tabulate(model, ref.run.trajectory);
    }
    solver_options.progress = nullptr;
  }
  trajectory::write_csv(ref.table, options.output);

  const auto& st = ref.run.stats;
  studies::StudyRecord record = scene_record(options.scene, scene);
  record.table("integrator")
      .set("kind", "reference")
      .set("solver", ref.run.solver)
      .set("solver_reason", solver_reason)
      .set("method", ref.run.method)
      .set("method_reason", ref.run.method_reason)
      .set("jacobian", ref.run.jacobian)
      .set("coordinates", ref.run.coordinates)
      .set("coordinates_reason", ref.run.coordinates_reason)
      .set("rtol", options.rtol)
      .set("atol", solver_options.absolute_tolerance())
      .set("steps", st.steps)
      .set("rhs_evaluations", st.rhs_evaluations)
      .set("jacobian_evaluations", st.jacobian_evaluations)
      .set("error_test_failures", st.error_test_failures)
      .set("nonlinear_failures", st.nonlinear_failures)
      .set("cpu_seconds", st.cpu_seconds)
      .set("events", ref.run.event_times.size())
      .set("event_times", ref.run.event_times);
  const trajectory::BalancePeak balance = trajectory::largest_energy_balance(ref.table);
  if (!std::isnan(balance.value)) {
    record.table("integrator")
        .set("largest_energy_balance", balance.value)
        .set("largest_energy_balance_time", balance.time);
  }
  if (options.estimate) {
    const auto& e = ref.estimate;
    // estimate = inf: no check was a different, more accurate solution (see method).
    record.table("error_estimate")
        .set("metric", e.metric)
        .set("estimate", e.estimate())
        .set("method", e.method);
    if (!std::isnan(e.energy_balance)) {
      // The balance next to the scale it is read against (trajectory/certified_reference.hpp).
      record.table("error_estimate")
          .set("energy_balance", e.energy_balance)
          .set("energy_balance_time", e.energy_balance_time)
          .set("energy_estimate", e.energy_estimate);
    }
    studies::add_estimate_checks(record, "error_estimate.check", e);
  }
  record.table("columns")
      .set("names", ref.table.columns)
      .set("units", trajectory::trajectory_units(model));
  studies::add_versions(record);
  write_sidecar(record, options.output);

  std::ostream& summary = summary_stream(options.output);
  summary << "reference " << scene.name << " with " << ref.run.solver << " (" << ref.run.method
          << ")";
  if (model.has_flexible_bodies()) {
    summary << " (" << core::to_string(model.formulation()) << " model)";
  }
  if (ref.run.solver == "exact") {
    summary << " (analytic, " << st.steps << " output times)";
  } else {
    summary << " (rtol " << options.rtol << "): " << st.steps << " steps, " << st.rhs_evaluations
            << " evaluations";
  }
  if (model.switching_function_count() > 0 || !ref.run.event_times.empty()) {
    summary << ", " << ref.run.event_times.size() << " events located";
  }
  summary << ", " << st.cpu_seconds << " s CPU; wrote " << options.output << "\n";
  if (options.solver == studies::ReferenceSolver::kAuto)
    summary << "solver: " << solver_reason << "\n";
  if (ref.run.solver == "cvode" || ref.run.solver == "ida" || ref.run.solver == "arkode") {
    summary << "method: " << ref.run.method_reason << "\n";
  }
  if (!ref.run.jacobian.empty()) summary << "newton systems: " << ref.run.jacobian << "\n";
  if (model.has_constraints() && ref.run.solver == "cvode") {
    summary << "coordinates: " << ref.run.coordinates << " (" << ref.run.coordinates_reason
            << ")\n";
  }
  if (!options.estimate && !std::isnan(balance.value)) {
    summary << "energy balance: largest |E - E0 + W_d - W_a - W_drive| " << balance.value
            << " J at t = " << balance.time << " s\n";
  }
  if (options.estimate) {
    const auto& e = ref.estimate;
    summary << "estimated error (" << e.metric << " [" << trajectory::metric_unit(e.metric)
            << "]): " << trajectory::describe_estimate(e) << "\n";
    if (!std::isnan(e.energy_balance)) {
      summary << "energy balance: " << trajectory::describe_energy_balance(e) << "\n";
    }
    for (const auto& c : e.checks) {
      summary << "  " << c.role << ": " << c.solver;
      if (c.rtol > 0.0) summary << " rtol " << c.rtol;
      summary << ", " << c.steps << " steps, distance " << c.distance
              << (c.used ? "" : " (not used: " + c.note + ")") << "\n";
    }
  }
  return kExitOk;
}

RegisteredCommand register_reference_command(CLI::App& app) {
  auto options = std::make_shared<ReferenceOptions>();
  CLI::App* cmd = app.add_subcommand("reference", "compute a reference solution");
  cmd->add_option("scene", options->scene, "scene file (TOML)")->required();
  add_enum_option(cmd, "--solver", options->solver,
                  "auto (arkode's ESDIRK on a stiff oscillatory scene, else cvode) | ida | "
                  "cvode | arkode | odeint | exact",
                  {"auto", "ida", "cvode", "arkode", "odeint", "exact"},
                  studies::parse_reference_solver,
                  [](studies::ReferenceSolver v) { return studies::to_string(v); });
  add_enum_option(cmd, "--method", options->method,
                  "cvode: auto (from the scene's stiff elements) | adams | bdf | bdf2 (BDF "
                  "orders 1-2); ida: auto | bdf | bdf2; arkode: auto | erk | esdirk",
                  {"auto", "adams", "bdf", "bdf2", "erk", "esdirk"},
                  studies::parse_reference_method,
                  [](studies::ReferenceMethod v) { return studies::to_string(v); });
  add_enum_option(
      cmd, "--newton-matrix", options->newton_matrix,
      "ida on ideal joints: auto (sparse) | dense (difference quotients, dense "
      "LU) | sparse (coloured difference quotients, KLU)",
      {"auto", "dense", "sparse"},
      [](const std::string& v) {
        return v == "dense"    ? reference::NewtonMatrix::kDense
               : v == "sparse" ? reference::NewtonMatrix::kSparse
                               : reference::NewtonMatrix::kAuto;
      },
      [](reference::NewtonMatrix v) {
        return v == reference::NewtonMatrix::kDense    ? std::string("dense")
               : v == reference::NewtonMatrix::kSparse ? std::string("sparse")
                                                       : std::string("auto");
      });
  add_enum_option(
      cmd, "--coordinates", options->coordinates,
      "cvode on ideal joints: auto (joint coordinates for rigid bodies without contact where "
      "Adams runs, else maximal) | maximal | joint",
      {"auto", "maximal", "joint"}, reference::parse_coordinates,
      [](reference::Coordinates v) { return std::string(reference::to_string(v)); });
  cmd->add_option("--rtol", options->rtol,
                  "relative tolerance (double >= 1e-15; default for extended 1e-16, quad 1e-28)")
      ->check(number_in(1e-32, 1e-1))
      ->capture_default_str();
  cmd->add_option("--atol", options->atol, "absolute tolerance (default: = rtol)")
      ->check(number_in(1e-16, 1.0));
  cmd->add_flag("!--no-estimate", options->estimate,
                "skip the error estimate (rerun 100x tighter and a second solver)");
  cmd->add_option("-o,--output", options->output, std::string("CSV ") + kOutputFileHelp)
      ->required();
  add_model_option(cmd, options->model);
  add_enum_option(
      cmd, "--precision", options->precision,
      "double | extended (80-bit long double) | quad (binary128): the arithmetic of "
      "the reference (docs/precision.md; extended and quad carry every scene: "
      "rigid and flexible bodies, loads, potentials, contacts, gap supports and "
      "joints)",
      {"double", "extended", "quad"},
      [](const std::string& name) { return precision::parse_precision(name); },
      [](precision::Precision p) { return precision::to_string(p); });
  add_limits(cmd, options->limits, false);

  return {cmd, [options, cmd] {
            options->rtol_given = cmd->count("--rtol") > 0;
            return reference_command(*options);
          }};
}

}  // namespace flexref::app
