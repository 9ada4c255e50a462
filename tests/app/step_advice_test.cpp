#include "app/step_advice.hpp"

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "core/force_element.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::app {
namespace {

TEST_CASE("run warns when h|W| exceeds the scheme's measured rotational stability limit",
          "[app][run]") {
  const core::Model model = testing::free_spin();  // |W0| = 2.03 rad/s
  // C2's limit 0.582: h = 0.5 gives h|W| = 1.01 (the paper's Fig. 1 step), h = 1e-3 gives 2e-3.
  const std::string warning = rotational_step_warning(model, "c2", 0.5, model.initial_state(), 0.0);
  CHECK(warning.find("0.582") != std::string::npos);
  CHECK(warning.find("body 'spinner'") != std::string::npos);
  CHECK(rotational_step_warning(model, "c2", 1e-3, model.initial_state(), 0.0).empty());
  // C1's limit 8.96 is not reached at h = 0.5; a method without a measured limit never warns.
  CHECK(rotational_step_warning(model, "c1", 0.5, model.initial_state(), 0.0).empty());
  CHECK(rotational_step_warning(model, "mine", 100.0, model.initial_state(), 0.0).empty());
  // The suggested step: a tenth of the limit over |W| (0.0287 s), rounded down to {1, 2, 5}·10^k
  // on the output grid of 0.1 s: 0.02.
  CHECK(suggested_step(model, "c2", 0.5, {0.0, 0.1, 0.2}, model.initial_state()[0].w_WB_B.norm()) ==
        0.02);
}

TEST_CASE("run advises a smaller step only after a run at it passed", "[app][run]") {
  const core::Model model = testing::free_spin();
  const std::vector<double> times{0.0, 0.1, 0.2};
  const double spin = model.initial_state()[0].w_WB_B.norm();
  // The step it tries first: 0.02 (above).
  const double h = suggested_step(model, "c2", 0.5, times, spin);
  RunAttempt broke;
  broke.quantity = "energy balance";
  broke.change = 0.4;
  broke.time = 0.2;
  std::vector<double> tried;
  SECTION("the smaller step passes: advised, and said to be checked") {
    const std::string advice =
        verified_step_advice(model, "c2", 0.5, times, spin, broke, [&](double dt) {
          tried.push_back(dt);
          RunAttempt a;
          a.passed = true;
          return a;
        });
    CHECK(tried == std::vector<double>{h});
    CHECK_THAT(advice, Catch::Matchers::Contains("use --dt 0.02"));
    CHECK_THAT(advice, Catch::Matchers::Contains("checked: a run at that step passes"));
  }
  SECTION("the change does not shrink with the step: no step advised") {
    const std::string advice =
        verified_step_advice(model, "c2", 0.5, times, spin, broke, [&](double dt) {
          tried.push_back(dt);
          RunAttempt a = broke;
          a.change = 0.39;  // the motion's, not h's
          return a;
        });
    CHECK(tried.size() == 1);
    CHECK_THAT(advice, Catch::Matchers::Contains("a smaller step does not help"));
    CHECK(advice.find("use --dt") == std::string::npos);
  }
  SECTION("a step that fails at the same time: a dead point no smaller step crosses") {
    RunAttempt failed;
    failed.time = 0.15;
    failed.why = "Newton did not converge";
    const std::string advice =
        verified_step_advice(model, "c2", 0.5, times, spin, failed, [&](double dt) {
          tried.push_back(dt);
          RunAttempt a = failed;
          a.time = 0.15 + dt;
          return a;
        });
    CHECK_THAT(advice, Catch::Matchers::Contains("fails at the same time"));
    CHECK(advice.find("use --dt") == std::string::npos);
  }
  SECTION("a change that shrinks but not enough: one more step, then no advice") {
    const std::string advice =
        verified_step_advice(model, "c2", 0.5, times, spin, broke, [&](double dt) {
          tried.push_back(dt);
          RunAttempt a = broke;
          a.change = 0.3 * broke.change;
          return a;
        });
    CHECK(tried.size() == 2);
    CHECK(tried[1] < tried[0]);
    CHECK_THAT(advice, Catch::Matchers::Contains("no smaller step passed"));
  }
}

TEST_CASE("run's stiff-mode warning says what is true for the scheme", "[app][run]") {
  core::PenaltyMode spring;
  spring.label = "spring 'c0'";
  spring.kind = "spring";
  spring.frequency = 100.0;
  spring.step_limit = 0.02;
  CHECK(stiff_mode_warning("c1", 0.02, spring).empty());  // at the limit: no warning
  const std::string c1 = stiff_mode_warning("c1", 0.05, spring);
  CHECK(c1.find("exceeds 2/omega = 0.02 s of spring 'c0' (omega = 100 rad/s, h omega = 5)") !=
        std::string::npos);
  CHECK(c1.find("c1 integrates translation and modes by explicit central differences, unstable "
                "above this step, and spring 'c0' is not resolved") != std::string::npos);
  // genalpha is implicit: before issue 46 its warning spoke of explicit central differences.
  const std::string genalpha = stiff_mode_warning("genalpha", 0.05, spring);
  CHECK(genalpha.find("genalpha is implicit and stays stable, but spring 'c0' is not resolved") !=
        std::string::npos);
  CHECK(genalpha.find("central differences") == std::string::npos);
  CHECK(stiff_mode_warning("mine", 0.05, spring).find("does not know whether mine is explicit") !=
        std::string::npos);
  core::PenaltyMode beam = spring;
  beam.label = "beam";
  beam.kind = "flexible body";
  CHECK(stiff_mode_warning("nmb", 0.05, beam)
            .find("the highest modes of flexible body beam are "
                  "not resolved") != std::string::npos);
}

}  // namespace
}  // namespace flexref::app
