/// \file high_precision_contact_test.cpp
/// Contact in extended and quad precision (precision/switched_integration.hpp, docs/precision.md
/// "Events"): onsets and releases of the bouncing ball against closed forms computed here
/// independently of the model (free flight, and the Hunt–Crossley impact without gravity by its
/// first integral and a tanh-sinh quadrature). The ordering double < extended < quad on the
/// contact scenes is checked with the other scenes (precision_order.hpp).
#include <algorithm>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/multiprecision/float128.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "contact/contact.hpp"
#include "core/output_times.hpp"
#include "precision/high_precision_reference.hpp"
#include "reference/solve_reference.hpp"
#include "scene/build_model.hpp"
#include "tests/precision/precision_order.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {
namespace {

using Quad = boost::multiprecision::float128;

/// The ball's Hunt–Crossley law as the model builds it (α from the scene's restitution).
contact::NormalLaw ball_law(const scene::SceneSpec& spec) {
  const core::Model model = scene::build_model(spec);
  for (const auto& element : model.elements()) {
    if (const auto* c = dynamic_cast<const contact::ContactElement*>(element.get())) {
      return c->normal_law();
    }
  }
  FAIL("bouncing_ball has no contact");
  return contact::NormalLaw::linear(1.0, 0.0);
}

/// φ(x) = x − ln(1 + x) in quad (|x| ≥ 0.1 here: no cancellation to guard against).
Quad phi(const Quad& x) { return x - boost::multiprecision::log1p(x); }

/// Onset and release of a Hunt–Crossley impact without gravity, in closed form. With the
/// compression rate v = δ̇ and c = αv, m v dv/dδ = −k δⁿ(1 + αv) separates:
///   (m/α²) φ(c) = (m/α²) φ(a) − k δⁿ⁺¹/(n + 1),   a = α v₀   (docs/contact.md),
/// so the release rate is c_r/α with φ(c_r) = φ(a), c_r ∈ (−1, 0), and the contact lasts
///   T = ∫ dt = ∫_{c_r}^{a} m dc / (α k δ(c)ⁿ (1 + c)),  δ(c)ⁿ⁺¹ = m(n + 1)(φ(a) − φ(c))/(α² k).
/// The integrand has integrable endpoint singularities (φ(a) − φ(c) vanishes linearly at both
/// ends, δⁿ like its 0.6th power); each half is integrated in the distance d to its end, with
/// φ(a) − φ(c) formed without cancellation: d − log1p(d/(1 + c)) at c = a − d and
/// −d − log1p(−d/(1 + c)) at c = c_r + d (using φ(c_r) = φ(a)).
struct ImpactClosedForm {
  Quad release_rate;  ///< c_r/α (< 0: the ball leaves)
  Quad duration;      ///< T, s
};

ImpactClosedForm hunt_crossley_impact(const contact::NormalLaw& law, const Quad& mass,
                                      const Quad& v0) {
  const Quad alpha(law.alpha()), k(law.stiffness()), n(law.exponent());
  const Quad a = alpha * v0;
  // φ decreases on (−1, 0) from +∞ to 0: bisection to the last bit (120 halvings of 1).
  Quad lo(-1), hi(0);
  for (int i = 0; i < 200 && hi - lo > 0; ++i) {
    const Quad mid = (lo + hi) / 2;
    if (mid == lo || mid == hi) break;
    (phi(mid) > phi(a) ? lo : hi) = mid;
  }
  const Quad c_r = hi;
  const Quad scale = mass * (n + 1) / (alpha * alpha * k);
  const auto integrand = [&](const Quad& delta_phi, const Quad& c) {
    using boost::multiprecision::pow;
    return mass / (alpha * k * pow(scale * delta_phi, n / (n + 1)) * (1 + c));
  };
  boost::math::quadrature::tanh_sinh<Quad> quadrature;
  const Quad tolerance(1e-30);
  const Quad compression = quadrature.integrate(
      [&](const Quad& d) {
        const Quad c = a - d;
        return integrand(d - boost::multiprecision::log1p(d / (1 + c)), c);
      },
      Quad(0), a, tolerance);
  const Quad restitution = quadrature.integrate(
      [&](const Quad& d) {
        const Quad c = c_r + d;
        return integrand(-d - boost::multiprecision::log1p(-d / (1 + c)), c);
      },
      Quad(0), -c_r, tolerance);
  return {c_r / alpha, compression + restitution};
}

TEST_CASE("quad locates a Hunt-Crossley impact without gravity to its closed form",
          "[precision][contact]") {
  // The bouncing ball thrown down at the law's reference speed with gravity off: onset at
  // h/v₀, release T later (hunt_crossley_impact), leaving at e v₀ with e = 0.5 exactly.
  scene::SceneSpec spec = spec_of("scenes/bouncing_ball.toml");
  spec.g_W.setZero();
  spec.end_time = 0.3;
  const contact::NormalLaw law = ball_law(spec);
  const double v0 = law.reference_speed();
  spec.bodies[0].description.initial.v_WBo = Eigen::Vector3d(0.0, 0.0, -v0);
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  const HighPrecisionRun run = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
  REQUIRE(run.events.size() == 2);
  CHECK(run.events[0].kind == "onset");
  CHECK(run.events[1].kind == "release");

  const Quad h = Quad(1.0) - Quad(0.1);  // the centre's height above the floor minus r
  const Quad onset = h / Quad(v0);
  const ImpactClosedForm exact = hunt_crossley_impact(law, Quad(1.0), Quad(v0));
  const Quad release = onset + exact.duration;
  const Quad t_on(run.events[0].time), t_off(run.events[1].time);
  const Quad vz_off(run.events[1].row[column(run, "ball.vz")]);
  INFO("onset " << t_on << " (off by " << static_cast<double>(t_on - onset) << " s), release "
                << t_off << " (off by " << static_cast<double>(t_off - release) << " s), contact "
                << exact.duration << " s, leaving at " << vz_off << " m/s (off by "
                << static_cast<double>(vz_off + exact.release_rate) << ")");
  // The bound, 1e-20 s: BS at rtol 1e-28 keeps the trajectory to ~1e-27 m over the
  // 10 ms contact, which moves an event by that over the rate 4.2 m/s (~3e-28 s), and the
  // location itself is to 4 ulps of t (~1e-34 s); 1e-20 leaves eight digits of margin and still
  // fails for any modelling error (a sign or a factor in the law moves the release by ms).
  CHECK(static_cast<double>(abs(t_on - onset)) < 1e-20);
  CHECK(static_cast<double>(abs(t_off - release)) < 1e-20);
  // Leaving speed: −c_r/α (e v₀ = 2.101 m/s), to the same trajectory accuracy (1e-27 m/s
  // over 2 m/s): 1e-24 relative.
  CHECK(static_cast<double>(abs(vz_off + exact.release_rate) / abs(exact.release_rate)) < 1e-24);
  CHECK(abs(vz_off / Quad(v0) - Quad(0.5)) < Quad(1e-12));  // e = 0.5 at v_ref (double α)
}

TEST_CASE("quad bouncing ball: every onset follows its release by the free flight",
          "[precision][contact]") {
  // First onset after a drop of h = 0.9 m: √(2h/g). Later onsets: the ball leaves the floor
  // (gap 0) at v_r upward and lands after the parabola's 2 v_r/g.
  const scene::SceneSpec spec = spec_of("scenes/bouncing_ball.toml");
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  const HighPrecisionRun run = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
  REQUIRE(run.events.size() >= 10);
  const Quad g(9.81);
  const Quad h = Quad(1.0) - Quad(0.1);
  using boost::multiprecision::sqrt;
  CHECK(run.events.front().kind == "onset");
  // 1e-20 s as above; the flights are exact parabolas in BS up to rounding.
  CHECK(static_cast<double>(abs(Quad(run.events.front().time) - sqrt(2 * h / g))) < 1e-20);
  const std::size_t vz = column(run, "ball.vz");
  int flights = 0;
  for (std::size_t i = 1; i + 1 < run.events.size(); i += 2) {
    CAPTURE(i);
    REQUIRE(run.events[i].kind == "release");
    REQUIRE(run.events[i + 1].kind == "onset");
    const Quad t_release(run.events[i].time);
    const Quad v_release(run.events[i].row[vz]);
    const Quad landing = t_release + 2 * v_release / g;
    INFO("landing at " << Quad(run.events[i + 1].time) << ", off by "
                       << static_cast<double>(Quad(run.events[i + 1].time) - landing) << " s");
    CHECK(static_cast<double>(abs(Quad(run.events[i + 1].time) - landing)) < 1e-20);
    // The impact speed that ended the flight equals the speed that began it (a parabola),
    // to the trajectory's accuracy (1e-27 m/s over ~1 m/s): 1e-24 relative.
    const Quad v_landing = -Quad(run.events[i + 1].row[vz]);
    CHECK(static_cast<double>(abs(v_landing - v_release) / v_release) < 1e-24);
    // The impact before dissipated energy: the ball leaves slower than it arrived (0 < e < 1;
    // a sign error in the damping would make it leave faster).
    const Quad v_arrival = -Quad(run.events[i - 1].row[vz]);
    CHECK(v_release > Quad(0));
    CHECK(v_release < v_arrival);
    ++flights;
  }
  CHECK(flights >= 5);
}

TEST_CASE("quad carries the double model's contact outputs: energy balance and wear",
          "[precision][contact]") {
  // bouncing_ball: E(t) − E(0) + W_d(t) = 0 with W_d integrated beside the motion. Both terms
  // are ~10 J and kept to rtol 1e-28 (~1e-27 J), so 1e-24 J leaves a factor 1000; a sign error
  // in the dissipated power makes the balance 2 W_d ≈ 17 J.
  // With the contact named, its `impacts` column counts the located onsets.
  {
    scene::SceneSpec spec = spec_of("scenes/bouncing_ball.toml");
    spec.contacts[0].name = "floor";
    const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
    const HighPrecisionRun run = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
    const auto onsets =
        std::count_if(run.events.begin(), run.events.end(),
                      [](const HighPrecisionEvent& e) { return e.kind == "onset"; });
    CHECK(onsets >= 20);
    CHECK(Quad(run.text.back()[column(run, "floor.impacts")]) == Quad(onsets));
    const std::size_t balance = column(run, "energy_balance");
    const std::size_t work = column(run, "dissipated_work");
    Quad worst(0);
    for (const auto& row : run.text) worst = std::max(worst, Quad(abs(Quad(row[balance]))));
    CHECK(static_cast<double>(worst) < 1e-24);
    CHECK(Quad(run.text.back()[work]) > Quad(8));  // ~8.8 J dissipated in 3 s of bouncing
  }
  // The ball dropped 5 cm onto a plane tilted 0.3 rad, bouncing and then sliding down it with
  // friction (μ = 0.3): the plane's unit normal as double stores it (|n| − 1 ~ 1e-16) let
  // friction work along n that W_d does not count, 1.6e-15 J of balance by 0.6 s; normalized
  // again in quad (core/unit_vector_tpl.hpp), the balance closes as above (1e-24 J).
  {
    scene::SceneSpec spec = spec_of("scenes/bouncing_ball.toml");
    const Eigen::Vector3d n_W(std::sin(0.3), 0.0, std::cos(0.3));
    spec.contacts[0].pairs[0].n_W = n_W;
    spec.contacts[0].pairs[0].p_WQ = Eigen::Vector3d(0.0, 0.0, 1.0 - 0.15 / n_W.z());
    spec.contacts[0].friction.mu = 0.3;
    spec.contacts[0].friction.v_reg = 0.01;
    spec.end_time = 0.6;
    const std::vector<double> times = core::output_times(spec.end_time, 0.05);
    const HighPrecisionRun run = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
    const std::size_t balance = column(run, "energy_balance");
    const std::size_t work = column(run, "dissipated_work");
    Quad worst(0);
    for (const auto& row : run.text) worst = std::max(worst, Quad(abs(Quad(row[balance]))));
    INFO("balance " << static_cast<double>(worst) << " J, dissipated " << run.text.back()[work]
                    << " J, events " << run.events.size());
    CHECK(static_cast<double>(worst) < 1e-24);
    CHECK(Quad(run.text.back()[work]) > Quad(0.1));
  }
  // sliding_block with its contact named: the wear channel's columns, as the double model
  // writes them (same names and order), agree with a double reference. CVODE at rtol 1e-10
  // keeps the normal force (~2.4 N per corner) and the wear work (~0.36 J) to ~1e-8; 1e-6
  // relative leaves a factor 100 (extended precision, rtol 1e-16, is far closer than that).
  scene::SceneSpec spec = spec_of("scenes/sliding_block.toml");
  spec.contacts[0].name = "floor";
  spec.end_time = 1.0;
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  const HighPrecisionRun high = solve_high_precision(spec, times, Precision::kExtended, 1e-16);
  const core::Model model = scene::build_model(spec);
  reference::SolverOptions o;
  o.rtol = 1e-10;
  o.atol = 1e-12;
  const trajectory::TrajectoryTable d =
      trajectory::tabulate(model, reference::solve_reference("cvode", model, times, o).trajectory);
  REQUIRE(high.columns == d.columns);
  const auto at_end = [&](const std::string& name) {
    const std::size_t c = column(high, name);
    return std::pair<double, double>{static_cast<double>(Quad(high.text.back()[c])),
                                     d.rows.back()[c + 1]};
  };
  for (const char* name : {"floor.fn", "floor.wear_work", "dissipated_work", "energy"}) {
    CAPTURE(name);
    const auto [precise, rounded] = at_end(name);
    CHECK(std::abs(precise - rounded) <= 1e-6 * std::abs(rounded));
  }
  CHECK(at_end("floor.wear_work").first > 0.1);
}

}  // namespace
}  // namespace flexref::precision
