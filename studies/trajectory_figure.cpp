#include "studies/trajectory_figure.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/invariants.hpp"
#include "core/output_times.hpp"
#include "lie/method_registry.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "reference/solve_reference.hpp"
#include "studies/parallel.hpp"
#include "studies/progress.hpp"
#include "trajectory/column_layout.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::studies {

namespace {

std::string step_text(double h) {
  std::ostringstream out;
  out << h;
  return out.str();
}

FigureCurve run_scheme_curve(const core::Model& model, const std::string& scheme, double h,
                             double t0, double t_end, double output_step,
                             const FigureSettings& settings) {
  FigureCurve curve;
  curve.scheme = scheme;
  curve.step = h;
  curve.label = scheme + " h=" + step_text(h);
  // Refuses a step that double precision cannot resolve (also bounds n_steps below).
  lie::validate_step_grid(model, h, {t0, t_end});
  const auto stepper = lie::make_stepper(scheme, model, settings.method_options);
  stepper->initialize(t0, model.initial_state());
  const core::TrackedPoint& point =
      model.body(settings.body).description().points[static_cast<std::size_t>(settings.point)];
  // This loop does not integrate the dissipated work: the energy balance is monitored only on
  // a model that dissipates nothing.
  core::InvariantMonitor monitor(model, core::kInvariantTolerance, model.tracks_work());
  const auto record = [&] {
    curve.times.push_back(stepper->time());
    curve.p_W.push_back(model.p_WP(
        settings.body, stepper->state()[static_cast<std::size_t>(settings.body)], point));
    monitor.observe(stepper->time(), stepper->state(), 0.0, 0.0);
  };
  record();
  const long n_steps = std::lround((t_end - t0) / h);
  const long stride = std::max(1L, std::lround(output_step / h));
  for (long n = 0; n < n_steps; ++n) {
    const double t_n = stepper->time();
    const double t_next = t0 + static_cast<double>(n + 1) * h;
    const lie::StepStatus status = stepper->step(t_next - t_n);
    const auto& s = stepper->state()[static_cast<std::size_t>(settings.body)];
    const bool finite = s.p_WBr.allFinite() && s.theta_WB.allFinite() && s.w_WB_B.allFinite();
    if (!status.ok || !finite) {
      std::ostringstream why;
      why << "stopped at t = " << t_n << " (step " << n
          << "): " << (status.ok ? std::string("non-finite state") : status.message);
      curve.completed = false;
      curve.failure = why.str();
      break;
    }
    if ((n + 1) % stride == 0 || n + 1 == n_steps) record();
  }
  if (monitor.breach()) {
    curve.instability = monitor.breach()->describe();
    curve.label += " (unstable)";
  }
  return curve;
}

/// L∞ distance to the reference over the curve's times that are on the reference grid.
double max_distance(const FigureCurve& curve, const FigureCurve& reference, double t0,
                    double output_step) {
  double worst = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t k = 0; k < curve.times.size(); ++k) {
    const double index = (curve.times[k] - t0) / output_step;
    const long i = std::lround(index);
    if (std::abs(index - static_cast<double>(i)) > 1e-6 || i < 0 ||
        i >= static_cast<long>(reference.times.size())) {
      continue;
    }
    const double d = (curve.p_W[k] - reference.p_W[static_cast<std::size_t>(i)]).norm();
    worst = std::isnan(worst) ? d : std::max(worst, d);
  }
  return worst;
}

}  // namespace

FigureResult run_trajectory_figure(const core::Model& model,
                                   const std::vector<double>& output_times,
                                   const FigureSettings& settings) {
  if (settings.body < 0 || settings.body >= model.num_bodies()) {
    throw std::invalid_argument("figure: body index out of range");
  }
  const auto& points = model.body(settings.body).description().points;
  if (settings.point < 0 || settings.point >= static_cast<int>(points.size())) {
    throw std::invalid_argument("figure: the body has no tracked point " +
                                std::to_string(settings.point));
  }
  if (output_times.size() < 2) throw std::invalid_argument("figure: need two output times");
  const double t0 = output_times.front();
  const double t_end = output_times.back();
  const double output_step = output_times[1] - output_times[0];
  for (double h : settings.steps) {
    if (!(h > 0.0) || !core::is_multiple_of(t_end - t0, h)) {
      throw std::invalid_argument("figure: step " + step_text(h) +
                                  " does not divide the time span " + step_text(t_end - t0));
    }
  }
  lie::check_method_options(settings.method_options, settings.schemes);
  for (const std::string& s : settings.schemes) {
    (void)lie::make_stepper(s, model, settings.method_options);
  }

  FigureResult result;
  reference::SolverOptions options;
  options.rtol = settings.rtol;
  reference::ReferenceRun run;
  if (settings.given_reference) {
    run = settings.given_reference->run;
    result.reference_estimate = settings.given_reference->estimate.estimate();
    result.reference_estimate_method =
        trajectory::describe_estimate(settings.given_reference->estimate);
    result.reference_precision = settings.given_precision;
  } else {
    Progress progress("figure: reference (" + settings.solver + ")", 0, "", settings.progress);
    reference::SolveProgress solves(
        settings.estimate ? trajectory::reference_solve_count(model, settings.solver) : 1);
    options.progress = &solves;
    progress.follow(&solves);
    run = reference::solve_reference(settings.solver, model, output_times, options);
    if (settings.estimate) {
      reference::ReferenceRun reported = run;
      reported.options.progress = &solves;
      const trajectory::ReferenceEstimate estimate = trajectory::estimate_error(
          model, output_times, reported, trajectory::tabulate(model, run.trajectory), "points");
      result.reference_estimate = estimate.estimate();
      result.reference_estimate_method = trajectory::describe_estimate(estimate);
    }
  }
  result.reference.label = "reference (" + run.solver +
                           (result.reference_precision == ReferencePrecision::kDouble
                                ? std::string()
                                : std::string(" ") + to_string(result.reference_precision)) +
                           ")";
  result.reference.times = run.trajectory.times;
  const core::TrackedPoint& point = points[static_cast<std::size_t>(settings.point)];
  if (settings.given_reference) {
    // A high-precision reference carries its table (rounded to double), not double states.
    const trajectory::TrajectoryTable& table = settings.given_reference->table;
    const std::string& body = model.body(settings.body).name();
    const trajectory::ColumnLayout layout = trajectory::ColumnLayout::parse(table.columns);
    std::array<int, 3> p{};
    if (!layout.find_group(trajectory::ColumnKind::point, body, p, point.name) ||
        table.size() != output_times.size()) {
      throw std::invalid_argument(
          "figure: the given reference has no column " +
          trajectory::column_name(trajectory::ColumnKind::point, body, 0, point.name) +
          " on the output times");
    }
    result.reference.times.clear();
    for (std::size_t r = 0; r < table.size(); ++r) {
      const std::vector<double>& row = table.rows[r];
      result.reference.times.push_back(table.time(r));
      result.reference.p_W.emplace_back(row[static_cast<std::size_t>(p[0])],
                                        row[static_cast<std::size_t>(p[1])],
                                        row[static_cast<std::size_t>(p[2])]);
    }
  } else {
    for (const core::State& s : run.trajectory.states) {
      result.reference.p_W.push_back(
          model.p_WP(settings.body, s[static_cast<std::size_t>(settings.body)], point));
    }
  }

  const std::size_t n_steps = settings.steps.size();
  result.curves.resize(settings.schemes.size() * n_steps);
  Progress progress("figure", static_cast<long>(result.curves.size()), "runs", settings.progress);
  parallel_for(static_cast<int>(result.curves.size()), settings.jobs, [&](int k) {
    const auto u = static_cast<std::size_t>(k);
    FigureCurve& curve = result.curves[u];
    curve = run_scheme_curve(model, settings.schemes[u / n_steps], settings.steps[u % n_steps], t0,
                             t_end, output_step, settings);
    curve.max_error = max_distance(curve, result.reference, t0, output_step);
    // NaN estimate (not estimated): nothing to certify against; +inf: certifies nothing.
    curve.certified = !(curve.max_error < 100.0 * result.reference_estimate);
    progress.advance();
  });
  return result;
}

std::string figure_csv(const FigureResult& result) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "curve,scheme,step,t,x,y,z\n";
  const auto write = [&out](const FigureCurve& c) {
    for (std::size_t k = 0; k < c.times.size(); ++k) {
      out << c.label << ',' << c.scheme << ',' << c.step << ',' << c.times[k] << ',' << c.p_W[k].x()
          << ',' << c.p_W[k].y() << ',' << c.p_W[k].z() << '\n';
    }
  };
  write(result.reference);
  for (const FigureCurve& c : result.curves) write(c);
  return out.str();
}

bool figure_has_uncertified(const FigureResult& result) {
  return std::any_of(result.curves.begin(), result.curves.end(),
                     [](const FigureCurve& c) { return !c.certified; });
}

std::string figure_table(const FigureResult& result) {
  std::ostringstream out;
  out << result.reference.label << " in " << to_string(result.reference_precision) << " precision";
  if (std::isnan(result.reference_estimate)) {
    out << ", error not estimated\n";
  } else {
    // The tracked point's distance, as the table's errors.
    out << ", estimated error (points [m]): " << result.reference_estimate_method << "\n";
  }
  // The scheme column fits the longest name with two spaces after it ("genalpha", a user's
  // method), and is 8 wide for the paper's c1, c2 and nmb.
  int scheme_width = 8;
  for (const FigureCurve& c : result.curves) {
    scheme_width = std::max(scheme_width, static_cast<int>(c.scheme.size()) + 2);
  }
  out << std::left << std::setw(scheme_width) << "scheme" << std::setw(12) << "step [s]"
      << std::setw(16) << "max |dp| [m]" << std::setw(11) << "certified"
      << "status\n";
  for (const FigureCurve& c : result.curves) {
    std::ostringstream error;
    error << std::setprecision(3) << std::scientific << c.max_error;
    out << std::left << std::setw(scheme_width) << c.scheme << std::setw(12) << step_text(c.step)
        << std::setw(16) << error.str() << std::setw(11) << (c.certified ? "yes" : "NO")
        << (!c.completed            ? c.failure
            : c.instability.empty() ? std::string("completed")
                                    : "unstable: " + c.instability)
        << "\n";
  }
  if (figure_has_uncertified(result)) {
    out << "note: NO = the error is below 100x the reference's estimated error: an upper bound, "
           "not a measurement (--reference-precision quad; docs/precision.md)\n";
  }
  return out.str();
}

}  // namespace flexref::studies
