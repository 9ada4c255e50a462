#include "app/genalpha_step.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "core/output_times.hpp"
#include "lie/genalpha.hpp"
#include "lie/genalpha_parameters.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::app {
namespace {

/// A body of 1 kg on a [[spring]] to the ground (k = 1 N/m, rest length 1 m), 0.1 m beyond its
/// rest length along x: x'' = −(x − 1), ω = 1 rad/s, the line through the centre of mass (no
/// rotation): the undamped linear oscillator of the period error.
constexpr const char* kSpringOscillator = R"(
[scene]
name = "spring_oscillator"
end_time = 1.0
output_step = 0.1

[[body]]
name = "m"
mass = 1.0
inertia = [1.0, 1.0, 1.0]
position = [1.1, 0.0, 0.0]

[[spring]]
body_a = "m"
point_a = [0.0, 0.0, 0.0]
body_b = "ground"
point_b = [0.0, 0.0, 0.0]
stiffness = 1.0
rest_length = 1.0
)";

TEST_CASE("genalpha's period error on a linear oscillator is c(rho_inf) (h omega)^2",
          "[app][genalpha]") {
  const scene::Scene s = scene::parse_scene(kSpringOscillator, "oscillator.toml");
  const double h = 0.1;  // h ω = 0.1
  for (const double rho_inf : {0.0, 0.5, 0.9, 1.0}) {
    CAPTURE(rho_inf);
    lie::GenAlphaStepper stepper(*s.model, lie::GenAlphaParameters::from_rho_inf(rho_inf));
    stepper.initialize(0.0, s.model->initial_state());
    // 200 steps first: the spurious root of the one-step map (|λ| ≤ 0.73 at ρ∞ = 0.9, 0 or
    // not excited at the others) is then below 1e-27 of its start.
    std::vector<double> y;
    for (int n = 0; n < 400; ++n) {
      REQUIRE(stepper.step(h).ok);
      if (n >= 200) y.push_back(stepper.state()[0].p_WBr.x() - 1.0);
    }
    // The two remaining roots e^{±iθ} make y_{n+1} + y_{n−1} = 2 cos θ y_n: least squares for
    // cos θ, θ = h ω̄ the numerical frequency, ΔT/T = ω/ω̄ − 1.
    double num = 0.0;
    double den = 0.0;
    for (std::size_t n = 1; n + 1 < y.size(); ++n) {
      num += y[n] * (y[n + 1] + y[n - 1]);
      den += 2.0 * y[n] * y[n];
    }
    const double theta = std::acos(num / den);
    const double period_error = h / theta - 1.0;
    const double expected = genalpha_period_error_coefficient(rho_inf) * h * h;
    // The next term of the expansion is O((h ω)²) relative to this one: at h ω = 0.1 it is 1.8 %
    // for ρ∞ = 0 and below 0.2 % for the others (the eigenvalues of the one-step map), so 3 %.
    // The coefficient's second term, 3/8 ((1 − ρ∞)/(1 + ρ∞))², is 82 % of c at ρ∞ = 0 and 33 %
    // at ρ∞ = 0.5: leaving it out fails there.
    CHECK(period_error == Approx(expected).epsilon(0.03));
  }
  // The bound the advice uses at the default ρ∞ = 0.9: h ω ≤ 0.344 for a 1 % period error.
  CHECK(std::sqrt(kGenalphaPeriodError / genalpha_period_error_coefficient(0.9)) ==
        Approx(0.3443).epsilon(1e-4));  // 4 digits of √(0.01/0.08437)
}

/// A compound pendulum at rest at the bottom on an ideal revolute joint about z: mass 2 kg, its
/// centre of mass 0.5 m below the pivot, I_c = 0.1 kg·m²; I_O = 0.1 + 2·0.5² = 0.6 kg·m², small
/// oscillations at ω = √(m g d / I_O) = √(2·9.81·0.5/0.6) rad/s. At rest with no spring, drive or
/// contact, only the motion linearized on the joint gives a rate.
constexpr const char* kPendulum = R"(
[scene]
name = "compound_pendulum"
end_time = 1.0
output_step = 0.1
gravity = [0.0, -9.81, 0.0]

[[body]]
name = "rod"
mass = 2.0
inertia = [0.1, 0.1, 0.1]
center_of_mass = [0.0, -0.5, 0.0]

[[joint]]
name = "pivot"
model = "ideal"
kind = "revolute"
body_a = "rod"
point_a = [0.0, 0.0, 0.0]
body_b = "ground"
point_b = [0.0, 0.0, 0.0]
axis_a = [0.0, 0.0, 1.0]
axis_b = [0.0, 0.0, 1.0]
)";

TEST_CASE("genalpha's step advice resolves a pendulum on its joint at rest", "[app][genalpha]") {
  const scene::Scene s = scene::parse_scene(kPendulum, "pendulum.toml");
  const std::vector<double> times = core::output_times(s.end_time, s.output_step);
  const GenalphaStepAdvice advice = genalpha_step_advice(*s.model, times, 0.9);
  const double omega = std::sqrt(2.0 * 9.81 * 0.5 / 0.6);
  CAPTURE(advice.what);
  // The rate is an eigenvalue of a forward-difference Jacobian (step √ε·max(1, |y|): error
  // ~ √ε·|f''|/|f'| ≈ 1e-8 relative here); 1e-6 leaves a wide margin.
  CHECK(advice.rate == Approx(omega).epsilon(1e-6));
  CHECK(advice.what.find("linearized") != std::string::npos);
  const double bound = std::sqrt(0.01 / genalpha_period_error_coefficient(0.9)) / omega;
  CHECK(advice.bound == Approx(bound).epsilon(1e-6));  // the rate's tolerance
  // 0.344/4.04 = 0.0851 s: the largest {1, 2, 5}·10^k below it that divides the output step 0.1.
  CHECK(advice.step == 0.05);
}

TEST_CASE("genalpha's step advice: a spring's frequency and a drive's rate", "[app][genalpha]") {
  SECTION("the spring oscillator: omega = sqrt(k/m) of spring[1]") {
    const scene::Scene s = scene::parse_scene(kSpringOscillator, "oscillator.toml");
    const GenalphaStepAdvice advice =
        genalpha_step_advice(*s.model, core::output_times(s.end_time, s.output_step), 0.9);
    CAPTURE(advice.what);
    CHECK(advice.rate == Approx(1.0).epsilon(1e-6));  // the Jacobian's rate agrees to 1e-8
    CHECK(advice.step == 0.1);  // 0.344 s, but no step may exceed the output step 0.1 s
  }
  SECTION("a revolute drive at 300 rad/s sets the rate of a body that starts at rest") {
    const std::string axis = "axis_b = [0.0, 0.0, 1.0]\n";
    std::string text = kPendulum;
    text.replace(text.find(axis), axis.size(),
                 axis + "drive = { law = \"spin-up\", rate = 300.0, spin_up_time = 0.5 }\n");
    const scene::Scene s = scene::parse_scene(text, "driven.toml");
    const GenalphaStepAdvice advice =
        genalpha_step_advice(*s.model, core::output_times(s.end_time, s.output_step), 0.9);
    CHECK(advice.rate == 300.0);
    CHECK(advice.what == "the rate of the drive of joint 'pivot'");
    // 0.344/300 = 1.15e-3 s: 1e-3 on the grid of 0.1 s.
    CHECK(advice.step == 1e-3);
  }
}

}  // namespace
}  // namespace flexref::app
