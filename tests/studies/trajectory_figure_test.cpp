#include "studies/trajectory_figure.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::studies {
namespace {

TEST_CASE("trajectory figure: curves, errors of order 2, parallel = serial", "[studies][figure]") {
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(5.0, 0.1);
  FigureSettings settings;
  settings.steps = {0.02, 0.01};
  settings.rtol = 1e-12;
  const FigureResult serial = run_trajectory_figure(model, times, settings);
  REQUIRE(serial.reference.times.size() == times.size());
  REQUIRE(serial.curves.size() == 6);
  for (std::size_t s = 0; s < 3; ++s) {
    const FigureCurve& coarse = serial.curves[2 * s];
    const FigureCurve& fine = serial.curves[2 * s + 1];
    INFO(coarse.label << ": " << coarse.max_error << " -> " << fine.label << ": "
                      << fine.max_error);
    CHECK(coarse.completed);
    // A curve is recorded on the output grid: every 0.1 s, 51 points.
    CHECK(coarse.times.size() == times.size());
    CHECK(fine.times.size() == times.size());
    // Second order: halving h divides the L∞ point error by 4 (two-sided, ±0.3 in log2).
    const double ratio = coarse.max_error / fine.max_error;
    CHECK(ratio > std::pow(2.0, 1.7));
    CHECK(ratio < std::pow(2.0, 2.3));
  }
  settings.jobs = 2;
  const FigureResult parallel = run_trajectory_figure(model, times, settings);
  for (std::size_t k = 0; k < serial.curves.size(); ++k) {
    CHECK(parallel.curves[k].max_error == serial.curves[k].max_error);
  }
  const std::string csv = figure_csv(serial);
  CHECK(csv.rfind("curve,scheme,step,t,x,y,z\n", 0) == 0);
  CHECK(figure_table(serial).find("completed") != std::string::npos);
}

TEST_CASE("trajectory figure: a failing run keeps its curve and says why", "[studies][figure]") {
  // free_spin has |W| = 2.03 rad/s; C1's Newton iteration fails beyond h|W| ≈ 9
  // (docs/schemes.md, stability): at h = 10 s (h|W| ≈ 20) the first step fails.
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(20.0, 0.1);
  FigureSettings settings;
  settings.steps = {10.0};
  settings.schemes = {"c1"};
  const FigureResult result = run_trajectory_figure(model, times, settings);
  REQUIRE(result.curves.size() == 1);
  const FigureCurve& c = result.curves.front();
  CHECK_FALSE(c.completed);
  CHECK(c.failure.find("stopped at t = 0") != std::string::npos);
  CHECK(c.failure.find("Newton") != std::string::npos);
  CHECK(c.times.size() == 1);  // the initial point only
  CHECK(figure_table(result).find("stopped at") != std::string::npos);
}

TEST_CASE("trajectory figure: curves below 100x the reference's error are not certified",
          "[studies][figure]") {
  // free_spin has an exact solution: the reference's estimate is its distance to it. At a
  // loose tolerance (1e-6) the estimate is large (~1e-5 m), so the fine curves (errors ~1e-5 …
  // 1e-4 m at h = 0.01) fall below 100× it and are marked; at 1e-12 every curve is certified.
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(5.0, 0.1);
  FigureSettings settings;
  settings.steps = {0.2, 0.01};
  settings.rtol = 1e-6;
  const FigureResult loose = run_trajectory_figure(model, times, settings);
  INFO("reference estimate " << loose.reference_estimate);
  REQUIRE(std::isfinite(loose.reference_estimate));
  CHECK(loose.reference_estimate > 0.0);
  bool any_uncertified = false;
  for (const FigureCurve& c : loose.curves) {
    INFO(c.label << ": " << c.max_error);
    CHECK(c.certified == (c.max_error >= 100.0 * loose.reference_estimate));
    any_uncertified = any_uncertified || !c.certified;
  }
  CHECK(any_uncertified);
  CHECK(figure_has_uncertified(loose));
  CHECK(figure_table(loose).find("NO") != std::string::npos);
  settings.rtol = 1e-12;
  const FigureResult tight = run_trajectory_figure(model, times, settings);
  CHECK_FALSE(figure_has_uncertified(tight));
  CHECK(figure_table(tight).find("in double precision, estimated error") != std::string::npos);
}

TEST_CASE("trajectory figure: bad settings are refused", "[studies][figure]") {
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(1.0, 0.1);
  FigureSettings settings;
  settings.steps = {0.3};  // does not divide 1 s
  CHECK_THROWS_AS(run_trajectory_figure(model, times, settings), std::invalid_argument);
  settings.steps = {0.1};
  settings.point = 5;
  CHECK_THROWS_AS(run_trajectory_figure(model, times, settings), std::invalid_argument);
  settings.point = 0;
  settings.schemes = {"rk4"};
  CHECK_THROWS_AS(run_trajectory_figure(model, times, settings), std::invalid_argument);
}

TEST_CASE("trajectory figure: the table's scheme column fits the longest name",
          "[studies][figure]") {
  FigureResult result;
  result.reference.label = "reference (cvode)";
  for (const char* scheme : {"c2", "genalpha"}) {
    FigureCurve curve;
    curve.scheme = scheme;
    curve.step = 0.01;
    curve.max_error = 1.5e-7;
    result.curves.push_back(curve);
  }
  const std::string table = figure_table(result);
  // "genalpha" is 8 characters: two spaces before its step, and c2's row aligned with it.
  CHECK(table.find("\ngenalpha  0.01") != std::string::npos);
  CHECK(table.find("\nc2        0.01") != std::string::npos);
  CHECK(table.find("\nscheme    step") != std::string::npos);
}

}  // namespace
}  // namespace flexref::studies
