#include "lie/run_scheme.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "lie/scheme_support.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::lie {
namespace {

std::string invalid_argument_message(const core::Model& model, double dt,
                                     const std::vector<double>& times) {
  const auto stepper = make_stepper("c2", model);
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

TEST_CASE("run_scheme requires load discontinuities inside (t0, t_end] on the grid",
          "[lie][run_scheme]") {
  const core::Model model = testing::book_toss_step();  // switches at 0 and 0.1
  // 0.3 = 4 × 0.075, but 0.1 is not a multiple of 0.075.
  const std::string message = invalid_argument_message(model, 0.075, {0.0, 0.3});
  CHECK(message.find("load discontinuity t = 0.1") != std::string::npos);
  CHECK(message.find("dt = 0.075") != std::string::npos);
  // Outside (t0, t_end] the discontinuities do not constrain the step.
  const auto stepper = make_stepper("c2", model);
  CHECK_NOTHROW(run_scheme(model, *stepper, 0.0075, {0.0, 0.03}));
}

TEST_CASE("run_scheme steps on t0 + n dt and records the output times", "[lie][run_scheme]") {
  const core::Model model = testing::book_toss();
  const double t0 = 0.3;
  const double dt = 0.01;
  const std::vector<double> times{t0, 0.5, 0.55, 1.3};
  for (const std::string& name : scheme_names()) {
    DYNAMIC_SECTION("scheme " << name) {
      const auto stepper = make_stepper(name, model);
      const core::Trajectory run = run_scheme(model, *stepper, dt, times);
      CHECK(run.times == times);
      REQUIRE(run.states.size() == times.size());
      CHECK(run.states[0][0].w_WB_B == model.initial_state()[0].w_WB_B);
      // The clock is t0 + n·dt by multiplication, never accumulated: exact at the end.
      CHECK(stepper->time() == t0 + 100.0 * dt);
      // The same steps taken by hand give the same recorded states.
      const auto manual = make_stepper(name, model);
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
