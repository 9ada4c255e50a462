#include "reference/solve_reference.hpp"

#include <catch2/catch.hpp>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

/// A finite reference of free_spin, then one entry spoiled at output row k.
ReferenceRun spoiled(const core::Model& model, std::size_t k, double value, int component) {
  ReferenceRun run = solve_reference("cvode", model, core::output_times(1.0, 0.25), {});
  core::BodyState& s = run.trajectory.states[k][0];
  if (component == 0) s.p_WBr.x() = value;
  if (component == 1) s.theta_WB(2) = value;
  if (component == 2) s.w_WB_B.z() = value;
  return run;
}

TEST_CASE("check_finite names the first output time whose state is not finite",
          "[reference][solve_reference]") {
  const core::Model model = testing::free_spin();
  for (int component = 0; component < 3; ++component) {
    INFO("component " << component);
    const ReferenceRun run = spoiled(model, 2, std::numeric_limits<double>::quiet_NaN(), component);
    try {
      check_finite(run, model);
      FAIL("no exception");
    } catch (const core::SolverError& e) {
      CHECK(e.solver() == "cvode");
      CHECK(e.time() == 0.5);  // output row 2 of 0, 0.25, 0.5, …
      CHECK(std::string(e.what()).find("not finite") != std::string::npos);
      // The step is unknown here: the message must not print a made-up one.
      CHECK(std::string(e.what()).find("(step") == std::string::npos);
    }
  }
}

TEST_CASE("check_finite refuses a finite state whose energy overflows",
          "[reference][solve_reference]") {
  const core::Model model = testing::free_spin();
  // |W| = 1e160 rad/s: ½ Wᵀ J W = 2.5e320 J is inf although every component is finite.
  const ReferenceRun run = spoiled(model, 3, 1e160, 2);
  try {
    check_finite(run, model);
    FAIL("no exception");
  } catch (const core::SolverError& e) {
    CHECK(e.time() == 0.75);
    CHECK(std::string(e.what()).find("energy") != std::string::npos);
  }
  // The untouched run passes.
  CHECK_NOTHROW(check_finite(spoiled(model, 3, 0.1, 2), model));
}

TEST_CASE("check_finite refuses a trajectory with a missing state",
          "[reference][solve_reference]") {
  const core::Model model = testing::free_spin();
  ReferenceRun run = spoiled(model, 0, 0.0, 0);
  run.trajectory.states.pop_back();
  CHECK_THROWS_AS(check_finite(run, model), core::SolverError);
}

}  // namespace
}  // namespace flexref::reference
