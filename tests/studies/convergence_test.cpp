#include "studies/convergence.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::studies {
namespace {

/// One scheme's levels h0, h0/2, … with the given errors, all "ok" before classification.
ConvergenceResult levels(const std::vector<double>& errors, double h0, double step_limit,
                         double reference_estimate) {
  ConvergenceResult r;
  r.options.schemes = {"nmb"};
  r.options.h0 = h0;
  r.options.levels = static_cast<int>(errors.size());
  r.step_limit.h = step_limit;
  r.step_limit.what = "contact[1]";
  r.reference.estimate.value = reference_estimate;
  for (std::size_t l = 0; l < errors.size(); ++l) {
    r.levels.push_back(ConvergenceLevel{.scheme = "nmb",
                                        .h = h0 / std::ldexp(1.0, static_cast<int>(l)),
                                        .error = errors[l],
                                        .status = "ok"});
  }
  r.summaries.push_back(
      summarize_levels("nmb", 2, r.levels, reference_estimate, r.step_limit, r.notes));
  return r;
}

bool has_note(const ConvergenceResult& r, const std::string& fragment) {
  for (const std::string& n : r.notes) {
    if (n.find(fragment) != std::string::npos) return true;
  }
  return false;
}

TEST_CASE("converge leaves levels above the explicit step limit out of the fit",
          "[studies][convergence]") {
  // The measured NMB errors of `converge scenes/bouncing_ball.toml --levels 5`:
  // h = 1e-2 and 5e-3 lie above the contact's limit 2/ω = 4.77e-3 s. Fitted over all five
  // levels they gave "observed 3.42"; only the three stable levels may enter the fit.
  const ConvergenceResult r = levels({312.6, 1.447, 0.1488, 0.04563, 0.01266}, 1e-2, 4.77e-3, 3e-8);
  CHECK(r.levels[0].status == "above step limit");
  CHECK(r.levels[1].status == "above step limit");
  CHECK(r.levels[2].status == "ok");
  CHECK(r.levels[4].status == "ok");
  REQUIRE(r.summaries.size() == 1);
  CHECK(r.summaries[0].fitted_levels == 3);
  // Least squares over log2 ratios 1.705 and 1.850 of the three levels: their mean, 1.78.
  CHECK(r.summaries[0].fitted_order == Approx(1.777).margin(0.005));
  CHECK(has_note(r, "2 levels above the explicit step limit"));
  CHECK_FALSE(r.refused());
}

TEST_CASE("converge refuses to fit an order from fewer than three valid levels",
          "[studies][convergence]") {
  // Two stable levels: two points always lie on a line, their "order" verifies nothing.
  const ConvergenceResult r = levels({312.6, 1.447, 0.1488, 0.04563}, 1e-2, 4.77e-3, 3e-8);
  CHECK(r.summaries[0].fitted_levels == 2);
  CHECK(std::isnan(r.summaries[0].fitted_order));
  CHECK(r.refused());
  CHECK(has_note(r, "refused to fit an order from 2 valid levels"));
}

TEST_CASE("converge leaves levels whose error does not decrease out of the fit",
          "[studies][convergence]") {
  // Second order down to 2.5e-4, then an error that grows: not in the asymptotic range.
  const ConvergenceResult r = levels({4e-2, 1e-2, 2.5e-3, 6.25e-4, 7e-4}, 1e-2,
                                     std::numeric_limits<double>::infinity(), 1e-12);
  CHECK(r.levels[4].status == "not decreasing");
  CHECK(r.summaries[0].fitted_levels == 4);
  CHECK(r.summaries[0].fitted_order == Approx(2.0).margin(1e-12));
  CHECK(has_note(r, "does not decrease"));
  // A level equal to the previous one does not decrease either.
  const ConvergenceResult flat = levels({4e-2, 1e-2, 1e-2, 2.5e-3}, 1e-2, 1.0, 1e-12);
  CHECK(flat.levels[2].status == "not decreasing");
  CHECK(flat.levels[3].status == "ok");
}

TEST_CASE("converge refuses bad inputs before computing the reference", "[studies][convergence]") {
  const std::vector<double> times = core::output_times(1.0, 0.01);
  ConvergenceOptions options;
  options.h0 = 0.003;  // not a divisor of the output step 0.01
  options.levels = 3;
  try {
    check_convergence_inputs(testing::free_spin(), times, options);
    FAIL("no exception");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("level 1 (h = 0.003)") != std::string::npos);
  }
  options.h0 = 0.01;
  options.levels = 2;
  CHECK_THROWS_AS(check_convergence_inputs(testing::free_spin(), times, options),
                  std::invalid_argument);
  // The schemes refuse the coupled model of a flexible body: before any reference solve.
  options.levels = 3;
  const core::Model coupled = testing::flexible_spinner_model(core::FlexibleFormulation::kCoupled);
  CHECK_THROWS_AS(check_convergence_inputs(coupled, times, options), std::invalid_argument);
  CHECK_NOTHROW(check_convergence_inputs(
      testing::flexible_spinner_model(core::FlexibleFormulation::kLte), times, options));
}

}  // namespace
}  // namespace flexref::studies
