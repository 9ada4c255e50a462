/// \file reference_targets_test.cpp
/// The accuracy targets of the references (docs/references.md "Targets"), as
/// properties: the error against an exact solution at the tightest tolerance, an error that
/// falls with every decade of tolerance, the two BDF references against the tightest explicit
/// one on the sensitive book toss, and IDA against CVODE on the coupled flexible spinner.
/// Errors are L∞ over all output times of the geodesic attitude angle (rad), the quantity the
/// issue measured, or of the tracked point (m) where said.
#include <Eigen/Core>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstddef>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/exact_solution.hpp"
#include "reference/reference_solver.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/exact_scenes.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/solver_options.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

using testing::with_rtol;

/// L∞ over the outputs and bodies of the geodesic angle between two runs' attitudes, rad.
double attitude_difference(const ReferenceRun& a, const ReferenceRun& b) {
  REQUIRE(a.trajectory.times == b.trajectory.times);
  double d = 0.0;
  for (std::size_t k = 0; k < a.trajectory.states.size(); ++k) {
    for (std::size_t i = 0; i < a.trajectory.states[k].size(); ++i) {
      d = std::max(d, rotation::geodesic_angle(a.trajectory.states[k][i].theta_WB,
                                               b.trajectory.states[k][i].theta_WB));
    }
  }
  return d;
}

/// L∞ of the tracked point's position difference, m (every body's "tracked" or "tip").
double point_difference(const core::Model& model, const ReferenceRun& a, const ReferenceRun& b) {
  double d = 0.0;
  for (std::size_t k = 0; k < a.trajectory.states.size(); ++k) {
    for (int i = 0; i < model.num_bodies(); ++i) {
      const core::Body& body = model.body(i);
      for (const core::TrackedPoint& p : body.description().points) {
        const auto u = static_cast<std::size_t>(i);
        d = std::max(d, (model.p_WP(i, a.trajectory.states[k][u], p) -
                         model.p_WP(i, b.trajectory.states[k][u], p))
                            .norm());
      }
    }
  }
  return d;
}

const char* const kTargetSolverNames[] = {"cvode", "ida", "arkode", "odeint"};

}  // namespace

TEST_CASE("free_spin at rtol 1e-13: every reference within its target of the exact solution",
          "[reference][targets]") {
  // Targets: Odeint and ARKODE (explicit, order 8) ≤ 1e-11 rad, CVODE and IDA
  // ≤ 1e-10 rad over the 100 s scene. Measured: CVODE (Adams, chosen automatically) 3.1e-12,
  // IDA (BDF) 9.1e-11, ARKODE 3.5e-13, Odeint 5.8e-12.
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(100.0, 0.1);
  const ReferenceRun exact = solve_exact(model, times);
  for (const char* solver : kTargetSolverNames) {
    const ReferenceRun run = solve_reference(solver, model, times, with_rtol(1e-13));
    const double error = attitude_difference(run, exact);
    const double target = run.solver == "cvode" || run.solver == "ida" ? 1e-10 : 1e-11;
    CAPTURE(solver, run.method, error, target, run.stats.steps);
    CHECK(error <= target);
  }
}

TEST_CASE("every reference's error falls with each decade of rtol from 1e-4 to 1e-12",
          "[reference][targets]") {
  // free_spin and heavy_top against their exact solutions, coulomb_wall against Odeint at
  // rtol 1e-14 (ARKODE at 1e-14 agrees with it to 8.0e-12 rad over the 100 s). Measured before
  // issue 51: each decade gains 2–40× (free_spin: CVODE 1.7e-2 → 2.6e-10, IDA 7.4e-3 →
  // 2.2e-10, ARKODE 5.8e-4 → 6.6e-13, Odeint 3.7e-3 → 5.1e-11 rad). The property: strictly
  // smaller at every decade — until a run is at its floor: with the rotation weighted per unit
  // step (docs/references.md, "Error weights") IDA on coulomb_wall reaches 6.0e-11 rad at rtol
  // 1e-11 (93 510 steps) and 1.1e-10 at 1e-12 (100 469 steps: its rotation weights are at their
  // round-off floor, 8 ε, and the steps no longer shrink); below `floor` (2e-10 rad, twice the
  // latter) a decade need not gain.
  struct Case {
    std::string name;
    core::Model model;
    double end_time;
    double output_step;
    double floor;  ///< rad
  };
  std::vector<Case> cases;
  cases.push_back({"free_spin", testing::free_spin(), 100.0, 0.1, 0.0});
  cases.push_back({"heavy_top", testing::heavy_top(), 2.0, 0.01, 0.0});
  cases.push_back({"coulomb_wall", testing::coulomb_wall(), 100.0, 0.1, 2e-10});
  for (const Case& c : cases) {
    const std::vector<double> times = core::output_times(c.end_time, c.output_step);
    const ReferenceRun truth = c.name == "coulomb_wall"
                                   ? solve_odeint(c.model, times, with_rtol(1e-14))
                                   : solve_exact(c.model, times);
    for (const char* solver : kTargetSolverNames) {
      double previous = 1e300;
      for (double rtol = 1e-4; rtol > 5e-13; rtol /= 10.0) {
        const ReferenceRun run = solve_reference(solver, c.model, times, with_rtol(rtol));
        const double error = attitude_difference(run, truth);
        CAPTURE(c.name, solver, rtol, error, previous);
        CHECK((error < previous || error <= c.floor));
        previous = error;
      }
    }
  }
}

TEST_CASE("book_toss: IDA and CVODE within 1e-7 of the tightest Odeint run",
          "[reference][targets][ida][cvode]") {
  // Near the separatrix a perturbation of 1e-12 in ω̄ grows to ~1e-7 in ω̄ and 1e-8 rad
  // (reference_cross_check_test.cpp): 1e-7 rad and 1e-7 m at the tracked corner (1 m from the
  // centre) is the target. Odeint at rtol 1e-14 is the tightest run (Odeint at 1e-13
  // differs from it by 1.8e-8 rad). Measured: CVODE (Adams) at 1e-12 3.7e-9 rad; IDA at 1e-13
  // 5.0e-8 rad (at 1e-12 2.7e-7: IDA's BDF needs a decade more).
  const core::Model model = testing::book_toss();
  const std::vector<double> times = core::output_times(10.0, 0.01);
  const ReferenceRun odeint = solve_odeint(model, times, with_rtol(1e-14));
  const ReferenceRun cvode = solve_cvode(model, times, with_rtol(1e-12));
  const ReferenceRun ida = solve_ida(model, times, with_rtol(1e-13));
  for (const ReferenceRun* run : {&cvode, &ida}) {
    const double angle = attitude_difference(*run, odeint);
    const double point = point_difference(model, *run, odeint);
    CAPTURE(run->solver, run->options.rtol, angle, point);
    CHECK(angle <= 1e-7);
    CHECK(point <= 1e-7);
  }
}

TEST_CASE("coupled flexible_spinner: IDA and CVODE agree to 1e-8 at rtol 1e-12",
          "[reference][targets][ida][cvode][flexible]") {
  // The scene: 10 s, outputs every 0.01 s, spin-up torque on [0, 0.5). Target 1e-8 in the
  // attitude (rad) and the beam tip (m).
  // Measured: 1.9e-10 rad and 1.4e-9 m.
  const core::Model model = testing::flexible_spinner_model(core::FlexibleFormulation::kCoupled);
  const std::vector<double> times = core::output_times(10.0, 0.01);
  const ReferenceRun cvode = solve_cvode(model, times, with_rtol(1e-12));
  const ReferenceRun ida = solve_ida(model, times, with_rtol(1e-12));
  const double angle = attitude_difference(cvode, ida);
  const double point = point_difference(model, cvode, ida);
  CAPTURE(angle, point, cvode.method);
  CHECK(angle <= 1e-8);
  CHECK(point <= 1e-8);
}

}  // namespace flexref::reference
