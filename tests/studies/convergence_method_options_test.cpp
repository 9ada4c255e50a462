/// The convergence study builds its steppers with its own lie::MethodOptions
/// (studies/convergence.hpp, ConvergenceOptions::method_options): a study of genalpha at
/// ρ∞ = 0.5 measures exactly the errors of GenAlphaStepper built directly at 0.5, different
/// from those at 0.9; two studies with different ρ∞ running at the same time in one process
/// each get their own (a process-wide setting could give both the same).
#include <catch2/catch.hpp>
#include <cstddef>
#include <thread>
#include <vector>

#include "core/output_times.hpp"
#include "lie/genalpha.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/run_scheme.hpp"
#include "studies/convergence.hpp"
#include "tests/support/test_problems.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_contract.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::studies {
namespace {

ConvergenceOptions genalpha_study(double rho_inf) {
  ConvergenceOptions options;
  options.schemes = {"genalpha"};
  options.method_options.rho_inf = rho_inf;
  options.h0 = 0.02;
  options.levels = 3;
  options.reference_solver = "cvode";
  options.reference_rtol = 1e-12;
  return options;
}

/// The errors the study measures for each level, recomputed from GenAlphaStepper built
/// directly at rho_inf against the study's own reference (the study's path: tabulate,
/// compare_trajectories, metric_value).
std::vector<double> direct_errors(const core::Model& model, const std::vector<double>& times,
                                  const ConvergenceResult& result, double rho_inf) {
  std::vector<double> errors;
  for (const ConvergenceLevel& level : result.levels) {
    lie::GenAlphaStepper stepper(model, lie::GenAlphaParameters::from_rho_inf(rho_inf));
    const trajectory::TrajectoryTable table =
        trajectory::tabulate(model, lie::run_scheme(model, stepper, level.h, times));
    errors.push_back(trajectory::metric_value(
        trajectory::compare_trajectories(table, result.reference.table), result.options.metric));
  }
  return errors;
}

std::vector<double> study_errors(const ConvergenceResult& result) {
  std::vector<double> errors;
  for (const ConvergenceLevel& level : result.levels) errors.push_back(level.error);
  return errors;
}

TEST_CASE("converge runs genalpha with the study's rho_inf, two studies at once apart",
          "[studies][convergence][options]") {
  // free_spin over [0, 1] at h = 0.02, 0.01, 0.005 (h|W| ≤ 0.04): 350 implicit steps per study
  // and a CVODE reference, a fraction of a second.
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(1.0, 0.1);
  ConvergenceResult damped;
  ConvergenceResult mild;
  std::thread first([&] { damped = run_convergence(model, times, genalpha_study(0.5)); });
  std::thread second([&] { mild = run_convergence(model, times, genalpha_study(0.9)); });
  first.join();
  second.join();
  REQUIRE(damped.levels.size() == 3);
  REQUIRE(mild.levels.size() == 3);
  // Bit for bit: the same stepper on the same model and reference.
  CHECK(study_errors(damped) == direct_errors(model, times, damped, 0.5));
  CHECK(study_errors(mild) == direct_errors(model, times, mild, 0.9));
  for (std::size_t l = 0; l < 3; ++l) {
    INFO("level " << l << ": errors " << damped.levels[l].error << " and " << mild.levels[l].error);
    CHECK(damped.levels[l].error != mild.levels[l].error);
  }
}

}  // namespace
}  // namespace flexref::studies
