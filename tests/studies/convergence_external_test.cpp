/// The convergence study of a method outside the registry (studies/convergence.hpp,
/// ExternalMethod): its files, measured under the trajectory contract, give the numbers a
/// registered scheme gets for the same trajectories; a level that fails fails alone.
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "core/output_times.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "studies/convergence.hpp"
#include "tests/support/test_problems.hpp"
#include "trajectory/trajectory_contract.hpp"

namespace flexref::studies {
namespace {

/// C2's trajectory at step h as another code would hand it over: only t, the Euler
/// parameters and the angular velocity, as columns in memory.
ExternalLevel c2_as_external(const core::Model& model, const std::vector<double>& times, double h) {
  const auto stepper = lie::make_stepper("c2", model, {});
  const trajectory::TrajectoryTable table =
      trajectory::tabulate(model, lie::run_scheme(model, *stepper, h, times));
  std::vector<std::string> names{"t"};
  for (const char* s : {".e0", ".e1", ".e2", ".e3", ".W1", ".W2", ".W3"}) {
    names.push_back("spinner" + std::string(s));
  }
  std::vector<std::vector<double>> columns(names.size());
  for (std::size_t c = 0; c < names.size(); ++c) {
    for (const auto& row : table.rows) {
      columns[c].push_back(row[static_cast<std::size_t>(table.column(names[c]))]);
    }
  }
  return {trajectory::run_from_columns("c2 at h", names, columns), 0.0};
}

TEST_CASE("an external method is studied like a registered scheme", "[studies][convergence]") {
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(2.0, 0.1);
  ConvergenceOptions options;
  options.schemes = {"c2"};
  options.metric = "rotation";  // the external files have no point columns
  options.h0 = 0.02;
  options.levels = 3;
  options.reference_solver = "cvode";
  options.reference_rtol = 1e-12;
  ExternalMethod mine;
  mine.label = "mine";
  mine.claimed_order = 2;
  mine.run = [&](double h, int level) {
    if (level == 3) throw std::runtime_error("the program crashed");
    return c2_as_external(model, times, h);
  };
  mine.steps = {0.005, 0.02, 0.01, 0.0025};  // any order; the study sorts them
  options.external = {mine};
  const ConvergenceResult r = run_convergence(model, times, options);
  REQUIRE(r.levels.size() == 7);
  REQUIRE(r.summaries.size() == 2);
  for (int l = 0; l < 3; ++l) {
    const ConvergenceLevel& a = r.levels[static_cast<std::size_t>(l)];
    const ConvergenceLevel& b = r.levels[static_cast<std::size_t>(3 + l)];
    CHECK(b.scheme == "mine");
    CHECK(b.h == a.h);
    // The same trajectories, measured through the contract: the same numbers, exactly.
    CHECK(b.error == a.error);
    CHECK(b.status == a.status);
  }
  CHECK(r.levels[6].h == 0.0025);
  CHECK_THAT(r.levels[6].status, Catch::Matchers::Contains("failed: the program crashed"));
  CHECK(r.summaries[1].claimed_order == 2);
  CHECK(r.summaries[1].fitted_order == r.summaries[0].fitted_order);
  // The note says what the metric measured in the external files.
  bool noted = false;
  for (const auto& n : r.notes) noted |= n.find("mine: metric rotation over spinner.rotation") == 0;
  CHECK(noted);
}

}  // namespace
}  // namespace flexref::studies
