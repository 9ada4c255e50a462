#include "lie/run_scheme.hpp"

#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "lie/scheme_support.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::lie {
namespace {

std::string invalid_argument_message(const core::Model& model, double dt,
                                     const std::vector<double>& times) {
  const auto stepper = make_stepper("c2", model, {});
  try {
    run_scheme(model, *stepper, dt, times);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no exception)";
}

TEST_CASE("run_scheme rejects a bad step or output grid", "[lie][run_scheme]") {
  const core::Model model = testing::free_spin();
  const std::vector<double> grid = core::output_times(1.0, 0.1);
  CHECK(invalid_argument_message(model, 0.0, grid).find("dt") != std::string::npos);
  CHECK(invalid_argument_message(model, -0.1, grid).find("dt") != std::string::npos);
  CHECK(
      invalid_argument_message(model, std::numeric_limits<double>::quiet_NaN(), grid).find("dt") !=
      std::string::npos);
  CHECK(invalid_argument_message(model, 0.1, {}).find("no output") != std::string::npos);
  CHECK(invalid_argument_message(model, 0.1, {0.0, 0.2, 0.2}).find("increasing") !=
        std::string::npos);
  // 0.1 is not a multiple of 0.03: the message names the time and the step.
  const std::string off_grid = invalid_argument_message(model, 0.03, grid);
  CHECK(off_grid.find("output time t = 0.1") != std::string::npos);
  CHECK(off_grid.find("dt = 0.03") != std::string::npos);
}

TEST_CASE("run_scheme requires load discontinuities with t0 < t <= t_end on the grid",
          "[lie][run_scheme]") {
  const core::Model model = testing::book_toss_step();  // switches at 0 and 0.1
  // 0.3 = 4 × 0.075, but 0.1 is not a multiple of 0.075.
  const std::string message = invalid_argument_message(model, 0.075, {0.0, 0.3});
  CHECK(message.find("load discontinuity t = 0.1") != std::string::npos);
  CHECK(message.find("dt = 0.075") != std::string::npos);
  // Outside (t0, t_end] the discontinuities do not constrain the step.
  const auto stepper = make_stepper("c2", model, {});
  CHECK_NOTHROW(run_scheme(model, *stepper, 0.0075, {0.0, 0.03}));
}

TEST_CASE("run_scheme steps on t0 + n dt and records the output times", "[lie][run_scheme]") {
  const core::Model model = testing::book_toss();
  const double t0 = 0.3;
  const double dt = 0.01;
  const std::vector<double> times{t0, 0.5, 0.55, 1.3};
  for (const std::string& name : builtin_scheme_names()) {
    DYNAMIC_SECTION("scheme " << name) {
      const auto stepper = make_stepper(name, model, {});
      const core::Trajectory run = run_scheme(model, *stepper, dt, times);
      CHECK(run.times == times);
      REQUIRE(run.states.size() == times.size());
      CHECK(run.states[0][0].w_WB_B == model.initial_state()[0].w_WB_B);
      // The clock is t0 + n·dt by multiplication, never accumulated: exact at the end.
      CHECK(stepper->time() == t0 + 100.0 * dt);
      // The same steps taken by hand give the same recorded states.
      const auto manual = make_stepper(name, model, {});
      manual->initialize(t0, model.initial_state());
      for (long n = 0; n < 100; ++n) {
        REQUIRE(manual->step(t0 + static_cast<double>(n + 1) * dt - manual->time()).ok);
        if (n + 1 == 20) CHECK(manual->state()[0].theta_WB == run.states[1][0].theta_WB);
        if (n + 1 == 25) CHECK(manual->state()[0].w_WB_B == run.states[2][0].w_WB_B);
      }
      CHECK(manual->state()[0].theta_WB == run.states[3][0].theta_WB);
    }
  }
}

TEST_CASE("a step starts on a discontinuity within 1e-9 of the step", "[lie][run_scheme]") {
  const std::vector<double> switches{0.1, 0.25};
  CHECK(detail::starts_on_discontinuity(switches, 0.1, 0.01));
  CHECK(detail::starts_on_discontinuity(switches, 10 * 0.01, 0.01));  // 0.1 in floating point
  CHECK(detail::starts_on_discontinuity(switches, 0.25 + 1e-13, 0.01));
  CHECK_FALSE(detail::starts_on_discontinuity(switches, 0.09, 0.01));
  CHECK_FALSE(detail::starts_on_discontinuity(switches, 0.26, 0.01));
  CHECK_FALSE(detail::starts_on_discontinuity({}, 0.1, 0.01));
}

}  // namespace
}  // namespace flexref::lie

namespace flexref::lie {
namespace {

TEST_CASE("validate_step_grid refuses a step double precision cannot resolve",
          "[lie][run_scheme]") {
  const core::Model model = testing::free_spin();
  const std::vector<double> grid = core::output_times(10.0, 0.1);
  // At t = 10 s times are rounded to ε·10 = 2.2e-15 s; a step must span 1e6 of them:
  // 2.2e-9 s (core::smallest_resolved_step). Unchecked, 1e-19 s would overflow the step
  // count and 1e-12 s start 1e13 silent steps.
  for (const double dt : {1e-300, 1e-19, 1e-12, 2e-9}) {
    INFO("dt = " << dt);
    const std::string message = invalid_argument_message(model, dt, grid);
    CHECK(message.find("below what double precision resolves at t = 10") != std::string::npos);
  }
  // Just above the bound the grid is accepted and the step count returned (10 / 2.5e-9).
  CHECK(validate_step_grid(model, 2.5e-9, grid) == 4'000'000'000L);
  CHECK(validate_step_grid(model, 0.01, grid) == 1000);
}

TEST_CASE("validate_step_grid refuses a step longer than the run or an output interval",
          "[lie][run_scheme]") {
  const core::Model model = testing::free_spin();
  const std::vector<double> grid = core::output_times(100.0, 0.1);
  // 1e15 s: (t − t0)/dt rounds to 0 steps for every output time, which the grid check accepted
  // (the run then returned one state for 1001 output times). 1e10 s: accepted up to t = 10 s.
  for (const double dt : {1e15, 1e10, 200.0}) {
    INFO("dt = " << dt);
    const std::string message = invalid_argument_message(model, dt, grid);
    CHECK(message.find("is longer than the whole run (100 s, t = 0 to 100)") != std::string::npos);
    CHECK(message.find("not on the step grid") == std::string::npos);
  }
  for (const double dt : {0.2, 50.0}) {
    INFO("dt = " << dt);
    const std::string message = invalid_argument_message(model, dt, grid);
    CHECK(message.find("is longer than the output interval (0.1 s)") != std::string::npos);
  }
  // The output step itself is one step per interval.
  CHECK(validate_step_grid(model, 0.1, grid) == 1000);
}

TEST_CASE("run_scheme stops with a SolverError when the energy is not finite",
          "[lie][run_scheme]") {
  // W = 1e160 rad/s: every state component is finite but ½ Wᵀ J W = 2e320 J overflows. The
  // driver must refuse at t0 instead of returning a trajectory whose table holds inf.
  std::vector<core::Body> bodies;
  bodies.emplace_back(testing::rigid_body("spinner", 1.0, {3.0, 4.0, 5.0}, {1e160, 0.0, 0.0}));
  const core::Model model(std::move(bodies), testing::Elements{});
  const auto stepper = make_stepper("c2", model, {});
  try {
    run_scheme(model, *stepper, 1e-3, {0.0, 1e-2});
    FAIL("no exception");
  } catch (const core::SolverError& e) {
    CHECK(e.time() == 0.0);
    CHECK(std::string(e.what()).find("energy is not finite") != std::string::npos);
  }
}

TEST_CASE("run_scheme reports its step count for a progress line", "[lie][run_scheme]") {
  const core::Model model = testing::free_spin();
  const auto stepper = make_stepper("c1", model, {});
  std::atomic<long> steps{0};
  run_scheme(model, *stepper, 0.01, core::output_times(1.0, 0.1), &steps);
  CHECK(steps.load() == 100);
}

}  // namespace
}  // namespace flexref::lie
