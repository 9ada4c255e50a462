/// Wall time of the three reference solvers on the coupled flexible_spinner
/// (tests/support/flexible_models.hpp: 4 bending modes on 10 elements, hub torque pulse on
/// [0, 0.5); end 10 s, outputs every 0.01 s), over tolerances, with each run's estimated error
/// (docs/performance.md, "Flexible bodies"):
///
///   est_final    difference to the same solver at 100× tighter rtol, at t = 10 s: the larger of
///                the tip's world position error (m) and the hub's geodesic attitude angle (rad)
///   est_final_x  the same against the other solvers (the largest difference to the anchor runs
///                CVODE at rtol 1e-13 and Odeint at 1e-13, leaving out the solver's own anchor)
///   est_linf, est_linf_x   the same, max over the 1001 output times
///
/// A failed estimate run is reported as −1. The estimates are computed once per (solver, rtol)
/// outside the timed loop. Counters steps and rhs_evals are the solver's own (IDA: residuals).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/reference_solver.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/flexible_models.hpp"

namespace {

using flexref::core::Model;
using flexref::core::Trajectory;
using flexref::reference::ReferenceRun;
using flexref::reference::SolverOptions;
using Solver = ReferenceRun (*)(const Model&, const std::vector<double>&, const SolverOptions&);

struct SolverEntry {
  const char* name;
  Solver solve;
};
const SolverEntry kSolvers[] = {{"cvode", flexref::reference::solve_cvode},
                                {"ida", flexref::reference::solve_ida},
                                {"odeint", flexref::reference::solve_odeint}};
constexpr int kAnchorExponent = 13;  ///< anchors at rtol 1e-13

const Model& spinner() {
  static const Model model =
      flexref::testing::flexible_spinner_model(flexref::core::FlexibleFormulation::kCoupled);
  return model;
}

const std::vector<double>& times() {
  static const std::vector<double> t = flexref::core::output_times(10.0, 0.01);
  return t;
}

double rtol_of(int exponent) { return std::pow(10.0, -exponent); }

/// Trajectories by (solver, rtol = 10^−exponent); nullptr when the solver failed.
const Trajectory* cached_run(const SolverEntry& solver, int exponent) {
  static std::map<std::pair<std::string, int>, std::pair<bool, Trajectory>> cache;
  const auto key = std::make_pair(std::string(solver.name), exponent);
  auto it = cache.find(key);
  if (it == cache.end()) {
    SolverOptions options;
    options.rtol = rtol_of(exponent);
    std::pair<bool, Trajectory> entry{false, {}};
    try {
      entry = {true, solver.solve(spinner(), times(), options).trajectory};
    } catch (const std::exception&) {
    }
    it = cache.emplace(key, std::move(entry)).first;
  }
  return it->second.first ? &it->second.second : nullptr;
}

/// max(|tip − tip_ref|, geodesic angle) at one output.
double difference(const flexref::core::State& a, const flexref::core::State& b) {
  const Model& model = spinner();
  const flexref::core::TrackedPoint& tip = model.body(0).description().points[0];
  const double tip_error = (model.p_WP(0, a[0], tip) - model.p_WP(0, b[0], tip)).norm();
  const double angle = flexref::rotation::geodesic_angle(a[0].theta_WB, b[0].theta_WB);
  return std::max(tip_error, angle);
}

struct Estimate {
  double final = -1.0;
  double linf = -1.0;
};

Estimate compare(const Trajectory* run, const Trajectory* reference) {
  if (run == nullptr || reference == nullptr) return {};
  Estimate e;
  e.final = difference(run->states.back(), reference->states.back());
  e.linf = 0.0;
  for (std::size_t k = 0; k < run->states.size(); ++k) {
    e.linf = std::max(e.linf, difference(run->states[k], reference->states[k]));
  }
  return e;
}

void BM_SpinnerReference(benchmark::State& state, const SolverEntry& solver, int exponent) {
  // Error estimates (once per configuration, untimed).
  const Trajectory* run = cached_run(solver, exponent);
  const Estimate tight = compare(run, cached_run(solver, exponent + 2));
  Estimate cross{0.0, 0.0};
  for (const SolverEntry& other : kSolvers) {
    if (std::string(other.name) == solver.name || std::string(other.name) == "ida") continue;
    const Estimate e = compare(run, cached_run(other, kAnchorExponent));
    cross.final = e.final < 0.0 || cross.final < 0.0 ? -1.0 : std::max(cross.final, e.final);
    cross.linf = e.linf < 0.0 || cross.linf < 0.0 ? -1.0 : std::max(cross.linf, e.linf);
  }

  const double rtol = rtol_of(exponent);
  SolverOptions options;
  options.rtol = rtol;
  ReferenceRun timed;
  for (auto _ : state) {
    timed = solver.solve(spinner(), times(), options);
    benchmark::DoNotOptimize(timed.trajectory.states.back()[0].q_f.data());
  }
  state.counters["rtol"] = rtol;
  state.counters["steps"] = static_cast<double>(timed.stats.steps);
  state.counters["rhs_evals"] = static_cast<double>(timed.stats.rhs_evaluations);
  state.counters["est_final"] = tight.final;
  state.counters["est_final_x"] = cross.final;
  state.counters["est_linf"] = tight.linf;
  state.counters["est_linf_x"] = cross.linf;
}

/// BM_SpinnerReference/<solver>/rtol:<rtol>, rtol 1e-8 … 1e-12.
const bool kRegistered = [] {
  for (const SolverEntry& solver : kSolvers) {
    for (int e = 8; e <= 12; ++e) {
      benchmark::RegisterBenchmark(
          ("BM_SpinnerReference/" + std::string(solver.name) + "/rtol:1e-" + std::to_string(e))
              .c_str(),
          [&solver, e](benchmark::State& s) { BM_SpinnerReference(s, solver, e); })
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond);
    }
  }
  return true;
}();

}  // namespace
