#include "studies/convergence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/invariants.hpp"
#include "io/input_file.hpp"
#include "io/output_file.hpp"
#include "lie/method_registry.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "studies/missing_value.hpp"
#include "studies/mpi/distribution.hpp"
#include "studies/observed_order.hpp"
#include "studies/parallel.hpp"
#include "studies/progress.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/joint_violation.hpp"
#include "trajectory/reference_sidecar.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::studies {
namespace {

// An error below this is at the level of accumulated round-off for the step counts studies
// use (10³–10⁷ steps: √N·ε·|state| ≈ 1e-14…1e-12 for O(1) states, with the constant of the
// error propagation of unstable motions such as the book toss on top); refining further
// measures round-off, not the scheme.
constexpr double kRoundOffFloor = 1e-11;

/// The degrees of freedom the joints leave the bodies: the velocity unknowns of the motion the
/// model integrates (6 per free body, the 3 rotations of a pivot, none for a prescribed rigid
/// motion; the modes of every flexible body) less the independent joint rows. 0: the motion is
/// kinematic, set at every instant by the joints and their drives.
int degrees_of_freedom(const core::Model& model) {
  int unknowns = 0;
  for (const core::Body& body : model.bodies()) {
    unknowns += (body.is_free()                              ? 6
                 : body.motion() == core::MotionKind::kPivot ? 3
                                                             : 0) +
                body.mode_count();
  }
  return unknowns - static_cast<int>(model.independent_rows().size());
}

bool measures_positions(const std::string& metric) {
  return metric == "relative" || metric == "rotation+points" || metric == "rotation" ||
         metric == "points" || metric == "position";
}

/// External levels: the quantities the metric measured and the run's columns it ignored.
struct Measured {
  std::vector<std::string> used, ignored;
  std::string kept_bytes;   ///< the level's output file, from a rank other than 0
  std::string instability;  ///< an unstable level: the invariant it broke (InvariantBreach)
  std::string bounds;       ///< metric_bounds_text of the level's comparison
  std::string off_joints;   ///< an external level off its joints: why (judge_joints)
};

SlotCodec level_codec(std::vector<ConvergenceLevel>& levels, std::vector<Measured>& measured) {
  require_codec_size<ConvergenceLevel, 152>();
  const auto fields = [](auto& io, auto& l) {
    io(l.scheme, l.h, l.steps, l.error, l.order, l.cpu_seconds, l.status, l.saturation, l.violation,
       l.joints);
  };
  return {[&levels, &measured, fields](int i, SlotWriter& w) {
            auto put = [&w](const auto&... x) { (w.put(x), ...); };
            const auto k = static_cast<std::size_t>(i);
            fields(put, levels[k]);
            for (const auto* names : {&measured[k].used, &measured[k].ignored}) {
              w.put(static_cast<long>(names->size()));
              for (const std::string& name : *names) w.put(name);
            }
            w.put(measured[k].kept_bytes);
            w.put(measured[k].instability);
            w.put(measured[k].bounds);
            w.put(measured[k].off_joints);
          },
          [&levels, &measured, fields](int i, SlotReader& r) {
            auto get = [&r](auto&... x) { (r.get(x), ...); };
            const auto k = static_cast<std::size_t>(i);
            fields(get, levels[k]);
            for (auto* names : {&measured[k].used, &measured[k].ignored}) {
              names->resize(static_cast<std::size_t>(r.get_int()));
              for (std::string& name : *names) name = r.get_string();
            }
            measured[k].kept_bytes = r.get_string();
            measured[k].instability = r.get_string();
            measured[k].bounds = r.get_string();
            measured[k].off_joints = r.get_string();
          }};
}

/// A level's largest joint violation and each joint's (trajectory/joint_violation.hpp).
void record_joints(const std::vector<trajectory::JointViolation>& joints, ConvergenceLevel& out) {
  if (joints.empty()) return;
  double largest = 0.0;
  for (const trajectory::JointViolation& j : joints) {
    out.joints += (out.joints.empty() ? "" : "; ") + trajectory::describe_violation(j);
    largest = j.measured ? std::max(largest, j.value()) : kNaN;
  }
  out.violation = largest;
}

}  // namespace

std::string kept_file_bytes(const ExternalMethod& method, int level) {
  if (distribution().is_root() || !method.kept_file) return {};
  io::InputFile in(method.kept_file(level), "a run's output file");
  if (!in.is_open()) return {};
  try {
    return in.read_all();
  } catch (const std::runtime_error&) {
    return {};
  }
}

void restore_kept_file(const ExternalMethod& method, int level, const std::string& bytes) {
  if (bytes.empty() || !distribution().is_root() || !method.kept_file) return;
  io::write_output_file(method.kept_file(level), bytes);
}

SchemeSummary summarize_levels(const std::string& method, int claimed_order,
                               std::vector<ConvergenceLevel>& levels, double reference_estimate,
                               const core::StepLimit& step_limit, std::vector<std::string>& notes) {
  std::vector<double> steps, errors;
  std::vector<bool> use;
  bool stopped = false;
  double last_valid_error = std::numeric_limits<double>::infinity();
  int above_limit = 0;
  int not_decreasing = 0;
  std::vector<double> saturated;
  double saturation = 0.0;
  for (ConvergenceLevel& lv : levels) {
    steps.push_back(lv.h);
    errors.push_back(lv.error);
    if ((lv.status == "ok" || lv.status == "unstable") && lv.h > step_limit.h) {
      // Central differences on the limiting mode are unstable: the error measures that
      // instability (or an implicit scheme's unresolved mode), not the scheme's order. The
      // cause is named rather than its symptom.
      lv.status = "above step limit";
      ++above_limit;
    } else if (lv.status != "ok") {
      // failed or unstable: stays as it is
    } else if (stopped) {
      lv.status = "round-off";
    } else if (lv.saturation >= trajectory::kSaturationFraction) {
      // The error is a sizeable fraction of the largest the metric can give: it measures how
      // far the run strayed, not the scheme's order.
      lv.status = "saturated";
      saturated.push_back(lv.h);
      saturation = std::max(saturation, lv.saturation);
    } else if (lv.error <= kRoundOffFloor) {
      lv.status = "round-off";
      stopped = true;
      std::ostringstream note;
      note << lv.scheme << ": refinement stopped at h = " << lv.h << ": error " << lv.error
           << " is at round-off level (<= " << kRoundOffFloor << ")";
      notes.push_back(note.str());
    } else if (lv.error >= last_valid_error) {
      lv.status = "not decreasing";
      ++not_decreasing;
    } else if (lv.error < trajectory::kCertificationFactor * reference_estimate) {
      lv.status = "uncertified";
    }
    if (lv.status == "ok") last_valid_error = lv.error;
    use.push_back(lv.status == "ok");
  }
  const std::vector<double> p = pairwise_orders(steps, errors);
  for (std::size_t l = 0; l < levels.size(); ++l) levels[l].order = l == 0 ? kNaN : p[l - 1];
  SchemeSummary summary;
  summary.scheme = method;
  summary.claimed_order = claimed_order;
  for (bool u : use) summary.fitted_levels += u ? 1 : 0;
  summary.fitted_order = summary.refused() ? kNaN : least_squares_order(steps, errors, use);
  if (above_limit > 0) {
    std::ostringstream note;
    note << method << ": " << above_limit << " level" << (above_limit > 1 ? "s" : "")
         << " above the explicit step limit " << std::setprecision(3) << step_limit.h << " s of "
         << step_limit.what
         << " (2/omega: central differences are unstable there) left out of the fit";
    notes.push_back(note.str());
  }
  if (!saturated.empty()) {
    std::ostringstream note;
    note << method << ": " << saturated.size() << " level" << (saturated.size() > 1 ? "s" : "")
         << " saturated left out of the fit (h =";
    for (std::size_t k = 0; k < saturated.size(); ++k) {
      note << (k ? ", " : " ") << std::setprecision(3) << saturated[k];
    }
    note << "): errors up to " << std::fixed << std::setprecision(0) << 100.0 * saturation
         << " % of the largest the metric can give (saturated from "
         << 100.0 * trajectory::kSaturationFraction
         << " %) measure how far the run strayed from the reference, not the order";
    notes.push_back(note.str());
  }
  if (not_decreasing > 0) {
    std::ostringstream note;
    note << method << ": " << not_decreasing << " level" << (not_decreasing > 1 ? "s" : "")
         << " whose error does not decrease from the previous valid level left out of the "
            "fit (not in the asymptotic range)";
    notes.push_back(note.str());
  }
  if (summary.refused()) {
    std::ostringstream note;
    note << method << ": refused to fit an order from " << summary.fitted_levels << " valid level"
         << (summary.fitted_levels == 1 ? "" : "s") << " (at least "
         << SchemeSummary::kMinFittedLevels
         << " needed); change --dt or add --levels so that three levels lie below the step "
            "limit and above the reference's error";
    notes.push_back(note.str());
  }
  // Asymptotic range: the last two pairwise orders of the fitted levels must agree to 0.3
  // (a second-order scheme with an O(h³) term still visible drifts by more than that).
  std::vector<double> fitted_orders;
  for (std::size_t k = 1; k < levels.size(); ++k) {
    if (use[k] && use[k - 1]) fitted_orders.push_back(p[k - 1]);
  }
  const std::size_t m = fitted_orders.size();
  if (!summary.refused() && m >= 2 && std::abs(fitted_orders[m - 1] - fitted_orders[m - 2]) > 0.3) {
    std::ostringstream note;
    note << std::fixed << std::setprecision(2) << summary.scheme
         << ": the pairwise orders are still changing (" << fitted_orders[m - 2] << ", "
         << fitted_orders[m - 1]
         << "): the finest levels are not yet in the asymptotic range; refine further "
            "(more --levels) before trusting the fitted order";
    notes.push_back(note.str());
  }
  return summary;
}

void check_convergence_inputs(const core::Model& model, const std::vector<double>& output_times,
                              const ConvergenceOptions& options) {
  if (!(options.h0 > 0.0) || !std::isfinite(options.h0)) {
    throw std::invalid_argument("--dt must be positive and finite");
  }
  if (options.levels < SchemeSummary::kMinFittedLevels) {
    throw std::invalid_argument("--levels must be at least 3 (an order is fitted from three)");
  }
  for (const ExternalMethod& e : options.external) {
    if (!e.run) throw std::invalid_argument("external method '" + e.label + "' has no runner");
    if (!e.steps.empty() &&
        e.steps.size() < static_cast<std::size_t>(SchemeSummary::kMinFittedLevels)) {
      throw std::invalid_argument("external method '" + e.label +
                                  "' needs at least three steps (an order is fitted from three)");
    }
    for (double h : e.steps) {
      if (!(h > 0.0) || !std::isfinite(h)) {
        throw std::invalid_argument("external method '" + e.label + "': steps must be positive");
      }
    }
  }
  lie::check_method_options(options.method_options, options.schemes);
  for (const std::string& scheme : options.schemes) {
    lie::make_stepper(scheme, model, options.method_options);
  }
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

ConvergenceResult run_convergence(const core::Model& model, const std::vector<double>& output_times,
                                  const ConvergenceOptions& options) {
  check_convergence_inputs(model, output_times, options);
  ConvergenceResult result;
  result.options = options;
  result.step_limit = core::explicit_step_limit(model);

  // Methods as blocks of levels: the registered schemes, then the external methods.
  struct Block {
    std::string name;
    int external = -1;  ///< index into options.external, −1 for a scheme
    std::vector<double> steps;
    std::size_t first = 0;  ///< index of its first level in result.levels
  };
  std::vector<Block> blocks;
  std::vector<double> halvings;
  for (int l = 0; l < options.levels; ++l) halvings.push_back(options.h0 / std::ldexp(1.0, l));
  for (const std::string& scheme : options.schemes) blocks.push_back({scheme, -1, halvings, 0});
  for (std::size_t e = 0; e < options.external.size(); ++e) {
    std::vector<double> steps =
        options.external[e].steps.empty() ? halvings : options.external[e].steps;
    std::sort(steps.begin(), steps.end(), std::greater<>());
    blocks.push_back({options.external[e].label, static_cast<int>(e), steps, 0});
  }
  struct Task {
    std::size_t block;
    int level;
  };
  std::vector<Task> tasks;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    blocks[b].first = tasks.size();
    for (std::size_t l = 0; l < blocks[b].steps.size(); ++l) {
      tasks.push_back({b, static_cast<int>(l)});
    }
  }

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
    if (options.progress) std::fprintf(stderr, "converge: reference (%s) ...\n", solver.c_str());
    Progress progress("converge: reference (" + solver + ", with its error estimate)", 0, "",
                      options.progress);
    reference::SolveProgress solves(trajectory::reference_solve_count(model, solver));
    ref_options.progress = &solves;
    progress.follow(&solves);
    result.reference =
        trajectory::certified_reference(model, output_times, solver, ref_options, options.metric);
  }

  // The reference's own joint violations: a run is judged by what it adds to them.
  result.joints = model.has_constraints();
  const std::vector<trajectory::JointViolation> reference_joints =
      trajectory::measure_joints(model, result.reference.table);

  const int n_runs = static_cast<int>(tasks.size());
  result.levels.resize(tasks.size());
  std::vector<Measured> measured(tasks.size());
  ProgressLine progress("converge", "runs", options.progress);
  const auto task = [&](int k) {
    const Block& block = blocks[tasks[static_cast<std::size_t>(k)].block];
    const int level = tasks[static_cast<std::size_t>(k)].level;
    ConvergenceLevel& out = result.levels[static_cast<std::size_t>(k)];
    out.scheme = block.name;
    out.h = block.steps[static_cast<std::size_t>(level)];
    const double t_span = output_times.back() - output_times.front();
    out.steps = std::lround(t_span / out.h);
    try {
      trajectory::ComparisonReport report;
      std::vector<trajectory::JointViolation> joints;
      if (block.external < 0) {
        auto stepper = lie::make_stepper(block.name, model, options.method_options);
        const double start = thread_cpu_seconds();
        const core::Trajectory trajectory = lie::run_scheme(model, *stepper, out.h, output_times);
        out.cpu_seconds = thread_cpu_seconds() - start;
        const trajectory::TrajectoryTable table = trajectory::tabulate(model, trajectory);
        report = trajectory::compare_trajectories(table, result.reference.table);
        joints = trajectory::measure_joints(model, table);
        const core::InvariantCheck check = core::check_invariants(model, trajectory);
        if (check.breach) {
          measured[static_cast<std::size_t>(k)].instability = check.breach->describe();
        }
      } else {
        const ExternalMethod& method = options.external[static_cast<std::size_t>(block.external)];
        Measured& m = measured[static_cast<std::size_t>(k)];
        const ExternalLevel run = method.run(out.h, level);
        m.kept_bytes = kept_file_bytes(method, level);
        out.cpu_seconds = run.cpu_seconds;
        trajectory::ContractOptions contract;
        contract.run_step = out.h;
        report = trajectory::compare_run(run.run, result.reference.table, contract);
        m.used = trajectory::metric_quantities(report, options.metric);
        m.ignored = report.ignored_columns;
        // Its joints from its positions (a scheme's are held by its own invariant monitor).
        joints = trajectory::measure_joints(model, run.run.table);
        m.off_joints = trajectory::judge_joints(model, joints, reference_joints, report,
                                                result.reference.estimate.estimate())
                           .why;
      }
      record_joints(joints, out);
      out.error = trajectory::metric_value(report, options.metric);
      out.saturation = trajectory::metric_saturation(report, options.metric);
      measured[static_cast<std::size_t>(k)].bounds =
          trajectory::metric_bounds_text(report, options.metric);
      const Measured& m = measured[static_cast<std::size_t>(k)];
      out.status = !std::isfinite(out.error) ? "failed: non-finite error"
                   : !m.instability.empty()  ? "unstable"
                   : !m.off_joints.empty()   ? "off-joints"
                                             : "ok";
    } catch (const std::exception& e) {
      out.error = std::numeric_limits<double>::infinity();
      out.status = std::string("failed: ") + e.what();
    }
  };
  distributed_for(n_runs, options.jobs, task, level_codec(result.levels, measured),
                  progress.callback());
  progress.finish();
  for (std::size_t k = 0; k < tasks.size(); ++k) {
    const Block& block = blocks[tasks[k].block];
    if (block.external < 0) continue;
    restore_kept_file(options.external[static_cast<std::size_t>(block.external)], tasks[k].level,
                      measured[k].kept_bytes);
  }

  const double ref_estimate = result.reference.estimate.estimate();
  for (const Block& block : blocks) {
    const auto first = static_cast<std::ptrdiff_t>(block.first);
    const auto count = static_cast<std::ptrdiff_t>(block.steps.size());
    std::vector<ConvergenceLevel> levels(result.levels.begin() + first,
                                         result.levels.begin() + first + count);
    int claimed = 0;
    if (block.external < 0) {
      claimed = lie::make_stepper(block.name, model, options.method_options)->order();
    } else {
      claimed = options.external[static_cast<std::size_t>(block.external)].claimed_order;
      // What the metric measured in this method's files (the first level that was read).
      for (std::ptrdiff_t l = 0; l < count; ++l) {
        const Measured& m = measured[static_cast<std::size_t>(first + l)];
        if (m.used.empty()) continue;
        std::string used, ignored;
        for (const std::string& x : m.used) used += (used.empty() ? "" : ", ") + x;
        for (const std::string& x : m.ignored) ignored += (ignored.empty() ? "" : ", ") + x;
        result.notes.push_back(block.name + ": metric " + options.metric + " over " + used +
                               (ignored.empty() ? "" : "; ignored columns: " + ignored));
        break;
      }
    }
    result.summaries.push_back(
        summarize_levels(block.name, claimed, levels, ref_estimate,
                         block.external < 0 ? result.step_limit : core::StepLimit{}, result.notes));
    std::copy(levels.begin(), levels.end(), result.levels.begin() + first);
  }
  // Unstable levels (core/invariants.hpp) and the bounds saturation is measured against.
  for (std::size_t k = 0; k < result.levels.size(); ++k) {
    const ConvergenceLevel& lv = result.levels[k];
    if (lv.status != "unstable") continue;
    std::ostringstream note;
    note << lv.scheme << ": level h = " << std::setprecision(3) << lv.h
         << " unstable, left out of the fit: " << measured[k].instability;
    result.notes.push_back(note.str());
  }
  for (std::size_t k = 0; k < result.levels.size(); ++k) {
    const ConvergenceLevel& lv = result.levels[k];
    if (lv.status != "off-joints") continue;
    std::ostringstream note;
    note << lv.scheme << ": level h = " << std::setprecision(3) << lv.h
         << " off its joints, left out of the fit: " << measured[k].off_joints;
    result.notes.push_back(note.str());
  }
  bool any_round_off = false;
  for (const auto& lv : result.levels) any_round_off |= lv.status == "round-off";
  if (any_round_off && measures_positions(options.metric) && model.has_constraints() &&
      degrees_of_freedom(model) == 0) {
    result.notes.push_back(
        "the joints leave the scene's bodies no degree of freedom: their positions follow from "
        "the joints and drives alone at every step, exactly for any scheme that holds the "
        "joints, so the " +
        options.metric +
        " metric measures round-off; a scheme's error is in the velocities and the reactions "
        "(--metric velocity, angular_velocity, reaction_force or reaction_torque)");
  }
  bool any_saturated = false;
  for (const auto& lv : result.levels) any_saturated |= lv.status == "saturated";
  for (std::size_t k = 0; k < result.levels.size() && any_saturated; ++k) {
    if (measured[k].bounds.empty()) continue;
    result.notes.push_back(
        "saturation is measured against the largest values of the metric's "
        "quantities: " +
        measured[k].bounds + " (trajectory/error_metrics.hpp)");
    break;
  }
  bool any_uncertified = false;
  for (const auto& lv : result.levels) any_uncertified |= lv.status == "uncertified";
  if (any_uncertified) {
    std::ostringstream note;
    note << "reference refused for the levels marked 'uncertified': their error is not 100x "
            "above the reference's estimated error "
         << ref_estimate << " (tighten --reference-rtol or use a larger --dt)";
    result.notes.push_back(note.str());
  }
  return result;
}

bool ConvergenceResult::refused() const {
  for (const SchemeSummary& s : summaries) {
    if (s.refused()) return true;
  }
  return false;
}

std::string format_convergence_table(const ConvergenceResult& r) {
  std::ostringstream out;
  const auto& est = r.reference.estimate;
  // The metric first: every error below, the reference's included, is in its unit.
  out << "metric: " << trajectory::describe_metric(r.reference.table, r.options.metric) << "\n";
  out << "reference: " << trajectory::describe_reference_run(r.reference.run)
      << ", estimated error " << trajectory::describe_estimate(est) << "\n\n";
  out << std::left << std::setw(7) << "scheme" << std::right << std::setw(12) << "h"
      << std::setw(10) << "steps" << std::setw(12) << "error" << std::setw(8) << "order"
      << std::setw(11) << "cpu [s]";
  // With ideal joints, each level's largest joint violation from its positions.
  if (r.joints) out << std::setw(12) << "violation";
  out << "  status\n";
  for (const auto& lv : r.levels) {
    out << std::left << std::setw(7) << lv.scheme << std::right << std::scientific
        << std::setprecision(3) << std::setw(12) << lv.h << std::setw(10) << lv.steps
        << std::setw(12) << std::setprecision(3) << lv.error << std::fixed << std::setprecision(2)
        << std::setw(8);
    if (std::isnan(lv.order)) {
      out << "-";
    } else {
      out << lv.order;
    }
    out << std::scientific << std::setprecision(2) << std::setw(11) << lv.cpu_seconds;
    if (r.joints) {
      out << std::setw(12);
      if (std::isnan(lv.violation)) {
        out << "-";
      } else {
        out << lv.violation;
      }
    }
    out << "  " << lv.status << "\n";
  }
  if (r.step_limit.bounded()) {
    out << "explicit step limit: " << std::scientific << std::setprecision(3) << r.step_limit.h
        << " s (2/omega of " << r.step_limit.what << ")\n";
  }
  out << "\nobserved order (least squares over the valid levels, status ok):\n";
  for (const auto& s : r.summaries) {
    out << "  " << std::left << std::setw(5) << s.scheme << std::right << " claimed ";
    if (s.claimed_order > 0) {
      out << s.claimed_order;
    } else {
      out << "-";
    }
    if (s.refused()) {
      // No order from fewer than three valid levels: the line says so, not a number.
      out << ", no order: " << s.fitted_levels << " valid level"
          << (s.fitted_levels == 1 ? "" : "s") << " (" << SchemeSummary::kMinFittedLevels
          << " needed; see the notes)\n";
      continue;
    }
    out << ", observed ";
    if (std::isnan(s.fitted_order)) {
      out << "n/a";
    } else {
      out << std::fixed << std::setprecision(2) << s.fitted_order;
    }
    out << " over " << s.fitted_levels << " levels\n";
  }
  for (const auto& n : r.notes) out << "note: " << n << "\n";
  if (r.joints) {
    out << "\njoint violations |Phi| from each level's positions (length rows m, rotation rows "
           "rad; trajectory/joint_violation.hpp):\n";
    for (const auto& lv : r.levels) {
      out << "  " << lv.scheme << " h = " << std::scientific << std::setprecision(3) << lv.h << ": "
          << (lv.joints.empty() ? "not measured" : lv.joints) << "\n";
    }
  }
  return out.str();
}

std::string convergence_csv(const ConvergenceResult& r) {
  std::ostringstream out;
  out.precision(17);
  out << "scheme,h,steps,error,order,cpu_seconds,status\n";
  for (const auto& lv : r.levels) {
    const std::string status = trajectory::csv_text(lv.status);
    // The first level has no pairwise order and a run made earlier no CPU time: empty cells.
    out << lv.scheme << ',' << lv.h << ',' << lv.steps << ',' << lv.error << ','
        << trajectory::csv_number(lv.order) << ',' << trajectory::csv_number(lv.cpu_seconds) << ','
        << status << '\n';
  }
  return out.str();
}

}  // namespace flexref::studies
