#include "precision/high_precision_reference.hpp"

#include <algorithm>
#include <boost/multiprecision/float128.hpp>
#include <boost/numeric/odeint/integrate/integrate_times.hpp>
#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/joint_check.hpp"
#include "precision/ode_system.hpp"
#include "precision/parse_text.hpp"
#include "precision/precise_comparison.hpp"
#include "precision/roundoff_scale.hpp"
#include "precision/switched_integration.hpp"
#include "reference/method_choice.hpp"
#include "trajectory/error_metrics.hpp"

// Boost 1.74's odeint cannot deduce the value type of a multiprecision number for its
// controlled steppers; this is the specialisation its documentation gives for such types.
namespace boost::numeric::odeint::detail {
template <>
struct extract_value_type<boost::multiprecision::float128, void> {
  typedef boost::multiprecision::float128 type;
};
}  // namespace boost::numeric::odeint::detail

namespace flexref::precision {
namespace {

using Quad = boost::multiprecision::float128;

template <typename S>
bool finite(const S& x) {
  using boost::multiprecision::isfinite;
  using std::isfinite;
  return static_cast<bool>(isfinite(x));
}

/// The model as integrate_switched sees it, with `check(t)` every 64th evaluation (the
/// evaluations of its steps and of its event location alike): one clock read, ~20 ns, per 64
/// evaluations of ≥ 1 µs each.
template <typename Model, typename Check>
class CheckedModel {
 public:
  CheckedModel(const Model& model, const Check& check) : model_(model), check_(check) {}
  int switching_function_count() const { return model_.switching_function_count(); }
  template <typename S>
  void switching_functions(S t, const std::vector<S>& y, std::vector<S>& values) const {
    model_.switching_functions(t, y, values);
  }
  template <typename S>
  void derivative(const std::vector<S>& y, std::vector<S>& dydt, S t, double t_segment,
                  std::vector<S>* switching = nullptr) const {
    if (++evaluations_ % 64 == 0) check_(static_cast<double>(t));
    model_.derivative(y, dydt, t, t_segment, switching);
  }

 private:
  const Model& model_;
  const Check& check_;
  mutable long evaluations_ = 0;
};

/// `subdivisions` > 1 adds that many − 1 equally spaced stops (not written) inside every output
/// interval: no step is longer than 1/subdivisions of it (a second step sequence for the error
/// estimate when the first one took whole output intervals at the highest order).
template <typename S, typename Model>
HighPrecisionRun integrate_model(const Model& model, std::chrono::steady_clock::time_point start,
                                 const std::vector<double>& output_times, Precision precision,
                                 double rtol, const char* type_name, int subdivisions,
                                 const Budget& budget) {
  namespace odeint = boost::numeric::odeint;
  using State = std::vector<S>;
  HighPrecisionRun run;
  run.precision = precision;
  run.rtol = rtol;
  run.method = std::string("bulirsch-stoer (odeint), ") + type_name;
  run.columns = model.columns();
  run.table.columns = run.columns;
  const int digits = significant_digits(precision);
  RateWindow window(output_times.front());
  if (budget.progress != nullptr) {
    budget.progress->start_solve(output_times.front(), output_times.back());
  }
  const auto within_budget = [&](double t) {
    if (budget.progress != nullptr) budget.progress->reached(t);
    if (!(budget.seconds > 0.0)) return;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    check_budget(budget, window, elapsed, t, output_times.back(), precision);
  };

  State y = model.initial_state();
  std::vector<double> impacts(static_cast<std::size_t>(model.wear_channel_count()), 0.0);
  // The joints at every output, the rows set aside as redundant included (core/joint_check.hpp:
  // the same bound in the run's precision, its floor the round-off of S).
  const double joint_bound = std::max(core::kJointDriftFactor * rtol,
                                      1e4 * static_cast<double>(std::numeric_limits<S>::epsilon()));
  const auto record = [&](double t, const State& x) {
    if (model.has_constraints()) {
      const core::RelativeJointViolationTpl<S> v = model.relative_joint_violation(S(t), x);
      const bool position = !(v.position <= S(joint_bound));
      if (position || !(v.velocity <= S(joint_bound))) {
        const core::ConstraintEquationsTpl<S>& joints = *model.model().constraints();
        const int joint = joints.joint_of_row(position ? v.position_row : v.velocity_row);
        std::ostringstream out;
        out.precision(3);
        out << "joint '" << joints.joint_name(joint) << "' is violated "
            << (position ? "" : "in velocity ") << "by "
            << static_cast<double>(position ? v.position : v.velocity)
            << " (relative), more than the bound " << joint_bound
            << " its tolerance allows: the rows set aside as redundant at t = 0 are not "
               "enforced, or the joints cannot all hold together";
        throw core::SolverError("odeint-" + std::string(to_string(precision)), t, -1, out.str());
      }
    }
    const std::vector<S> row = model.output_row(S(t), x, impacts);
    if (row.size() + 1 != run.columns.size()) {
      throw std::logic_error("solve_high_precision: a row of " + std::to_string(row.size() + 1) +
                             " values for " + std::to_string(run.columns.size()) + " columns");
    }
    std::vector<std::string> text;
    std::vector<double> values{t};
    for (const S& v : row) {
      if (!finite(v)) {
        throw core::SolverError(
            "odeint-" + std::string(to_string(precision)), t, -1,
            "a non-finite value in the " + std::string(to_string(precision)) + "-precision state");
      }
      text.push_back(detail::print(v, digits));
      values.push_back(static_cast<double>(v));
    }
    run.text.push_back(std::move(text));
    run.table.rows.push_back(std::move(values));
    within_budget(t);
  };
  record(output_times.front(), y);

  // Segments between load switches: no step straddles one, and the branch of every
  // evaluation inside a segment is that segment's (t_segment = its midpoint).
  std::vector<double> bounds{output_times.front()};
  for (double d : model.discontinuities()) {
    if (d > output_times.front() && d < output_times.back()) bounds.push_back(d);
  }
  bounds.push_back(output_times.back());
  std::size_t next_output = 1;
  const S tol(rtol);
  const double first_step = output_times.size() > 1 ? output_times[1] - output_times[0]
                                                    : output_times.back() - output_times.front();
  for (std::size_t s = 0; s + 1 < bounds.size(); ++s) {
    const double a = bounds[s];
    const double b = bounds[s + 1];
    if (!(b > a)) continue;
    std::vector<S> times{S(a)};
    std::vector<bool> is_output{false};
    const auto add_stop = [&](double t, bool output) {
      const double previous = static_cast<double>(times.back());
      for (int j = 1; j < subdivisions; ++j) {
        times.emplace_back(previous + (t - previous) * j / subdivisions);
        is_output.push_back(false);
      }
      times.emplace_back(t);
      is_output.push_back(output);
    };
    while (next_output < output_times.size() && output_times[next_output] < b) {
      add_stop(output_times[next_output], true);
      ++next_output;
    }
    const bool b_is_output = next_output < output_times.size() && output_times[next_output] == b;
    add_stop(b, b_is_output);
    if (b_is_output) ++next_output;
    const double t_segment = 0.5 * (a + b);
    const S step0(std::min(first_step, b - a));
    if (model.switching_function_count() > 0) {
      // Contacts: no step straddles a switch (switched_integration.hpp).
      detail::SwitchedCounters counters;
      const std::vector<S> stops(times.begin() + 1, times.end());
      detail::integrate_switched(
          CheckedModel(model, within_budget), y, a, stops, t_segment, tol, step0,
          "odeint-" + std::string(to_string(precision)), counters,
          [&](std::size_t k, const State& x) {
            if (is_output[k + 1]) record(static_cast<double>(times[k + 1]), x);
          },
          [&](const detail::SwitchEvent<S>& e, const State& x) {
            HighPrecisionEvent event;
            event.time = detail::print(e.t, digits);
            event.pair = e.function / 2;
            event.kind = e.function % 2 == 0 ? (e.to_negative ? "onset" : "release")
                                             : (e.to_negative ? "clamp" : "unclamp");
            // An impact is an onset (core/impact_counter.hpp), counted at the event itself.
            const int channel = model.wear_channel_of_pair(event.pair);
            if (event.kind == "onset" && channel >= 0) ++impacts[static_cast<std::size_t>(channel)];
            for (const S& v : model.output_row(e.t, x, impacts))
              event.row.push_back(detail::print(v, digits));
            run.events.push_back(std::move(event));
            within_budget(static_cast<double>(e.t));
          });
      run.steps += counters.steps;
      run.evaluations += counters.evaluations + counters.located_evaluations;
      continue;
    }
    odeint::bulirsch_stoer<State, S> stepper(tol, tol);
    std::size_t k = 0;
    const auto system = [&](const State& x, State& dxdt, const S t) {
      // One clock read (~20 ns) per 64 evaluations of ≥ 1 µs each.
      if (++run.evaluations % 64 == 0) within_budget(static_cast<double>(t));
      model.derivative(x, dxdt, t, t_segment);
    };
    const auto observer = [&](const State& x, const S& /*t*/) {
      if (is_output[k]) record(static_cast<double>(times[k]), x);
      ++k;
    };
    try {
      run.steps += static_cast<long>(
          odeint::integrate_times(stepper, system, y, times.begin(), times.end(), step0, observer));
    } catch (const odeint::step_adjustment_error& e) {
      throw core::SolverError("odeint-" + std::string(to_string(precision)), a, run.steps,
                              std::string("Bulirsch-Stoer cannot reach rtol ") +
                                  detail::print(rtol, 3) + ": " + e.what());
    }
  }
  run.cpu_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

template <typename S>
HighPrecisionRun integrate(const scene::SceneSpec& spec, core::FlexibleFormulation formulation,
                           const std::vector<double>& output_times, Precision precision,
                           double rtol, const char* type_name, int subdivisions,
                           const Budget& budget) {
  // The run's wall time (cpu_seconds, and the budget's clock) includes building the model:
  // forming a many-mode body's invariants in quad is part of its cost.
  const auto start = std::chrono::steady_clock::now();
  // Ideal joints: Baumgarte's rate from the output spacing, as the double ODE references
  // (reference::constraint_stabilization_rate).
  return integrate_model<S>(
      OdeSystemTpl<S>(spec, formulation, reference::mean_output_spacing(output_times)), start,
      output_times, precision, rtol, type_name, subdivisions, budget);
}

HighPrecisionRun solve_subdivided(const scene::SceneSpec& spec,
                                  const std::vector<double>& output_times, Precision precision,
                                  double rtol, core::FlexibleFormulation formulation,
                                  int subdivisions, const Budget& budget = {}) {
  if (output_times.empty()) throw std::invalid_argument("solve_high_precision: no output times");
  if (!(rtol >= smallest_rtol(precision)) || !(rtol < 1.0)) {
    std::ostringstream out;
    out << "--rtol " << rtol << ": " << to_string(precision) << " precision takes rtol in ["
        << smallest_rtol(precision) << ", 1)";
    throw std::invalid_argument(out.str());
  }
  switch (precision) {
    case Precision::kDouble:
      return integrate<double>(spec, formulation, output_times, precision, rtol, "double",
                               subdivisions, budget);
    case Precision::kExtended:
      return integrate<long double>(spec, formulation, output_times, precision, rtol,
                                    "long double (x87 80-bit)", subdivisions, budget);
    case Precision::kQuad:
      return integrate<Quad>(spec, formulation, output_times, precision, rtol,
                             "float128 (IEEE binary128, libquadmath)", subdivisions, budget);
  }
  throw std::invalid_argument("solve_high_precision: unknown precision");
}

/// A run as precise_comparison.hpp's table: its text in its own precision.
PreciseTable precise_table(const HighPrecisionRun& run) {
  PreciseTable t;
  t.precision = run.precision;
  t.columns = run.columns;
  for (const auto& row : run.table.rows) t.times.push_back(row.front());
  t.text = run.text;
  return t;
}

}  // namespace

double default_rtol(Precision precision) {
  switch (precision) {
    case Precision::kDouble:
      return 1e-12;
    case Precision::kExtended:
      return 1e-16;
    case Precision::kQuad:
      return 1e-28;
  }
  return 1e-12;
}

double smallest_rtol(Precision precision) {
  switch (precision) {
    case Precision::kDouble:
      return 1e-13;
    case Precision::kExtended:
      return 1e-18;
    case Precision::kQuad:
      return 1e-30;
  }
  return 1e-13;
}

void check_supported(const scene::SceneSpec& spec, core::FlexibleFormulation formulation) {
  (void)OdeSystemTpl<double>(spec, formulation);
}

HighPrecisionRun solve_high_precision(const scene::SceneSpec& spec,
                                      const std::vector<double>& output_times, Precision precision,
                                      double rtol, core::FlexibleFormulation formulation,
                                      reference::SolveProgress* progress) {
  Budget unbounded;
  unbounded.progress = progress;
  return solve_subdivided(spec, output_times, precision, rtol, formulation, 1, unbounded);
}

double distance(const HighPrecisionRun& a, const HighPrecisionRun& b, const std::string& metric) {
  if (a.columns != b.columns || a.text.size() != b.text.size()) {
    throw std::invalid_argument("distance: runs of different scenes or output times");
  }
  if (metric != trajectory::kDefaultMetric && metric != "rotation+points" && metric != "rotation" &&
      metric != "points") {
    throw std::invalid_argument("metric '" + metric +
                                "' is not available for extended/quad references (relative, "
                                "rotation+points, rotation, points)");
  }
  // compare's norms in the wider precision, each run parsed in its own (precise_comparison.hpp).
  return trajectory::metric_value(compare_precisely(precise_table(a), precise_table(b)), metric);
}

trajectory::CertifiedReference certified_high_precision_reference(
    const scene::SceneSpec& spec, const std::vector<double>& output_times, Precision precision,
    double rtol, const std::string& metric, HighPrecisionRun* run_out,
    core::FlexibleFormulation formulation, double budget_seconds,
    reference::SolveProgress* progress) {
  const double tight_rtol = std::max(rtol / 100.0, smallest_rtol(precision));
  // The run's projection counts the whole reference: the tighter check costs about twice the
  // run (flexible_spinner_64 extended: 223 s for the run, 658 s with the check), so 3 × the
  // run's projected time when there is a check.
  HighPrecisionRun run =
      solve_subdivided(spec, output_times, precision, rtol, formulation, 1,
                       {budget_seconds, 0.0, tight_rtol < rtol ? 3.0 : 1.0, progress});
  trajectory::CertifiedReference result;
  result.table = run.table;
  result.run.solver = "odeint";
  result.run.method = run.method;
  result.run.method_reason = std::string(to_string(precision)) + " precision";
  result.run.options.rtol = rtol;
  result.run.options.atol = rtol;
  result.run.stats.steps = run.steps;
  result.run.stats.rhs_evaluations = run.evaluations;
  result.run.stats.cpu_seconds = run.cpu_seconds;
  result.run.trajectory.times = output_times;
  trajectory::ReferenceEstimate& e = result.estimate;
  e.metric = metric;
  trajectory::EstimateCheck check;
  check.role = "tighter";
  check.solver = "odeint";
  check.rtol = tight_rtol;
  if (tight_rtol < rtol) {
    double spent = run.cpu_seconds;
    HighPrecisionRun tight =
        solve_subdivided(spec, output_times, precision, tight_rtol, formulation, 1,
                         {budget_seconds, spent, 1.0, progress});
    check.method = tight.method;
    if (tight.steps == run.steps && tight.evaluations == run.evaluations) {
      // Both took whole output intervals at extrapolation's highest order (smooth, slow
      // scenes): the same discretization. Steps of at most half an interval are another one.
      spent += tight.cpu_seconds;
      tight = solve_subdivided(spec, output_times, precision, tight_rtol, formulation, 2,
                               {budget_seconds, spent, 1.0, progress});
      check.method = tight.method + ", steps of at most half an output interval";
    }
    check.steps = tight.steps;
    check.distance = distance(run, tight, metric);
    // Extrapolation raises its order, not only its step count, for a tighter tolerance: a
    // check with the run's steps but other evaluations is a different discretization.
    check.used =
        check.distance > 0.0 && (tight.steps != run.steps || tight.evaluations != run.evaluations);
    if (!check.used) {
      check.note =
          check.distance > 0.0 ? "the run's own steps and evaluations" : "distance exactly 0";
    }
  } else {
    check.note = "no tighter tolerance in this precision";
  }
  e.checks.push_back(check);
  // The check shares the precision's round-off, which a tighter tolerance cannot expose: add a
  // bound on it that assumes no cancellation, u per evaluation, scaled by the solution's size
  // and what it sweeps (roundoff_scale.hpp). Measured: extended on book_toss_step's first 2 s
  // is 3.5e-16 from quad while 2 x its distance to the tighter run is 1.2e-16; tippe_top's
  // first second (180 rad/s) 3.0e-13 from quad while 2 x the distance is 1.1e-13 and u x
  // evaluations x the t0 extent only 5.2e-14.
  const double roundoff = unit_roundoff(precision) * static_cast<double>(run.evaluations) *
                          roundoff_scale(run.table, metric, node_points(spec));
  e.value = check.used ? 2.0 * check.distance + roundoff : std::numeric_limits<double>::infinity();
  std::ostringstream method;
  method << "2 x the distance, computed in " << to_string(precision)
         << " precision, to the same integrator at rtol " << std::setprecision(3) << tight_rtol
         << " (a different step sequence, 100x tighter), + the round-off bound u x evaluations x "
            "(solution size + T max|w| + T max point speed) = "
         << roundoff;
  e.method = check.used ? method.str() : "none: no usable check";
  if (run_out != nullptr) *run_out = std::move(run);
  return result;
}

std::string high_precision_csv(const HighPrecisionRun& run) {
  std::ostringstream out;
  for (std::size_t c = 0; c < run.columns.size(); ++c) out << (c ? "," : "") << run.columns[c];
  out << '\n';
  for (std::size_t r = 0; r < run.text.size(); ++r) {
    out << detail::print(run.table.rows[r][0], 17);
    for (const std::string& v : run.text[r]) out << ',' << v;
    out << '\n';
  }
  return out.str();
}

}  // namespace flexref::precision
