#include "studies/wear_jump.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "reference/solve_reference.hpp"
#include "scene/build_model.hpp"
#include "studies/observed_order.hpp"
#include "studies/parallel.hpp"
#include "studies/progress.hpp"

namespace flexref::studies {
namespace {

/// An error at least this many times the reference's estimate measures the scheme.
constexpr double kResolved = 10.0;

struct Solved {
  Eigen::VectorXd depth;
  double cpu = 0.0;
  long steps = 0;
  std::vector<double> times;
  std::vector<double> max_depth;
};

Solved solve_coupled(const scene::SceneSpec& spec, const CycleJumpOptions& o, double rtol) {
  const double start = thread_cpu_seconds();
  const core::Model model = scene::build_model(spec, o.formulation);
  std::vector<double> times;
  const int n = std::max(1, static_cast<int>(std::ceil(o.until / o.output_step - 1e-9)));
  for (int k = 0; k <= n; ++k) times.push_back(k == n ? o.until : o.until * k / n);
  reference::SolverOptions options;
  options.rtol = rtol;
  const reference::ReferenceRun run = reference::solve_reference(o.solver, model, times, options);
  Solved s;
  s.cpu = thread_cpu_seconds() - start;
  s.steps = run.stats.steps;
  s.depth = run.trajectory.states.back().wear_depth;
  s.times = times;
  for (const core::State& state : run.trajectory.states) {
    s.max_depth.push_back(state.wear_depth.size() > 0 ? state.wear_depth.maxCoeff() : 0.0);
  }
  return s;
}

std::string number(double x, int precision = 3) {
  std::ostringstream out;
  out << std::setprecision(precision) << x;
  return out.str();
}

}  // namespace

double profile_error(const Eigen::VectorXd& depth, const Eigen::VectorXd& reference) {
  const double scale = reference.size() > 0 ? reference.cwiseAbs().maxCoeff() : 0.0;
  if (!(scale > 0.0)) return std::numeric_limits<double>::infinity();
  return (depth - reference).cwiseAbs().maxCoeff() / scale;
}

WearJumpResult run_wear_jump(const scene::SceneSpec& spec, const WearJumpOptions& options) {
  if (options.slow.empty() || options.jump_counts.empty()) {
    throw std::invalid_argument("wear-jump: no slow-time integrator or no jump");
  }
  for (const int n : options.jump_counts) {
    if (n < 1) throw std::invalid_argument("wear-jump: a jump count must be >= 1");
  }
  if (!(options.estimate_factor > 1.0)) {
    throw std::invalid_argument("wear-jump: the estimate factor must be > 1");
  }
  WearJumpResult result;
  result.options = options;
  std::vector<double> windows = options.windows;
  if (windows.empty()) windows.push_back(options.base.window);
  std::vector<int> counts = options.jump_counts;
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());

  // The runs: every integrator, window and jump.
  struct Task {
    SlowIntegrator slow;
    double window;
    int jumps;
  };
  std::vector<Task> tasks;
  for (const SlowIntegrator s : options.slow) {
    for (const double w : windows) {
      for (const int n : counts) tasks.push_back({s, w, n});
    }
  }
  Progress progress("wear-jump", static_cast<long>(tasks.size()) + 2, "runs", options.progress);

  // The fully coupled reference and its check.
  {
    // The depth layout (no dynamics: a scene without a wear law is refused here).
    const core::Model model = scene::build_model(spec, options.base.formulation);
    if (model.wear_depth_count() == 0) {
      throw std::invalid_argument("wear-jump: the scene has no contact with a wear law");
    }
    for (int c = 0; c < model.wear_channel_count(); ++c) {
      if (model.channel_depth_count(c) == 0) continue;
      result.layout.channels.push_back(model.wear_channel_names()[static_cast<std::size_t>(c)]);
      result.layout.channel_first.push_back(model.channel_depth_first(c));
      result.layout.channel_count.push_back(model.channel_depth_count(c));
      result.layout.channel_sectors.push_back(model.channel_wear_law(c)->sectors);
    }
    result.layout.depth_areas = model.wear_depth_areas();
  }
  Solved reference;
  Solved check;
  parallel_for(2, std::min(2, std::max(1, options.jobs)), [&](int i) {
    if (i == 0) {
      reference = solve_coupled(spec, options.base, options.base.rtol);
    } else {
      check = solve_coupled(spec, options.base, options.base.rtol / options.estimate_factor);
    }
    progress.advance();
  });
  result.reference_depth = reference.depth;
  result.reference_cpu = reference.cpu;
  result.reference_steps = reference.steps;
  result.reference_times = reference.times;
  result.reference_max_depth = reference.max_depth;
  result.reference_estimate = profile_error(reference.depth, check.depth);
  if (!(reference.depth.maxCoeff() > 0.0)) {
    throw std::invalid_argument(
        "wear-jump: the reference wears nothing over the slow time (no contact, or a zero "
        "rate): nothing to compare");
  }

  // The multi-scale runs.
  std::vector<WearJumpRow> rows(tasks.size());
  std::vector<std::vector<std::string>> regimes(tasks.size());
  parallel_for(static_cast<int>(tasks.size()), options.jobs, [&](int i) {
    const Task& task = tasks[static_cast<std::size_t>(i)];
    WearJumpRow& row = rows[static_cast<std::size_t>(i)];
    row.slow = to_string(task.slow);
    row.jumps = task.jumps;
    row.jump = options.base.until / task.jumps;
    row.window = task.window;
    CycleJumpOptions o = options.base;
    o.slow = task.slow;
    o.window = task.window;
    o.jump = row.jump;
    o.on_window = nullptr;
    try {
      const CycleJumpResult run = run_cycle_jump(spec, o);
      row.depth = run.path.back().depth;
      row.error = profile_error(row.depth, reference.depth);
      row.cpu = run.cpu_seconds;
      row.speedup = run.cpu_seconds > 0.0 ? reference.cpu / run.cpu_seconds : 0.0;
      row.window_count = static_cast<int>(run.windows.size());
      row.fast_time = run.fast_time;
      regimes[static_cast<std::size_t>(i)] = run.regime_changes;
      if (row.error < kResolved * result.reference_estimate) row.status = "unresolved";
      if (!run.regime_changes.empty()) row.status = "regime-change";
    } catch (const core::SolverError& e) {
      row.status = std::string("failed: ") + e.what();
    } catch (const std::invalid_argument& e) {
      row.status = std::string("failed: ") + e.what();
    }
    progress.advance();
  });
  progress.finish();
  result.rows = rows;

  // Orders, per integrator and window, over the resolved levels.
  for (const SlowIntegrator s : options.slow) {
    for (const double w : windows) {
      WearJumpFit fit;
      fit.slow = to_string(s);
      fit.claimed = claimed_order(s);
      fit.window = w;
      std::vector<double> steps, errors;
      std::vector<bool> use;
      for (const WearJumpRow& r : result.rows) {
        if (r.slow != fit.slow || r.window != w) continue;
        steps.push_back(r.jump);
        errors.push_back(r.error);
        const bool ok = r.status == "ok" && std::isfinite(r.error) && r.error > 0.0;
        use.push_back(ok);
        fit.levels += ok ? 1 : 0;
      }
      fit.observed = fit.levels >= 3 ? least_squares_order(steps, errors, use)
                                     : std::numeric_limits<double>::quiet_NaN();
      result.fits.push_back(fit);
    }
  }

  // Notes: the reference, the unresolved levels and the breakdown map.
  result.notes.push_back("reference: " + options.base.solver + " rtol " +
                         number(options.base.rtol) + ", the depths integrated with the dynamics; " +
                         "estimated error " + number(result.reference_estimate) +
                         " (the distance to rtol " +
                         number(options.base.rtol / options.estimate_factor) + "), CPU " +
                         number(reference.cpu) + " s");
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    const WearJumpRow& r = result.rows[i];
    if (r.status == "unresolved") {
      result.notes.push_back(r.slow + " D = " + number(r.jump) + " s: error " + number(r.error) +
                             " is not 10x above the reference's estimate: left out of the fit");
    }
    for (const std::string& change : regimes[i]) {
      result.notes.push_back("breakdown: " + r.slow + " D = " + number(r.jump) + " s, window " +
                             number(r.window) + " s: the contact regime changes inside " + change);
    }
  }
  return result;
}

std::string wear_jump_csv(const WearJumpResult& result) {
  std::ostringstream out;
  out << std::setprecision(10);
  out << "slow,jump,window,error,cpu,speedup,status\n";
  for (const WearJumpRow& r : result.rows) {
    std::string status = r.status;
    for (char& c : status) {
      if (c == ',' || c == '\n') c = ';';
    }
    out << r.slow << ',' << r.jump << ',' << r.window << ',' << r.error << ',' << r.cpu << ','
        << r.speedup << ',' << status << '\n';
  }
  return out.str();
}

std::string format_wear_jump(const WearJumpResult& result) {
  std::ostringstream out;
  out << "wear-jump: final worn profile of the multi-scale scheme against the fully coupled "
         "reference\n";
  out << "  (error = max |h - h_ref| / max h_ref at the slow time " << result.options.base.until
      << " s; reference max depth " << number(result.reference_depth.maxCoeff()) << " m, CPU "
      << number(result.reference_cpu) << " s)\n";
  out << std::left << std::setw(7) << "slow" << std::setw(7) << "jumps" << std::setw(11)
      << "jump [s]" << std::setw(11) << "window [s]" << std::setw(12) << "error" << std::setw(11)
      << "CPU [s]" << std::setw(10) << "speed-up"
      << "status\n";
  for (const WearJumpRow& r : result.rows) {
    out << std::left << std::setw(7) << r.slow << std::setw(7) << r.jumps << std::setw(11)
        << number(r.jump) << std::setw(11) << number(r.window) << std::setw(12) << number(r.error)
        << std::setw(11) << number(r.cpu) << std::setw(10) << number(r.speedup) << r.status << "\n";
  }
  for (const std::string& note : result.notes) out << "note: " << note << "\n";
  // Pairwise orders between consecutive `ok` levels, to read the fit below (where a ladder
  // mixes a pre-asymptotic level with a floor, the pairs show it).
  for (const WearJumpFit& f : result.fits) {
    std::vector<double> steps, errors;
    for (const WearJumpRow& r : result.rows) {
      if (r.slow != f.slow || r.window != f.window || r.status != "ok") continue;
      steps.push_back(r.jump);
      errors.push_back(r.error);
    }
    if (steps.size() < 2) continue;
    out << "note: " << f.slow << " pairwise orders from D = " << number(steps.front()) << " s:";
    for (const double p : pairwise_orders(steps, errors)) out << " " << number(p);
    out << "\n";
  }
  out << "observed slow-time order (least squares over the levels `ok`: resolved, no regime change "
         "inside a jump):\n";
  const bool several_windows = result.fits.size() > result.options.slow.size();
  for (const WearJumpFit& f : result.fits) {
    out << "  " << f.slow << " claimed " << f.claimed << ", observed ";
    if (std::isfinite(f.observed)) {
      out << std::fixed << std::setprecision(2) << f.observed << std::defaultfloat;
    } else {
      out << "-";
    }
    out << " over " << f.levels << " levels";
    if (several_windows) out << " (window " << number(f.window) << " s)";
    out << "\n";
  }
  return out.str();
}

}  // namespace flexref::studies
