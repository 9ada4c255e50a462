/// \file solver_conformance_test.cpp
/// The conformance suite every reference solver joins (IDA on the DAE form, CVODE and ARKODE's
/// ERK and ESDIRK on the ODE form, Boost.Odeint RKF7(8) on the ODE form): conservation on a
/// torque-free body, exactly the requested output times with unit Euler parameters, the start at t
/// = 0, input validation, and the failure path (too much work, singular loads) naming the time.
/// Solver-specific checks stay in <solver>_solver_test.cpp.
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/body.hpp"
#include "core/error.hpp"
#include "core/model.hpp"
#include "core/output_times.hpp"
#include "core/point_charge_potential.hpp"
#include "reference/arkode_esdirk_solver.hpp"
#include "reference/reference_solver.hpp"
#include "tests/support/solver_options.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

using testing::with_rtol;

struct Solver {
  const char* name;
  ReferenceRun (*solve)(const core::Model&, const std::vector<double>&, const SolverOptions&);
  const char* too_much_work;  ///< how the solver's message says it
};

const Solver kSolvers[] = {{"ida", solve_ida, "IDA_TOO_MUCH_WORK"},
                           {"cvode", solve_cvode, "CV_TOO_MUCH_WORK"},
                           {"arkode", solve_arkode, "ARK_TOO_MUCH_WORK"},
                           {"arkode", solve_arkode_esdirk, "ARK_TOO_MUCH_WORK"},
                           {"odeint", solve_odeint, "too much work"}};

/// coulomb_wall (tests/support/test_problems.hpp) started with both charges on the wall z = 0,
/// where the wall force β/z² is infinite.
core::Model coulomb_wall_on_the_wall() {
  core::RigidBodyDescription d =
      testing::rigid_body("charged", 1.0, {0.4, 0.9, 1.1}, {0.2, 0.3, 1.5});
  d.initial.v_WBo = Eigen::Vector3d(0.8, 0.0, 0.0);  // p_WBo = 0: the charges start at z = 0
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  testing::Elements elements;
  elements.push_back(std::make_unique<core::PointChargePotential>(
      4.0, 0.3, Eigen::Vector3d(0.0, 0.0, -1.0),
      std::vector<core::PointChargePotential::Charge>{{0, Eigen::Vector3d(0.5, 0.0, 0.0), 1.0},
                                                      {0, Eigen::Vector3d(-0.5, 0.0, 0.0), 0.6}}));
  return core::Model(std::move(bodies), std::move(elements));
}

}  // namespace

TEST_CASE("reference solvers conserve energy and angular momentum of a torque-free body",
          "[reference][conformance]") {
  const core::Model model = testing::free_spin();
  // Outputs every second, so that the tolerance, not the output grid, sets the steps.
  const std::vector<double> times = core::output_times(100.0, 1.0);
  const double rtol = 1e-10;
  for (const Solver& solver : kSolvers) {
    INFO("solver " << solver.name);
    const ReferenceRun run = solver.solve(model, times, with_rtol(rtol));
    REQUIRE(run.trajectory.states.size() == times.size());
    CHECK(run.solver == solver.name);
    const double energy0 = model.kinetic_energy(run.trajectory.states.front());
    const Eigen::Vector3d momentum0 = model.angular_momentum_W(run.trajectory.states.front());
    // Each accepted step commits a local error of at most ~rtol relative (the solver's error
    // test), so after N steps an invariant can have drifted by at most ~N·rtol relative if every
    // error had the same sign.
    const double bound = static_cast<double>(run.stats.steps) * rtol;
    for (const core::State& state : run.trajectory.states) {
      const double energy_error = std::abs(model.kinetic_energy(state) - energy0) / energy0;
      const double momentum_error =
          (model.angular_momentum_W(state) - momentum0).norm() / momentum0.norm();
      CAPTURE(energy_error, momentum_error, bound);
      CHECK(energy_error <= bound);
      CHECK(momentum_error <= bound);
    }
  }
}

TEST_CASE(
    "reference solvers write exactly the requested output times with unit Euler "
    "parameters",
    "[reference][conformance]") {
  const core::Model model = testing::book_toss_step();
  // Irregular times around the switch at 0.1 (one on it, one 1e-7 before, one 1e-7 after).
  const std::vector<double> times{0.0, 0.013, 0.05, 0.1 - 1e-7, 0.1, 0.1 + 1e-7, 0.37, 1.0};
  for (const Solver& solver : kSolvers) {
    INFO("solver " << solver.name);
    const ReferenceRun run = solver.solve(model, times, with_rtol(1e-10));
    REQUIRE(run.trajectory.times == times);
    REQUIRE(run.trajectory.states.size() == times.size());
    CHECK(run.trajectory.states.front()[0].w_WB_B == model.initial_state()[0].w_WB_B);
    for (const core::State& state : run.trajectory.states) {
      // unpack normalizes θ: the norm is 1 up to its last bit.
      CHECK(std::abs(state[0].theta_WB.norm() - 1.0) <= 4e-16);
    }
    CHECK(run.stats.steps > 0);
    CHECK(run.stats.rhs_evaluations > run.stats.steps);
    CHECK(run.stats.cpu_seconds >= 0.0);

    // The value at 0.37 on another output grid. Every solver fills outputs from its own dense
    // output (CVODE, IDA) or continuous extension (ARKODE, Odeint) and never lets the grid
    // shorten a step; the CVODE driver sizes each segment's first step towards the segment
    // end rather than the first output. So the steps are the same for any grid with the same
    // segments: agreement to round-off (measured bit for bit; 1e-12 leaves room for 0.37 and
    // 37 × 0.01 differing in the last bit).
    const ReferenceRun fine = solver.solve(model, core::output_times(1.0, 0.01), with_rtol(1e-10));
    const double difference =
        (fine.trajectory.states[37][0].w_WB_B - run.trajectory.states[6][0].w_WB_B).norm();
    CAPTURE(difference);
    CHECK(difference <= 1e-12);
  }
}

TEST_CASE("reference solvers start at t = 0 even when the first output is later",
          "[reference][conformance]") {
  const core::Model model = testing::free_spin();
  for (const Solver& solver : kSolvers) {
    INFO("solver " << solver.name);
    const ReferenceRun late = solver.solve(model, {0.5, 1.0}, with_rtol(1e-10));
    const ReferenceRun full = solver.solve(model, core::output_times(1.0, 0.5), with_rtol(1e-10));
    // Same start, same steps (outputs at 0.5 and 1.0 in both): agreement to round-off
    // (measured: bit for bit).
    const double difference =
        (late.trajectory.states[1][0].w_WB_B - full.trajectory.states[2][0].w_WB_B).norm();
    CAPTURE(difference);
    CHECK(difference <= 1e-12);
  }
}

TEST_CASE("reference solvers reject invalid output times and tolerances",
          "[reference][conformance]") {
  const core::Model model = testing::free_spin();
  for (const Solver& solver : kSolvers) {
    INFO("solver " << solver.name);
    CHECK_THROWS_AS(solver.solve(model, {}, SolverOptions{}), std::invalid_argument);
    CHECK_THROWS_AS(solver.solve(model, {0.0, 1.0, 0.5}, SolverOptions{}), std::invalid_argument);
    CHECK_THROWS_AS(solver.solve(model, {-1.0, 1.0}, SolverOptions{}), std::invalid_argument);
    SolverOptions bad;
    bad.rtol = 0.0;
    CHECK_THROWS_AS(solver.solve(model, {0.0, 1.0}, bad), std::invalid_argument);
    bad.rtol = 1e-10;
    bad.max_steps = 0;
    CHECK_THROWS_AS(solver.solve(model, {0.0, 1.0}, bad), std::invalid_argument);
  }
}

TEST_CASE("reference solvers report too much work with the time where they stopped",
          "[reference][conformance]") {
  const core::Model model = testing::coulomb_wall();
  for (const Solver& solver : kSolvers) {
    INFO("solver " << solver.name);
    SolverOptions options = with_rtol(1e-10);
    options.max_steps = 10;
    try {
      solver.solve(model, {0.0, 100.0}, options);
      FAIL("no SolverError");
    } catch (const core::SolverError& e) {
      CAPTURE(e.what());
      CHECK(e.solver() == solver.name);
      CHECK(e.time() > 0.0);
      CHECK(e.time() < 100.0);
      CHECK(e.step() >= 10);
      CHECK(std::string(e.what()).find("failed at t = ") != std::string::npos);
      CHECK(std::string(e.what()).find(solver.too_much_work) != std::string::npos);
    }
  }
}

TEST_CASE("reference solvers report singular loads at the initial state",
          "[reference][conformance]") {
  // Both charges start on the wall z = 0: the wall force β/z² is infinite.
  const core::Model model = coulomb_wall_on_the_wall();
  for (const Solver& solver : kSolvers) {
    INFO("solver " << solver.name);
    try {
      solver.solve(model, {0.0, 1.0}, with_rtol(1e-10));
      FAIL("no SolverError");
    } catch (const core::SolverError& e) {
      CAPTURE(e.what());
      CHECK(e.time() == 0.0);
      CHECK(std::string(e.what()).find("failed at t = 0") != std::string::npos);
    }
  }
}

}  // namespace flexref::reference
