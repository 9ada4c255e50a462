#include "app/step_advice.hpp"

#include <catch2/catch.hpp>
#include <string>

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

}  // namespace
}  // namespace flexref::app
