#include "studies/convergence.hpp"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <sstream>

#include "core/error.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "studies/distribution.hpp"
#include "studies/error_metrics.hpp"
#include "studies/observed_order.hpp"
#include "studies/parallel.hpp"

namespace flexref::studies {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// An error below this is at the level of accumulated round-off for the step counts studies
// use (10³–10⁷ steps: √N·ε·|state| ≈ 1e-14…1e-12 for O(1) states, with the constant of the
// error propagation of unstable motions such as the book toss on top); refining further
// measures round-off, not the scheme.
constexpr double kRoundOffFloor = 1e-11;

SlotCodec level_codec(std::vector<ConvergenceLevel>& levels) {
  require_codec_size<ConvergenceLevel, 104>();
  const auto fields = [](auto& io, auto& l) {
    io(l.scheme, l.h, l.steps, l.error, l.order, l.cpu_seconds, l.status);
  };
  return {[&levels, fields](int i, SlotWriter& w) {
            auto put = [&w](const auto&... x) { (w.put(x), ...); };
            fields(put, levels[static_cast<std::size_t>(i)]);
          },
          [&levels, fields](int i, SlotReader& r) {
            auto get = [&r](auto&... x) { (r.get(x), ...); };
            fields(get, levels[static_cast<std::size_t>(i)]);
          }};
}

}  // namespace

ConvergenceResult run_convergence(const core::Model& model, const std::vector<double>& output_times,
                                  const ConvergenceOptions& options) {
  if (!(options.h0 > 0.0)) throw std::invalid_argument("--dt must be positive");
  if (options.levels < 2) throw std::invalid_argument("--levels must be at least 2");
  ConvergenceResult result;
  result.options = options;

  reference::SolverOptions ref_options;
  ref_options.rtol = options.reference_rtol;
  const std::string solver =
      resolve_reference_solver(options.reference_solver, model, output_times);
  if (options.progress) std::fprintf(stderr, "converge: reference (%s) ...\n", solver.c_str());
  result.reference = certified_reference(model, output_times, solver, ref_options, options.metric);

  const int n_schemes = static_cast<int>(options.schemes.size());
  const int n_runs = n_schemes * options.levels;
  result.levels.resize(static_cast<std::size_t>(n_runs));
  ProgressLine progress("converge", "runs", options.progress);
  const auto task = [&](int k) {
    const std::string& scheme = options.schemes[static_cast<std::size_t>(k / options.levels)];
    const int level = k % options.levels;
    ConvergenceLevel& out = result.levels[static_cast<std::size_t>(k)];
    out.scheme = scheme;
    out.h = options.h0 / std::ldexp(1.0, level);
    const double t_span = output_times.back() - output_times.front();
    out.steps = std::lround(t_span / out.h);
    try {
      auto stepper = lie::make_stepper(scheme, model);
      const double start = thread_cpu_seconds();
      const core::Trajectory trajectory = lie::run_scheme(model, *stepper, out.h, output_times);
      out.cpu_seconds = thread_cpu_seconds() - start;
      out.error =
          metric_value(compare_trajectories(tabulate(model, trajectory), result.reference.table),
                       options.metric);
      out.status = std::isfinite(out.error) ? "ok" : "failed: non-finite error";
    } catch (const std::exception& e) {
      out.error = std::numeric_limits<double>::infinity();
      out.status = std::string("failed: ") + e.what();
    }
  };
  distributed_for(n_runs, options.jobs, task, level_codec(result.levels), progress.callback());
  progress.finish();

  const double ref_estimate = result.reference.estimate.estimate();
  for (int s = 0; s < n_schemes; ++s) {
    const auto first = static_cast<std::size_t>(s * options.levels);
    std::vector<double> steps, errors;
    std::vector<bool> use;
    bool stopped = false;
    for (int l = 0; l < options.levels; ++l) {
      ConvergenceLevel& lv = result.levels[first + static_cast<std::size_t>(l)];
      steps.push_back(lv.h);
      errors.push_back(lv.error);
      if (stopped) {
        lv.status = "round-off";
      } else if (lv.status == "ok" && lv.error <= kRoundOffFloor) {
        lv.status = "round-off";
        stopped = true;
        std::ostringstream note;
        note << lv.scheme << ": refinement stopped at h = " << lv.h << ": error " << lv.error
             << " is at round-off level (<= " << kRoundOffFloor << ")";
        result.notes.push_back(note.str());
      } else if (lv.status == "ok" && lv.error < 100.0 * ref_estimate) {
        lv.status = "uncertified";
      }
      use.push_back(lv.status == "ok");
    }
    const std::vector<double> p = pairwise_orders(steps, errors);
    for (int l = 0; l < options.levels; ++l) {
      result.levels[first + static_cast<std::size_t>(l)].order =
          l == 0 ? kNaN : p[static_cast<std::size_t>(l - 1)];
    }
    SchemeSummary summary;
    summary.scheme = options.schemes[static_cast<std::size_t>(s)];
    summary.claimed_order = lie::make_stepper(summary.scheme, model)->order();
    summary.fitted_order = least_squares_order(steps, errors, use);
    for (bool u : use) summary.fitted_levels += u ? 1 : 0;
    // Asymptotic range: the last two pairwise orders of the fitted levels must agree to 0.3
    // (a second-order scheme with an O(h³) term still visible drifts by more than that).
    std::vector<double> fitted_orders;
    for (int l = 1; l < options.levels; ++l) {
      const auto k = static_cast<std::size_t>(l);
      if (use[k] && use[k - 1]) fitted_orders.push_back(p[k - 1]);
    }
    const std::size_t m = fitted_orders.size();
    if (m >= 2 && std::abs(fitted_orders[m - 1] - fitted_orders[m - 2]) > 0.3) {
      std::ostringstream note;
      note << std::fixed << std::setprecision(2) << summary.scheme
           << ": the pairwise orders are still changing (" << fitted_orders[m - 2] << ", "
           << fitted_orders[m - 1]
           << "): the finest levels are not yet in the asymptotic range; refine further "
              "(more --levels) before trusting the fitted order";
      result.notes.push_back(note.str());
    }
    result.summaries.push_back(summary);
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

std::string format_convergence_table(const ConvergenceResult& r) {
  std::ostringstream out;
  const auto& est = r.reference.estimate;
  out << "reference: " << r.reference.run.solver << " rtol " << r.reference.run.options.rtol
      << ", estimated error " << describe_estimate(est) << "\n";
  out << "metric: " << r.options.metric << "\n\n";
  out << std::left << std::setw(7) << "scheme" << std::right << std::setw(12) << "h"
      << std::setw(10) << "steps" << std::setw(12) << "error" << std::setw(8) << "order"
      << std::setw(11) << "cpu [s]"
      << "  status\n";
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
    out << std::scientific << std::setprecision(2) << std::setw(11) << lv.cpu_seconds << "  "
        << lv.status << "\n";
  }
  out << "\nobserved order (least squares over certified levels):\n";
  for (const auto& s : r.summaries) {
    out << "  " << std::left << std::setw(5) << s.scheme << std::right << " claimed "
        << s.claimed_order << ", observed ";
    if (std::isnan(s.fitted_order)) {
      out << "n/a";
    } else {
      out << std::fixed << std::setprecision(2) << s.fitted_order;
    }
    out << " over " << s.fitted_levels << " levels\n";
  }
  for (const auto& n : r.notes) out << "note: " << n << "\n";
  return out.str();
}

std::string convergence_csv(const ConvergenceResult& r) {
  std::ostringstream out;
  out.precision(17);
  out << "scheme,h,steps,error,order,cpu_seconds,status\n";
  for (const auto& lv : r.levels) {
    std::string status = lv.status;
    for (char& c : status) {
      if (c == ',' || c == '\n') c = ';';
    }
    out << lv.scheme << ',' << lv.h << ',' << lv.steps << ',' << lv.error << ',' << lv.order << ','
        << lv.cpu_seconds << ',' << status << '\n';
  }
  return out.str();
}

}  // namespace flexref::studies
