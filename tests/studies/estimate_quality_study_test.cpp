/// \file estimate_quality_study_test.cpp
/// Label `study` (long): the estimator's contract (trajectory/certified_reference.hpp) on every
/// scene with an exact solution (tests/support/exact_scenes.hpp), for every reference solver and
/// every decade of rtol from 1e-6 to 1e-12: 1 ≤ estimate / true error ≤ 100, the estimate made
/// without the exact solution (as for a scene that has none). Prints the table of ratios.
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/exact_solution.hpp"
#include "reference/reference_solver.hpp"
#include "tests/support/exact_scenes.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::studies {

TEST_CASE("estimate / true error in [1, 100] on every exact scene, solver and rtol", "[estimate]") {
  constexpr const char* kMetric = "rotation+points";
  for (const testing::ExactScene& scene : testing::exact_scenes()) {
    const core::Model model = scene.model();
    const std::vector<double> times =
        core::output_times(scene.end_time, scene.end_time > 5.0 ? 0.1 : 0.01);
    const reference::ReferenceRun exact = reference::solve_exact(model, times);
    const trajectory::TrajectoryTable exact_table = trajectory::tabulate(model, exact.trajectory);
    for (const char* solver : {"cvode", "ida", "arkode", "odeint"}) {
      for (double rtol = 1e-6; rtol > 5e-13; rtol /= 10.0) {
        reference::SolverOptions options;
        options.rtol = rtol;
        const trajectory::CertifiedReference r = trajectory::certified_reference(
            model, times, solver, options, kMetric, {.use_exact_solution = false});
        const double truth = trajectory::metric_value(
            trajectory::compare_trajectories(r.table, exact_table), kMetric);
        const double ratio = r.estimate.value / truth;
        std::printf("%-45s %-7s rtol %.0e  true %.3e  estimate %.3e  ratio %6.2f\n",
                    scene.name.c_str(), solver, rtol, truth, r.estimate.value, ratio);
        CAPTURE(scene.name, solver, rtol, truth, r.estimate.value, r.estimate.method);
        CHECK(ratio >= 1.0);
        CHECK(ratio <= 100.0);
      }
    }
  }
}

}  // namespace flexref::studies
