#include "studies/work_precision.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/invariants.hpp"
#include "core/state.hpp"
#include "lie/method_registry.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "reference/solve_reference.hpp"
#include "studies/missing_value.hpp"
#include "studies/mpi/distribution.hpp"
#include "studies/parallel.hpp"
#include "studies/progress.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/joint_violation.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::studies {
namespace {

// A cost or an error that no run achieved (a failed or refused run): ranks last.
constexpr double kUnreached = std::numeric_limits<double>::infinity();

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// Integrates `repeats` times and returns the last trajectory; `cpu_seconds` is the minimum
/// thread CPU time of the `integrate` calls alone.
template <typename Integrate>
core::Trajectory timed_min(int repeats, double& cpu_seconds, Integrate&& integrate) {
  cpu_seconds = kUnreached;
  core::Trajectory trajectory;
  for (int r = 0; r < repeats; ++r) {
    const double start = thread_cpu_seconds();
    trajectory = integrate();
    cpu_seconds = std::min(cpu_seconds, thread_cpu_seconds() - start);
  }
  return trajectory;
}

/// Every field of a run, an external run's output file from a rank other than 0, and what an
/// unstable run broke (core::InvariantBreach::describe).
/// The largest violation of the measured joints (NaN when none is, or one is not).
double largest_violation(const std::vector<trajectory::JointViolation>& joints) {
  if (joints.empty()) return kNaN;
  double largest = 0.0;
  for (const trajectory::JointViolation& j : joints) {
    largest = j.measured ? std::max(largest, j.value()) : kNaN;
  }
  return largest;
}

SlotCodec run_codec(std::vector<WorkPrecisionRun>& runs, std::vector<std::string>& kept_bytes,
                    std::vector<std::string>& instability, std::vector<std::string>& off_joints) {
  require_codec_size<WorkPrecisionRun, 144>();
  const auto fields = [](auto& io, auto& r) {
    io(r.method, r.kind, r.setting, r.error, r.cpu_seconds, r.status, r.evaluations, r.cpu_reported,
       r.violation);
  };
  return {[&runs, &kept_bytes, &instability, &off_joints, fields](int i, SlotWriter& w) {
            auto put = [&w](const auto&... x) { (w.put(x), ...); };
            fields(put, runs[static_cast<std::size_t>(i)]);
            w.put(kept_bytes[static_cast<std::size_t>(i)]);
            w.put(instability[static_cast<std::size_t>(i)]);
            w.put(off_joints[static_cast<std::size_t>(i)]);
          },
          [&runs, &kept_bytes, &instability, &off_joints, fields](int i, SlotReader& r) {
            auto get = [&r](auto&... x) { (r.get(x), ...); };
            fields(get, runs[static_cast<std::size_t>(i)]);
            kept_bytes[static_cast<std::size_t>(i)] = r.get_string();
            instability[static_cast<std::size_t>(i)] = r.get_string();
            off_joints[static_cast<std::size_t>(i)] = r.get_string();
          }};
}

}  // namespace

void check_work_precision_inputs(const core::Model& model, const std::vector<double>& output_times,
                                 const WorkPrecisionOptions& options) {
  if (!(options.h0 > 0.0) || !std::isfinite(options.h0)) {
    throw std::invalid_argument("--dt must be positive");
  }
  if (options.levels < 1) throw std::invalid_argument("--levels must be at least 1");
  if (options.repeats < 1) throw std::invalid_argument("--repeats must be at least 1");
  if (options.schemes.empty() && options.solvers.empty() && options.external.empty()) {
    throw std::invalid_argument("work-precision needs at least one scheme or solver");
  }
  const std::vector<std::string> schemes = lie::scheme_names();
  for (const auto& s : options.schemes) {
    if (!contains(schemes, s)) throw std::invalid_argument("unknown scheme '" + s + "'");
  }
  const std::vector<std::string> solvers = reference::reference_solver_names();
  for (const auto& s : options.solvers) {
    if (s == "exact" || !contains(solvers, s)) {
      throw std::invalid_argument("unknown or tolerance-free solver '" + s +
                                  "' (use ida, cvode or odeint)");
    }
  }
  if (!options.solvers.empty() && options.tolerances.empty()) {
    throw std::invalid_argument("--tolerances must not be empty when solvers are given");
  }
  for (double tol : options.tolerances) {
    if (!(tol > 0.0) || !std::isfinite(tol)) {
      throw std::invalid_argument("--tolerances must be positive");
    }
  }
  // Refusals before the reference: a scheme that refuses the model (the coupled model of a
  // flexible body), a level whose step does not fit the output grid.
  lie::check_method_options(options.method_options, options.schemes);
  for (const auto& s : options.schemes) lie::make_stepper(s, model, options.method_options);
  if (options.schemes.empty()) return;
  for (int level = 0; level < options.levels; ++level) {
    const double h = options.h0 / std::ldexp(1.0, level);
    try {
      lie::validate_step_grid(model, h, output_times);
    } catch (const std::invalid_argument& e) {
      std::ostringstream out;
      out << "--dt " << options.h0 << ", level " << level + 1 << " (h = " << h << "): " << e.what();
      throw std::invalid_argument(out.str());
    }
  }
}

std::vector<double> default_target_errors() { return {1e-2, 1e-4, 1e-6, 1e-8}; }

std::vector<double> reference_target_errors() { return {1e-4, 1e-6, 1e-8, 1e-10, 1e-12}; }

std::vector<CheapestMethod> cheapest_methods(const std::vector<WorkPrecisionRun>& runs,
                                             const std::vector<double>& targets) {
  std::vector<CheapestMethod> out;
  out.reserve(targets.size());
  for (double target : targets) {
    CheapestMethod best;
    best.target = target;
    for (const auto& run : runs) {
      if (run.status != "ok" || !(run.error <= target) || !std::isfinite(run.cpu_seconds)) {
        continue;
      }
      if (!best.found || run.cpu_seconds < best.run.cpu_seconds) {
        best.found = true;
        best.run = run;
      }
    }
    out.push_back(best);
  }
  return out;
}

WorkPrecisionResult run_work_precision(const core::Model& model,
                                       const std::vector<double>& output_times,
                                       const WorkPrecisionOptions& options) {
  check_work_precision_inputs(model, output_times, options);
  WorkPrecisionResult result;
  result.options = options;

  if (options.given_reference) {
    if (options.given_reference->estimate.metric != options.metric) {
      throw std::invalid_argument("the given reference's estimate is in " +
                                  options.given_reference->estimate.metric + ", not " +
                                  options.metric);
    }
    result.reference = *options.given_reference;
  } else {
    reference::SolverOptions ref_options;
    ref_options.rtol = options.reference_rtol;
    const std::string solver =
        trajectory::resolve_reference_solver(options.reference_solver, model, output_times);
    if (options.progress) {
      std::fprintf(stderr, "work-precision: reference (%s) ...\n", solver.c_str());
    }
    Progress progress("work-precision: reference (" + solver + ", with its error estimate)", 0, "",
                      options.progress);
    reference::SolveProgress solves(trajectory::reference_solve_count(model, solver));
    ref_options.progress = &solves;
    progress.follow(&solves);
    result.reference =
        trajectory::certified_reference(model, output_times, solver, ref_options, options.metric);
  }

  const int n_scheme_runs = static_cast<int>(options.schemes.size()) * options.levels;
  const int n_tolerances = static_cast<int>(options.tolerances.size());
  const int n_solver_runs = static_cast<int>(options.solvers.size()) * n_tolerances;
  // External methods: (method, step) after the solvers.
  struct ExternalRun {
    std::size_t method;
    double h;
    int level;
  };
  std::vector<ExternalRun> external_runs;
  for (std::size_t e = 0; e < options.external.size(); ++e) {
    std::vector<double> steps = options.external[e].steps;
    if (steps.empty()) {
      for (int l = 0; l < options.levels; ++l) steps.push_back(options.h0 / std::ldexp(1.0, l));
    }
    std::sort(steps.begin(), steps.end(), std::greater<>());
    for (std::size_t l = 0; l < steps.size(); ++l) {
      external_runs.push_back({e, steps[l], static_cast<int>(l)});
    }
  }
  const int n_runs = n_scheme_runs + n_solver_runs + static_cast<int>(external_runs.size());
  result.runs.resize(static_cast<std::size_t>(n_runs));
  std::vector<std::string> kept_bytes(static_cast<std::size_t>(n_runs));
  std::vector<std::string> instability(static_cast<std::size_t>(n_runs));
  std::vector<std::string> off_joints(static_cast<std::size_t>(n_runs));
  // The reference's own joint violations: an external run is judged by what it adds to them.
  const std::vector<trajectory::JointViolation> reference_joints =
      trajectory::measure_joints(model, result.reference.table);
  ProgressLine progress("work-precision", "runs", options.progress);
  const auto task = [&](int k) {
    WorkPrecisionRun& out = result.runs[static_cast<std::size_t>(k)];
    try {
      core::Trajectory trajectory;
      trajectory::ComparisonReport report;
      if (k < n_scheme_runs) {
        out.method = options.schemes[static_cast<std::size_t>(k / options.levels)];
        out.kind = "scheme";
        out.setting = options.h0 / std::ldexp(1.0, k % options.levels);
        trajectory = timed_min(options.repeats, out.cpu_seconds, [&] {
          // The stepper is built inside the timed region: building it is part of the run's
          // cost just as a reference solver's setup is part of solve_reference.
          auto stepper = lie::make_stepper(out.method, model, options.method_options);
          return lie::run_scheme(model, *stepper, out.setting, output_times);
        });
      } else if (k >= n_scheme_runs + n_solver_runs) {
        const ExternalRun& x =
            external_runs[static_cast<std::size_t>(k - n_scheme_runs - n_solver_runs)];
        const ExternalMethod& method = options.external[x.method];
        out.method = method.label;
        out.kind = "external";
        out.setting = x.h;
        // The program's own CPU time (its report of the integration alone, else wait4's whole
        // process), minimum over the repeats like the others.
        ExternalLevel run;
        out.cpu_seconds = kUnreached;
        for (int r = 0; r < options.repeats; ++r) {
          run = method.run(x.h, x.level);
          out.cpu_seconds = std::min(out.cpu_seconds, run.cpu_seconds);
        }
        out.cpu_reported = run.cpu_reported;
        kept_bytes[static_cast<std::size_t>(k)] = kept_file_bytes(method, x.level);
        trajectory::ContractOptions contract;
        contract.run_step = x.h;
        report = trajectory::compare_run(run.run, result.reference.table, contract);
        // Its joints from its positions (trajectory/joint_violation.hpp).
        const std::vector<trajectory::JointViolation> joints =
            trajectory::measure_joints(model, run.run.table);
        out.violation = largest_violation(joints);
        off_joints[static_cast<std::size_t>(k)] =
            trajectory::judge_joints(model, joints, reference_joints, report,
                                     result.reference.estimate.estimate())
                .why;
      } else {
        const int j = k - n_scheme_runs;
        out.method = options.solvers[static_cast<std::size_t>(j / n_tolerances)];
        out.kind = "solver";
        out.setting = options.tolerances[static_cast<std::size_t>(j % n_tolerances)];
        reference::SolverOptions solver_options;
        solver_options.rtol = out.setting;
        trajectory = timed_min(options.repeats, out.cpu_seconds, [&] {
          reference::ReferenceRun run =
              reference::solve_reference(out.method, model, output_times, solver_options);
          out.evaluations = run.stats.rhs_evaluations;
          return std::move(run.trajectory);
        });
      }
      if (out.kind != "external") {
        const trajectory::TrajectoryTable table = trajectory::tabulate(model, trajectory);
        report = trajectory::compare_trajectories(table, result.reference.table);
        out.violation = largest_violation(trajectory::measure_joints(model, table));
      }
      if (out.kind == "scheme") {
        // A scheme run that breaks the scene's invariants (core/invariants.hpp) is unstable.
        const core::InvariantCheck check = core::check_invariants(model, trajectory);
        if (check.breach) instability[static_cast<std::size_t>(k)] = check.breach->describe();
      }
      out.error = trajectory::metric_value(report, options.metric);
      out.status =
          !std::isfinite(out.error)                           ? "failed: non-finite error"
          : !instability[static_cast<std::size_t>(k)].empty() ? "unstable"
          : !off_joints[static_cast<std::size_t>(k)].empty()  ? "off-joints"
          : trajectory::metric_saturation(report, options.metric) >= trajectory::kSaturationFraction
              ? "saturated"
              : "ok";
    } catch (const std::exception& e) {
      out.error = kUnreached;
      out.cpu_seconds = kNaN;
      out.status = std::string("failed: ") + e.what();
    }
  };
  distributed_for(n_runs, options.jobs, task,
                  run_codec(result.runs, kept_bytes, instability, off_joints), progress.callback());
  progress.finish();
  for (std::size_t x = 0; x < external_runs.size(); ++x) {
    const auto k = static_cast<std::size_t>(n_scheme_runs + n_solver_runs) + x;
    restore_kept_file(options.external[external_runs[x].method], external_runs[x].level,
                      kept_bytes[k]);
  }

  const double ref_estimate = result.reference.estimate.estimate();
  bool any_uncertified = false;
  for (auto& run : result.runs) {
    if (run.status == "ok" && run.error < 100.0 * ref_estimate) {
      run.status = "uncertified";
      any_uncertified = true;
    }
  }
  result.cheapest = cheapest_methods(result.runs, default_target_errors());
  std::vector<WorkPrecisionRun> solver_runs;
  for (const auto& run : result.runs) {
    if (run.kind == "solver") solver_runs.push_back(run);
  }
  result.cheapest_references = cheapest_methods(solver_runs, reference_target_errors());

  if (any_uncertified) {
    std::ostringstream note;
    note << "runs marked 'uncertified' have an error below 100x the reference's estimated "
            "error "
         << ref_estimate
         << ": it cannot be measured, and they are left out of the cheapest-method table "
            "(tighten --reference-rtol to measure them)";
    result.notes.push_back(note.str());
  }
  for (std::size_t k = 0; k < result.runs.size(); ++k) {
    const WorkPrecisionRun& run = result.runs[k];
    if (run.status != "unstable") continue;
    std::ostringstream note;
    note << run.method << " at h = " << std::setprecision(3) << run.setting
         << " is unstable and left out: " << instability[k];
    result.notes.push_back(note.str());
  }
  for (std::size_t k = 0; k < result.runs.size(); ++k) {
    const WorkPrecisionRun& run = result.runs[k];
    if (run.status != "off-joints") continue;
    std::ostringstream note;
    note << run.method << " at h = " << std::setprecision(3) << run.setting
         << " is off its joints and left out: " << off_joints[k];
    result.notes.push_back(note.str());
  }
  std::string saturated;
  for (const auto& run : result.runs) {
    if (run.status != "saturated") continue;
    std::ostringstream name;
    name << run.method << " " << std::setprecision(3) << run.setting;
    saturated += (saturated.empty() ? "" : ", ") + name.str();
  }
  if (!saturated.empty()) {
    std::ostringstream note;
    note << "runs marked 'saturated' (" << saturated << ") have an error of at least " << std::fixed
         << std::setprecision(0) << 100.0 * trajectory::kSaturationFraction
         << " % of the largest the metric can give (trajectory/error_metrics.hpp): it measures how "
            "far the run strayed, and they are left out of the cheapest-method table";
    result.notes.push_back(note.str());
  }
  for (const auto& run : result.runs) {
    if (run.status.rfind("failed", 0) == 0) {
      result.notes.push_back("some runs failed (see their status); they are left out");
      break;
    }
  }
  for (const ExternalMethod& method : options.external) {
    int reported = 0, measured = 0;
    for (const auto& run : result.runs) {
      if (run.kind != "external" || run.method != method.label || !std::isfinite(run.cpu_seconds))
        continue;
      (run.cpu_reported ? reported : measured) += 1;
    }
    if (reported + measured == 0) continue;
    result.notes.push_back(
        method.label + ": " +
        (measured == 0
             ? std::string("CPU time as reported by the program (`# cpu_seconds`: its "
                           "integration alone, like the schemes')")
             : (reported == 0 ? std::string("CPU time of the whole program (wait4: start-up, "
                                            "reading the scene and writing the file included; a "
                                            "program reports its integration alone with "
                                            "`# cpu_seconds = X`, docs/external.md)")
                              : std::string("CPU time as reported by the program for some runs, "
                                            "of the whole program for the others"))));
  }
  std::ostringstream timing;
  timing << "CPU time: thread CPU time of the integration alone (output excluded), minimum of "
         << options.repeats << " run(s), " << options.jobs
         << " job(s); parallel runs share caches and memory bandwidth, --jobs 1 gives the "
            "cleanest timings (the errors do not depend on --jobs)";
  result.notes.push_back(timing.str());
  return result;
}

std::string format_work_precision_table(const WorkPrecisionResult& r) {
  std::ostringstream out;
  const auto& est = r.reference.estimate;
  // The metric first: every error below, the reference's included, is in its unit.
  out << "metric: " << trajectory::describe_metric(r.reference.table, r.options.metric) << "\n";
  out << "reference: " << trajectory::describe_reference_run(r.reference.run)
      << ", estimated error " << trajectory::describe_estimate(est) << "\n";

  // With ideal joints, each run's largest joint violation from its positions.
  bool joints = false;
  for (const auto& run : r.runs) joints = joints || !std::isnan(run.violation);
  std::string current;
  for (const auto& run : r.runs) {
    if (run.method + run.kind != current) {
      current = run.method + run.kind;
      out << "\n"
          << run.method << " (" << run.kind << ")\n"
          << std::right << std::setw(12) << (run.kind == "solver" ? "rtol" : "h [s]")
          << std::setw(12) << "error" << std::setw(11) << "cpu [s]";
      if (joints) out << std::setw(12) << "violation";
      out << "  status\n";
    }
    out << std::scientific << std::setprecision(3) << std::setw(12) << run.setting << std::setw(12)
        << run.error << std::setprecision(2) << std::setw(11);
    if (std::isnan(run.cpu_seconds)) {
      out << "-";
    } else {
      out << run.cpu_seconds;
    }
    if (joints) {
      out << std::setw(12);
      if (std::isnan(run.violation)) {
        out << "-";
      } else {
        out << run.violation;
      }
    }
    out << "  " << run.status << "\n";
  }

  const auto cheapest_table = [&out](const std::vector<CheapestMethod>& cheapest,
                                     const char* title) {
    out << "\n"
        << title << " (certified runs only):\n"
        << std::right << std::setw(8) << "target"
        << "  " << std::left << std::setw(10) << "method" << std::setw(18) << "setting"
        << std::right << std::setw(11) << "error" << std::setw(11) << "cpu [s]\n";
    for (const auto& c : cheapest) {
      out << std::right << std::scientific << std::setprecision(0) << std::setw(8) << c.target
          << "  ";
      if (!c.found) {
        out << "none reaches it\n";
        continue;
      }
      std::ostringstream setting;
      setting << (c.run.kind == "solver" ? "rtol = " : "h = ") << std::scientific
              << std::setprecision(2) << c.run.setting;
      out << std::left << std::setw(10) << c.run.method << std::setw(18) << setting.str()
          << std::right << std::setprecision(2) << std::setw(11) << c.run.error << std::setw(11)
          << c.run.cpu_seconds << "\n";
    }
  };
  cheapest_table(r.cheapest, "cheapest method per target error");
  if (!r.cheapest_references.empty()) {
    cheapest_table(r.cheapest_references, "cheapest reference solver per target error");
  }
  for (const auto& n : r.notes) out << "note: " << n << "\n";
  return out.str();
}

std::string work_precision_csv(const WorkPrecisionResult& r) {
  std::ostringstream out;
  out.precision(17);
  out << "method,kind,setting,error,cpu_seconds,status,evaluations\n";
  for (const auto& run : r.runs) {
    // A failed run's CPU time is not measured: an empty cell, not NaN.
    out << run.method << ',' << run.kind << ',' << run.setting << ',' << run.error << ','
        << trajectory::csv_number(run.cpu_seconds) << ',' << trajectory::csv_text(run.status) << ','
        << run.evaluations << '\n';
  }
  return out.str();
}

}  // namespace flexref::studies
