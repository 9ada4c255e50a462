/// CPU time of the references on the stiff bundled scene flexible_spinner_64 (40 elements,
/// 64 bending modes up to 1.8e4 rad/s; coupled model, 10 s, outputs every 0.01 s) against the
/// 4-mode flexible_spinner with the same solver, method and rtol
/// (docs/references.md, "Stiff oscillatory scenes"). Run from the source root (the scenes are
/// read from scenes/):
///
///   BM_Stiff/<solver>/<method>/rtol:<r>   one run of the 64-mode scene per iteration, then
///                                         the 4-mode scene with the same solver and method
///                                         (forced: the 4-mode scene alone would get Adams or
///                                         the ERK); counters:
///     cpu_s      the 64-mode run's process CPU time (the solver's own clock, SolverStats)
///     cpu4_s     the 4-mode run's, same solver, method and rtol
///     ratio      cpu_s / cpu4_s (target ≤ 100)
///     steps, steps4, jacobians
///     error      max over the outputs of the tip's world position error (m) and the hub's
///                geodesic attitude angle (rad) against Odeint at rtol 1e-11 (computed once,
///                untimed: ~20 s; its own error ≈ 1e-11, docs/references.md)
///
/// The benchmark's own time column is wall time of both runs; the counters are what to quote.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/reference_solver.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/scene_reader.hpp"

namespace {

namespace ref = flexref::reference;
using flexref::core::State;

const flexref::scene::Scene& scene64() {
  static const flexref::scene::Scene s =
      flexref::scene::read_scene("scenes/flexible_spinner_64.toml");
  return s;
}
const flexref::scene::Scene& scene4() {
  static const flexref::scene::Scene s = flexref::scene::read_scene("scenes/flexible_spinner.toml");
  return s;
}
const std::vector<double>& times() {
  static const std::vector<double> t = flexref::core::output_times(10.0, 0.01);
  return t;
}

const flexref::core::Trajectory& odeint_anchor() {
  static const flexref::core::Trajectory t = [] {
    ref::SolverOptions o;
    o.rtol = 1e-11;
    return ref::solve_odeint(*scene64().model, times(), o).trajectory;
  }();
  return t;
}

double error_of(const flexref::core::Trajectory& run) {
  const flexref::core::Model& model = *scene64().model;
  const flexref::core::TrackedPoint& tip = model.body(0).description().points[0];
  const flexref::core::Trajectory& anchor = odeint_anchor();
  double worst = 0.0;
  for (std::size_t k = 0; k < run.states.size(); ++k) {
    const State& a = run.states[k];
    const State& b = anchor.states[k];
    worst = std::max(worst, (model.p_WP(0, a[0], tip) - model.p_WP(0, b[0], tip)).norm());
    worst = std::max(worst, flexref::rotation::geodesic_angle(a[0].theta_WB, b[0].theta_WB));
  }
  return worst;
}

void BM_Stiff(benchmark::State& state, const std::string& solver, const std::string& method,
              double rtol) {
  ref::SolverOptions options;
  options.rtol = rtol;
  if (solver == "arkode") {
    options.arkode_method = ref::parse_arkode_method(method);
  } else {
    options.cvode_method = ref::parse_cvode_method(method);
  }
  ref::ReferenceRun run64, run4;
  for (auto _ : state) {
    run64 = ref::solve_reference(solver, *scene64().model, times(), options);
    run4 = ref::solve_reference(solver, *scene4().model, times(), options);
    benchmark::DoNotOptimize(run64.trajectory.states.back()[0].q_f.data());
  }
  state.counters["rtol"] = rtol;
  state.counters["cpu_s"] = run64.stats.cpu_seconds;
  state.counters["cpu4_s"] = run4.stats.cpu_seconds;
  state.counters["ratio"] = run64.stats.cpu_seconds / run4.stats.cpu_seconds;
  state.counters["steps"] = static_cast<double>(run64.stats.steps);
  state.counters["steps4"] = static_cast<double>(run4.stats.steps);
  state.counters["jacobians"] = static_cast<double>(run64.stats.jacobian_evaluations);
  state.counters["error"] = error_of(run64.trajectory);
  state.SetLabel(run64.method + ", " + run64.jacobian);
}

std::string rtol_name(double rtol) {
  std::ostringstream s;
  s << rtol;
  return s.str();
}

/// ARKODE's ESDIRK (the default reference on this scene), CVODE and IDA with BDF ≤ 2 (their
/// automatic choice here), over rtol.
const bool kRegistered = [] {
  struct Config {
    const char* solver;
    const char* method;
    std::vector<double> rtols;
  };
  const Config configs[] = {{"arkode", "esdirk", {1e-7, 1e-8, 1e-9}},
                            {"cvode", "bdf2", {1e-8, 1e-10}},
                            {"ida", "bdf2", {1e-8, 1e-10}}};
  for (const Config& c : configs) {
    for (const double rtol : c.rtols) {
      const std::string solver = c.solver, method = c.method;
      benchmark::RegisterBenchmark(
          ("BM_Stiff/" + solver + "/" + method + "/rtol:" + rtol_name(rtol)).c_str(),
          [solver, method, rtol](benchmark::State& s) { BM_Stiff(s, solver, method, rtol); })
          ->Iterations(1)
          ->Unit(benchmark::kSecond);
    }
  }
  return true;
}();

}  // namespace
