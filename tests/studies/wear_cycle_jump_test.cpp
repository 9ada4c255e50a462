/// The multi-scale wear scheme (studies/wear_cycle_jump.hpp) and the wear-jump study
/// (studies/wear_jump.hpp) on pins whose wear has a closed form: two pins under a disk spinning
/// freely about its pivot (about a principal axis, the pins' torques cancelling) rub a plane
/// they penetrate by δ0, frictionless, so each normal force k (δ0 − h) falls as the pin wears
/// and Archard's law gives ḣ = λ (δ0 − h), h(t) = δ0 (1 − e^{−λt}). The windows' dynamics is
/// steady (the spin is), so every window averages the exact rate and the scheme's error is its
/// slow-time integrator's alone: Euler's is O(D), Heun's and AB2's O(D²).
#include "studies/wear_cycle_jump.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "scene/scene_reader.hpp"
#include "studies/observed_order.hpp"
#include "studies/wear_jump.hpp"
#include "studies/wear_output.hpp"

namespace flexref::studies {
namespace {

// λ = β k with β = F k_A |v_t| / (H A) = 1e-5 · 1 / (1e6 · 1e-6) = 1e-5 m/(N·s), |v_t| = 2 rad/s ·
// 0.5 m = 1 m/s, k = 1e4 N/m: λ = 0.1 1/s; δ0 = 1e-4 m. Undamped, so the wear does not change
// the normal force through the damping; no gravity, so the pivot carries nothing else.
const std::string kPinScene =
    "[scene]\n"
    "name = \"pin\"\n"
    "end_time = 10.0\n"
    "output_step = 0.01\n"
    "[[body]]\n"
    "name = \"disk\"\n"
    "motion = \"pivot\"\n"
    "pivot = [0.0, 0.0, 0.0]\n"
    "mass = 1.0\n"
    "inertia = [0.1, 0.1, 0.2]\n"
    "angular_velocity = [0.0, 0.0, 2.0]\n"
    "[[contact]]\n"
    "kind = \"point-plane\"\n"
    "name = \"pin\"\n"
    "body = \"disk\"\n"
    "points = [[0.5, 0.0, -1e-4], [-0.5, 0.0, -1e-4]]\n"
    "law = \"linear\"\n"
    "stiffness = 1e4\n"
    "damping = 0.0\n"
    "wear = { law = \"archard\", coefficient = 1e-5, hardness = 1e6, area = 1e-6 }\n";
constexpr double kLambda = 0.1;    // 1/s
constexpr double kDelta0 = 1e-4;   // m
constexpr double kHorizon = 10.0;  // s

double exact_depth(double t) { return kDelta0 * (1.0 - std::exp(-kLambda * t)); }

CycleJumpOptions pin_options(SlowIntegrator slow, int jumps) {
  CycleJumpOptions o;
  o.window = 0.01;
  o.transient = 0.01;
  o.jump = kHorizon / jumps;
  o.until = kHorizon;
  o.slow = slow;
  o.rtol = 1e-10;
  o.output_step = 0.005;
  return o;
}

}  // namespace

TEST_CASE("cycle jump: each slow-time integrator converges at its order to the closed form") {
  const scene::Scene scene = scene::parse_scene(kPinScene, "pin.toml");
  for (const SlowIntegrator slow :
       {SlowIntegrator::kEuler, SlowIntegrator::kHeun, SlowIntegrator::kAb2}) {
    std::vector<double> jumps, errors;
    for (const int n : {4, 8, 16, 32}) {
      const CycleJumpResult r = run_cycle_jump(scene.spec, pin_options(slow, n));
      REQUIRE(r.jumps == n);
      REQUIRE(r.path.size() == static_cast<std::size_t>(n + 1));
      CHECK(r.path.back().slow_time == kHorizon);
      // Euler and AB2 one window per jump (AB2's first by Heun: two), Heun two.
      const auto jumps_taken = static_cast<std::size_t>(n);
      const std::size_t expected = slow == SlowIntegrator::kHeun  ? 2 * jumps_taken
                                   : slow == SlowIntegrator::kAb2 ? jumps_taken + 1
                                                                  : jumps_taken;
      CHECK(r.windows.size() == expected);
      CHECK(r.fast_time == Approx(0.02 * static_cast<double>(expected)).epsilon(1e-12));
      CHECK(r.regime_changes.empty());
      // The first window's averaged rate is the exact λ δ0 (the windows measure the rate to
      // the solver's tolerance; 1e-7 relative covers rtol 1e-10 over a 0.01 s window).
      CHECK(r.windows.front().rate(0) == Approx(kLambda * kDelta0).epsilon(1e-7));
      jumps.push_back(kHorizon / n);
      errors.push_back(std::abs(r.path.back().depth(0) - exact_depth(kHorizon)) /
                       exact_depth(kHorizon));
    }
    const double order = least_squares_order(jumps, errors, std::vector<bool>(jumps.size(), true));
    INFO(to_string(slow) << ": errors " << errors[0] << " ... " << errors.back() << ", order "
                         << order);
    // λD ≤ 0.25: the integrators are in their asymptotic range; the fit over four halvings lies
    // within 0.15 of the claimed order (measured 1.03 Euler, 2.0 Heun, 2.0 AB2). A rate read at
    // the wrong geometry (a lagged window) or a Heun average of the wrong ends gives order 1.
    CHECK(order == Approx(claimed_order(slow)).margin(0.15));
    CHECK(errors.back() < errors.front());
  }
}

TEST_CASE("cycle jump: the worn geometry of a window and the scene's depth layout") {
  const scene::Scene scene = scene::parse_scene(kPinScene, "pin.toml");
  Eigen::VectorXd h(2);
  h << 3e-5, 3e-5;
  const scene::SceneSpec worn = with_wear_geometry(scene.spec, h, true);
  REQUIRE(worn.contacts[0].wear);
  CHECK(worn.contacts[0].wear->initial_depth == std::vector<double>{3e-5, 3e-5});
  CHECK(worn.contacts[0].wear->geometry_frozen);
  CHECK_THROWS_WITH(with_wear_geometry(scene.spec, Eigen::VectorXd::Zero(3), false),
                    Catch::Contains("more depths"));
  // A window on the frozen worn geometry wears at the rate of that geometry.
  const CycleJumpResult r = run_cycle_jump(scene.spec, pin_options(SlowIntegrator::kEuler, 1));
  CHECK(r.windows.front().rate(0) == Approx(kLambda * kDelta0).epsilon(1e-7));
  const std::string path = wear_path_csv(r);
  CHECK(path.starts_with("slow_time,pin.wear_depth,pin.wear_volume,pin.depth1,pin.depth2\n"));
  const std::string profile = wear_profile_csv(r, r.path.back().depth);
  CHECK(profile.starts_with("contact,index,angle_deg,depth\npin,1,,"));
}

TEST_CASE("cycle jump: a slow path that oscillates without decaying is named unstable") {
  // The linear slow system ḣ = λ h + b integrated by Euler: h_{k+1} − h* = (1 + λD)(h_k − h*),
  // and the rates r_k = λ (h_k − h*) alternate when 1 + λD < 0; |1 + λD| ≥ 1 is Euler's
  // instability (λD ≤ −2), below it the oscillation decays.
  const auto euler_rates = [](double lambda_d) {
    std::vector<Eigen::VectorXd> rates;
    std::vector<double> times;
    double x = 1e-5;  // h_0 − h*, m
    for (int k = 0; k < 8; ++k) {
      rates.push_back(Eigen::VectorXd::Constant(2, -0.1 * x));  // λ = −0.1 1/s
      times.push_back(10.0 * k);
      x *= 1.0 + lambda_d;
    }
    return std::make_pair(rates, times);
  };
  const auto [unstable, t_unstable] = euler_rates(-2.2);
  const std::string named = slow_instability(unstable, t_unstable, 1e-8);
  CHECK_THAT(named, Catch::Contains("jumps 0-3 (t = 0 -> 30 s)"));
  CHECK_THAT(named, Catch::Contains("oscillate without decaying"));
  // At λD = −2 exactly the oscillation neither grows nor decays: the edge is unstable too.
  CHECK_FALSE(slow_instability(euler_rates(-2.0).first, t_unstable, 1e-8).empty());
  CHECK(slow_instability(euler_rates(-1.5).first, t_unstable, 1e-8).empty());  // decays
  CHECK(slow_instability(euler_rates(-0.5).first, t_unstable, 1e-8).empty());  // monotone
  // An alternation below max(1e-3, 100 rtol) of the rate is the windows' noise.
  std::vector<Eigen::VectorXd> noisy;
  for (int k = 0; k < 8; ++k) {
    noisy.push_back(Eigen::VectorXd::Constant(2, 1e-6 * (1.0 + (k % 2 == 0 ? 1e-5 : -1e-5) * k)));
  }
  CHECK(slow_instability(noisy, t_unstable, 1e-8).empty());
  noisy[7](0) += 1e-8;  // a jump of 1 % of the rate: above the noise, but not an oscillation
  CHECK(slow_instability(noisy, t_unstable, 1e-8).empty());
}

TEST_CASE("cycle jump: options out of range and a scene without a wear law are refused") {
  const scene::Scene scene = scene::parse_scene(kPinScene, "pin.toml");
  CycleJumpOptions o = pin_options(SlowIntegrator::kEuler, 4);
  o.window = 0.0;
  CHECK_THROWS_WITH(run_cycle_jump(scene.spec, o), Catch::Contains("window"));
  o = pin_options(SlowIntegrator::kEuler, 4);
  o.jump = -1.0;
  CHECK_THROWS_WITH(run_cycle_jump(scene.spec, o), Catch::Contains("jump"));
  const std::string plain = std::string(kPinScene).replace(
      kPinScene.find("wear = {"), kPinScene.size() - kPinScene.find("wear = {"), "");
  const scene::Scene unworn = scene::parse_scene(plain, "plain.toml");
  CHECK_THROWS_WITH(run_cycle_jump(unworn.spec, pin_options(SlowIntegrator::kEuler, 4)),
                    Catch::Contains("no contact with a wear law"));
  CHECK_THROWS_WITH(parse_slow_integrator("rk4"), Catch::Contains("euler, heun or ab2"));
}

TEST_CASE("wear-jump: the study observes each integrator's order against the coupled reference") {
  const scene::Scene scene = scene::parse_scene(kPinScene, "pin.toml");
  WearJumpOptions o;
  o.jump_counts = {4, 8, 16, 32};
  o.base = pin_options(SlowIntegrator::kEuler, 4);
  const WearJumpResult r = run_wear_jump(scene.spec, o);
  // The coupled reference integrates ḣ = λ (δ0 − h) with the (here static) dynamics.
  // To its tolerance: atol = rtol = 1e-10 m on the depths (SI), 10 atol as the margin (measured
  // 2.8e-11 m).
  CHECK(r.reference_depth(0) == Approx(exact_depth(kHorizon)).margin(1e-9));
  REQUIRE(r.rows.size() == 12);
  for (const WearJumpRow& row : r.rows) {
    INFO(row.slow << " " << row.jumps << ": " << row.status);
    CHECK(row.status == "ok");
    // The error is the profile error of the one depth: the same arithmetic, to round-off.
    CHECK(row.error == Approx(std::abs(row.depth(0) - r.reference_depth(0)) / r.reference_depth(0))
                           .epsilon(1e-15));
    CHECK(row.speedup > 0.0);
  }
  REQUIRE(r.fits.size() == 3);
  for (const WearJumpFit& f : r.fits) {
    INFO(f.slow);
    CHECK(f.levels == 4);
    CHECK(f.reference_levels == 4);
    // As the closed-form case above, over three halvings: within 0.2 of the claimed order,
    // from the distances between levels and from the errors against the reference alike (the
    // windows are steady: the scheme's limit D → 0 is the reference).
    CHECK(f.observed == Approx(f.claimed).margin(0.2));
    CHECK(f.observed_reference == Approx(f.claimed).margin(0.2));
    // That limit, extrapolated from the two finest levels at the observed order p̂, is closer
    // to the reference than the finest level: with errors e = C D^p, extrapolating at p̂
    // leaves |(2^p − 1)/(2^p̂ − 1) − 1| of the finest error, ≤ 0.23 for |p̂ − p| ≤ 0.2 (the
    // margin above), plus the next term, O(λD) ≤ 0.03 of it. An extrapolation of the wrong
    // sign would leave 2 to 1.7 times the finest error.
    double finest = 0.0;
    for (const WearJumpRow& row : r.rows) {
      if (row.slow == f.slow && row.jumps == 32) finest = row.error;
    }
    CHECK(f.limit_error < 0.3 * finest);
  }
  const std::string csv = wear_jump_csv(r);
  CHECK(csv.starts_with("slow,jump,window,error,cpu,speedup,status\n"));
  // Three distances per integrator (four levels), all used.
  const std::string distances = wear_jump_distances_csv(r);
  CHECK(
      distances.starts_with("slow,window,coarse,fine,distance,used,limit_error\neuler,0.01,2.5,"
                            "1.25,"));
  CHECK(std::count(distances.begin(), distances.end(), '\n') == 1 + 3 * 3);
  const std::string text = format_wear_jump(r);
  CHECK_THAT(text, Catch::Contains("  euler claimed 1, observed "));
  CHECK_THAT(text, Catch::EndsWith("  ab2 claimed 2, observed " + [&] {
               char b[16];
               std::snprintf(b, sizeof b, "%.2f", r.fits[2].observed);
               return std::string(b);
             }() + " over 4 levels\n"));
}

}  // namespace flexref::studies
