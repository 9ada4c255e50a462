/// The options a method's factory receives (lie/method_options.hpp, lie/method_registry.hpp):
/// genalpha's ρ∞ and perturbed start reach the stepper make_stepper builds (its steps equal a
/// GenAlphaStepper built directly with them, and differ from the defaults'), a ρ∞ outside
/// [0, 1] is refused naming it, and a user method's named values reach its factory while a
/// name no scheme declares is refused.
#include "lie/method_options.hpp"

#include <catch2/catch.hpp>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "lie/genalpha.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/method_registry.hpp"
#include "lie/stepper.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::lie {
namespace {

/// The state after `steps` steps of h from the model's initial state.
core::State options_final_state(Stepper& stepper, const core::Model& model, int steps, double h) {
  stepper.initialize(0.0, model.initial_state());
  for (int k = 0; k < steps; ++k) REQUIRE(stepper.step(h).ok);
  return stepper.state();
}

bool options_same_state(const core::State& a, const core::State& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].p_WBr != b[i].p_WBr || a[i].theta_WB != b[i].theta_WB || a[i].v_WBr != b[i].v_WBr ||
        a[i].w_WB_B != b[i].w_WB_B) {
      return false;
    }
  }
  return true;
}

TEST_CASE("genalpha's options reach the stepper make_stepper builds", "[lie][options]") {
  // heavy_top at h = 2e-3 (h|W| = 0.3): 50 steps, long enough for the damping ρ∞ sets and the
  // start to leave their mark in every bit of the state, short enough to cost milliseconds.
  const core::Model model = testing::heavy_top();
  const int steps = 50;
  const double h = 2e-3;
  for (const bool perturbed : {false, true}) {
    for (const double rho : {0.5, 0.9}) {
      INFO("rho_inf " << rho << ", perturbed start " << perturbed);
      MethodOptions options;
      options.rho_inf = rho;
      options.perturbed_start = perturbed;
      const auto registered = make_stepper("genalpha", model, options);
      GenAlphaParameters parameters = GenAlphaParameters::from_rho_inf(rho);
      parameters.perturbed_start = perturbed;
      GenAlphaStepper direct(model, parameters);
      // The same scheme with the same coefficients: the same floating-point operations.
      CHECK(options_same_state(options_final_state(*registered, model, steps, h),
                               options_final_state(direct, model, steps, h)));
    }
  }
  // Each option changes the result: a factory that dropped one would pass the check above only
  // by building the defaults, which these comparisons tell apart.
  MethodOptions defaults;
  MethodOptions damped;
  damped.rho_inf = 0.5;
  MethodOptions perturbed;
  perturbed.perturbed_start = true;
  const core::State s_default =
      options_final_state(*make_stepper("genalpha", model, defaults), model, steps, h);
  CHECK_FALSE(options_same_state(
      s_default, options_final_state(*make_stepper("genalpha", model, damped), model, steps, h)));
  CHECK_FALSE(options_same_state(
      s_default,
      options_final_state(*make_stepper("genalpha", model, perturbed), model, steps, h)));
  CHECK(defaults.rho_inf == kDefaultRhoInfinity);
  CHECK_FALSE(defaults.perturbed_start);
}

TEST_CASE("genalpha's factory refuses a rho_inf outside [0, 1], naming it", "[lie][options]") {
  const core::Model model = testing::free_spin();
  for (const double bad : {-0.1, 1.5}) {
    MethodOptions options;
    options.rho_inf = bad;
    CHECK_THROWS_WITH(make_stepper("genalpha", model, options),
                      Catch::Matchers::Contains("rho_inf"));
    // The schemes that do not read it build as before.
    CHECK(make_stepper("c2", model, options) != nullptr);
  }
}

/// The value of "gain" the probe method's factory saw last (NaN before any).
double& probe_gain_seen() {
  static double seen = std::numeric_limits<double>::quiet_NaN();
  return seen;
}

/// A user method that declares the option "gain" and steps as C2 (registered once).
void register_options_probe() {
  static const bool registered = [] {
    register_method({"options_probe",
                     2,
                     "C2 that records its option 'gain' (test)",
                     [](const core::Model& m, const MethodOptions& options) {
                       probe_gain_seen() = options.value("gain", -1.0);
                       return make_stepper("c2", m, options);
                     },
                     false,
                     {"gain"}});
    return true;
  }();
  REQUIRE(registered);
}

TEST_CASE("a user method's named options reach its factory, and undeclared names are refused",
          "[lie][options]") {
  register_options_probe();
  const core::Model model = testing::free_spin();
  MethodOptions options;
  options.values["gain"] = 0.25;
  (void)make_stepper("options_probe", model, options);
  CHECK(probe_gain_seen() == 0.25);
  (void)make_stepper("options_probe", model, {});
  CHECK(probe_gain_seen() == -1.0);  // the fallback of MethodOptions::value

  // Read by the probe, so a study of {c2, options_probe} accepts it; c2 alone does not read it.
  CHECK_NOTHROW(check_method_options(options, {"c2", "options_probe"}));
  CHECK_THROWS_WITH(
      check_method_options(options, {"c2", "nmb"}),
      Catch::Matchers::Contains("method option 'gain'") && Catch::Matchers::Contains("c2, nmb"));
  MethodOptions misspelt;
  misspelt.values["gian"] = 0.25;
  CHECK_THROWS_WITH(check_method_options(misspelt, {"options_probe"}),
                    Catch::Matchers::Contains("'gian'"));
  // genalpha's options are named fields, checked by its factory, not by this rule.
  MethodOptions genalpha;
  genalpha.rho_inf = 0.5;
  CHECK_NOTHROW(check_method_options(genalpha, {"c2"}));
}

}  // namespace
}  // namespace flexref::lie
