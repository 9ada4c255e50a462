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

Solved solve_coupled(const scene::SceneSpec& spec, const CycleJumpOptions& o, double rtol,
                     reference::SolveProgress* solves) {
  const double start = thread_cpu_seconds();
  const core::Model model = scene::build_model(spec, o.formulation);
  std::vector<double> times;
  const int n = std::max(1, static_cast<int>(std::ceil(o.until / o.output_step - 1e-9)));
  for (int k = 0; k <= n; ++k) times.push_back(k == n ? o.until : o.until * k / n);
  reference::SolverOptions options;
  options.rtol = rtol;
  options.progress = solves;
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
  {
    // One after the other, they report to one SolveProgress; side by side, the line follows
    // the check, the longer of the two (its tolerance is tighter).
    const int jobs = std::min(2, std::max(1, options.jobs));
    reference::SolveProgress sequential(2);
    reference::SolveProgress side(1);
    Progress progress("wear-jump: the coupled reference and its check", 0, "", options.progress);
    progress.follow(jobs == 1 ? &sequential : &side);
    parallel_for(2, jobs, [&](int i) {
      if (i == 0) {
        reference =
            solve_coupled(spec, options.base, options.base.rtol, jobs == 1 ? &sequential : nullptr);
      } else {
        check = solve_coupled(spec, options.base, options.base.rtol / options.estimate_factor,
                              jobs == 1 ? &sequential : &side);
      }
    });
  }
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
  Progress progress("wear-jump", static_cast<long>(tasks.size()), "runs", options.progress);
  std::vector<WearJumpRow> rows(tasks.size());
  std::vector<std::vector<std::string>> regimes(tasks.size());
  std::vector<std::string> instabilities(tasks.size());
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
      instabilities[static_cast<std::size_t>(i)] = run.slow_instability;
      if (row.error < kResolved * result.reference_estimate) row.status = "unresolved";
      if (!run.regime_changes.empty()) row.status = "regime-change";
      // The instability first: an overshooting geometry also changes the regime.
      if (!run.slow_instability.empty()) row.status = "unstable";
    } catch (const core::SolverError& e) {
      row.status = std::string("failed: ") + e.what();
    } catch (const std::invalid_argument& e) {
      row.status = std::string("failed: ") + e.what();
    }
    progress.advance();
  });
  progress.finish();
  result.rows = rows;

  // Orders, per integrator and window: from the distances between successive `ok` levels
  // (coarsest first: the counts are sorted) and from the errors against the reference.
  const double max_reference = result.reference_depth.cwiseAbs().maxCoeff();
  for (const SlowIntegrator slow : options.slow) {
    for (const double w : windows) {
      WearJumpFit fit;
      fit.slow = to_string(slow);
      fit.claimed = claimed_order(slow);
      fit.window = w;
      // The levels that measure the integrator: stable, no regime change (an `unresolved`
      // level is within the reference's error of it, which the distances do not involve).
      std::vector<const WearJumpRow*> chain;
      std::vector<const WearJumpRow*> ok;
      for (const WearJumpRow& r : result.rows) {
        if (r.slow != fit.slow || r.window != w) continue;
        if (r.status == "ok" || r.status == "unresolved") chain.push_back(&r);
        if (r.status == "ok") ok.push_back(&r);
      }
      std::vector<LevelDistance> used;
      std::set<int> joined;
      for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
        const double d =
            (chain[i]->depth - chain[i + 1]->depth).cwiseAbs().maxCoeff() / max_reference;
        fit.distances.push_back({chain[i]->jump, chain[i + 1]->jump, d});
        const bool resolved = std::isfinite(d) && d >= kResolved * result.reference_estimate;
        fit.distance_used.push_back(resolved);
        if (!resolved) continue;
        used.push_back(fit.distances.back());
        joined.insert(chain[i]->jumps);
        joined.insert(chain[i + 1]->jumps);
      }
      fit.observed =
          used.size() >= 3 ? distance_order(used) : std::numeric_limits<double>::quiet_NaN();
      fit.levels = static_cast<int>(joined.size());
      if (std::isfinite(fit.observed)) {
        // u* ≈ u_f + (u_f − u_c) / ((D_c/D_f)^p − 1) from the finest distance used.
        const LevelDistance& last = used.back();
        const WearJumpRow* coarse = nullptr;
        const WearJumpRow* fine = nullptr;
        for (const WearJumpRow* r : chain) {
          if (r->jump == last.coarse) coarse = r;
          if (r->jump == last.fine) fine = r;
        }
        const double factor = std::pow(last.coarse / last.fine, fit.observed) - 1.0;
        const Eigen::VectorXd limit = fine->depth + (fine->depth - coarse->depth) / factor;
        fit.limit_error = profile_error(limit, result.reference_depth);
      } else {
        fit.limit_error = std::numeric_limits<double>::quiet_NaN();
      }
      std::vector<double> steps, errors;
      std::vector<bool> use;
      for (const WearJumpRow* r : ok) {
        steps.push_back(r->jump);
        errors.push_back(r->error);
        use.push_back(std::isfinite(r->error) && r->error > 0.0);
        fit.reference_levels += use.back() ? 1 : 0;
      }
      fit.observed_reference = fit.reference_levels >= 3 ? least_squares_order(steps, errors, use)
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
    if (!instabilities[i].empty()) {
      result.notes.push_back("breakdown: " + r.slow + " D = " + number(r.jump) + " s, window " +
                             number(r.window) + " s: unstable in slow time, " + instabilities[i]);
    }
  }
  for (const WearJumpFit& f : result.fits) {
    for (std::size_t i = 0; i < f.distances.size(); ++i) {
      if (f.distance_used[i]) continue;
      result.notes.push_back(f.slow + " D = " + number(f.distances[i].coarse) + " -> " +
                             number(f.distances[i].fine) + " s: the profiles' distance " +
                             number(f.distances[i].distance) +
                             " is not 10x above the reference's estimate: left out of the order");
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

std::string wear_jump_distances_csv(const WearJumpResult& result) {
  std::ostringstream out;
  out << std::setprecision(10);
  out << "slow,window,coarse,fine,distance,used,limit_error\n";
  for (const WearJumpFit& f : result.fits) {
    for (std::size_t i = 0; i < f.distances.size(); ++i) {
      const LevelDistance& d = f.distances[i];
      out << f.slow << ',' << f.window << ',' << d.coarse << ',' << d.fine << ',' << d.distance
          << ',' << (f.distance_used[i] ? 1 : 0) << ',';
      if (std::isfinite(f.limit_error)) out << f.limit_error;
      out << '\n';
    }
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
  const bool several_windows = result.fits.size() > result.options.slow.size();
  const auto label = [&](const WearJumpFit& f) {
    return f.slow + (several_windows ? " (window " + number(f.window) + " s)" : std::string());
  };
  const auto order = [](double p) {
    std::ostringstream o;
    if (std::isfinite(p)) {
      o << std::fixed << std::setprecision(2) << p;
    } else {
      o << "-";
    }
    return o.str();
  };
  for (const WearJumpFit& f : result.fits) {
    // Against the reference: the least-squares slope and the pairwise orders of the errors.
    std::vector<double> steps, errors;
    for (const WearJumpRow& r : result.rows) {
      if (r.slow != f.slow || r.window != f.window || r.status != "ok") continue;
      steps.push_back(r.jump);
      errors.push_back(r.error);
    }
    if (steps.size() >= 2) {
      out << "note: " << label(f) << " against the reference: order " << order(f.observed_reference)
          << " over " << f.reference_levels
          << " levels, pairwise from D = " << number(steps.front()) << " s:";
      for (const double p : pairwise_orders(steps, errors)) out << " " << number(p);
      out << "\n";
    }
    // Between levels: each distance, and the order of each two successive ones.
    if (!f.distances.empty()) {
      out << "note: " << label(f) << " distances between successive levels:";
      for (const LevelDistance& d : f.distances) {
        out << " " << number(d.coarse) << "->" << number(d.fine) << " s " << number(d.distance);
      }
      if (f.distances.size() >= 2) out << "; pairwise orders:";
      for (std::size_t i = 0; i + 1 < f.distances.size(); ++i) {
        out << " " << number(distance_order({f.distances[i], f.distances[i + 1]}));
      }
      out << "\n";
    }
    if (std::isfinite(f.limit_error)) {
      out << "note: " << label(f) << " limit D -> 0 (Richardson at the observed order) is "
          << number(f.limit_error)
          << " from the reference: the averaging error, which no smaller jump removes\n";
    }
  }
  out << "observed slow-time order (from the distances between the final profiles of "
         "successive levels: stable, no regime change, distance resolved):\n";
  for (const WearJumpFit& f : result.fits) {
    out << "  " << f.slow << " claimed " << f.claimed << ", observed " << order(f.observed)
        << " over " << f.levels << " levels";
    if (several_windows) out << " (window " << number(f.window) << " s)";
    out << "\n";
  }
  return out.str();
}

}  // namespace flexref::studies
