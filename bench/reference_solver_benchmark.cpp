/// Cost of the reference solvers (docs/references.md, "Cost"): free_spin (100 s, outputs every
/// 0.1 s, the scene's grid) and book_toss (10 s, outputs every 0.01 s) at rtol 1e-8, 1e-10 and
/// 1e-12, and each solver's setting for the issue-9 targets at 1e-13. CVODE runs with its
/// automatic method (Adams on both scenes) and, for comparison, forced BDF with projection.
/// Counters: steps, right-hand-side (or residual) evaluations, the solver's own process-CPU
/// time of the integration and its output states (solver_cpu_s), and on free_spin the error
/// against the exact solution (L∞ geodesic attitude angle, rad; computed once, outside the timed
/// loop).
///
/// For scale: on free_spin Simbody's RK-Merson needs about 4 s of CPU for 4e-11 rad
/// and its CPodes about 2.4 s for 7e-11 rad.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/exact_solution.hpp"
#include "reference/reference_solver.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/test_problems.hpp"

namespace {

namespace ref = flexref::reference;
using flexref::core::Model;

struct Scene {
  Model model;
  std::vector<double> times;
};

const Scene& free_spin() {
  static const Scene s{flexref::testing::free_spin(), flexref::core::output_times(100.0, 0.1)};
  return s;
}

const Scene& book_toss() {
  static const Scene s{flexref::testing::book_toss(), flexref::core::output_times(10.0, 0.01)};
  return s;
}

double attitude_error(const ref::ReferenceRun& run, const ref::ReferenceRun& exact) {
  double e = 0.0;
  for (std::size_t k = 0; k < run.trajectory.states.size(); ++k) {
    e = std::max(e, flexref::rotation::geodesic_angle(run.trajectory.states[k][0].theta_WB,
                                                      exact.trajectory.states[k][0].theta_WB));
  }
  return e;
}

/// `solver`: "cvode", "cvode-bdf", "ida", "arkode", "odeint".
void BM_Reference(benchmark::State& state, const Scene& (*scene)(), std::string solver,
                  double rtol) {
  const Scene& s = scene();
  ref::SolverOptions options;
  options.rtol = rtol;
  if (solver == "cvode-bdf") {
    solver = "cvode";
    options.cvode_method = ref::CvodeMethod::kBdf;
  }
  ref::ReferenceRun run;
  for (auto _ : state) {
    run = ref::solve_reference(solver, s.model, s.times, options);
    benchmark::DoNotOptimize(run.trajectory.states.back()[0].w_WB_B.data());
  }
  state.counters["rtol"] = rtol;
  state.counters["steps"] = static_cast<double>(run.stats.steps);
  state.counters["rhs_evals"] = static_cast<double>(run.stats.rhs_evaluations);
  state.counters["solver_cpu_s"] = run.stats.cpu_seconds;
  if (scene == &free_spin) {
    state.counters["error_rad"] = attitude_error(run, ref::solve_exact(s.model, s.times));
  }
  state.SetLabel(run.method);
}

void register_all() {
  for (const char* solver : {"cvode", "cvode-bdf", "ida", "arkode", "odeint"}) {
    for (const double rtol : {1e-8, 1e-10, 1e-12, 1e-13}) {
      char tolerance[16];
      std::snprintf(tolerance, sizeof tolerance, "%.0e", rtol);
      const std::string suffix = std::string(solver) + "/" + tolerance;
      benchmark::RegisterBenchmark(("free_spin/" + suffix).c_str(), BM_Reference, &free_spin,
                                   solver, rtol)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(("book_toss/" + suffix).c_str(), BM_Reference, &book_toss,
                                   solver, rtol)
          ->Unit(benchmark::kMillisecond);
    }
  }
}

const int kRegistered = (register_all(), 0);

}  // namespace
