/// \file exact_high_precision_test.cpp
/// The exact solutions (torque-free body, Lagrange top, compound pendulum) evaluated in quad and
/// extended precision (precision/exact_high_precision.hpp) against the quad Bulirsch–Stoer
/// reference, against the double exact solution, and against a sign error.
#include "precision/exact_high_precision.hpp"

#include <boost/multiprecision/float128.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "precision/high_precision_reference.hpp"
#include "reference/exact_solution.hpp"
#include "reference/exact_torque_free.hpp"
#include "scene/build_model.hpp"
#include "tests/precision/precision_order.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {
namespace {

constexpr const char* kMetric = "rotation+points";

/// distance(a, b) in the runs' precision over the solution's size (π + the largest point
/// distance from the origin, trajectory::solution_scale).
double relative_distance(const HighPrecisionRun& a, const HighPrecisionRun& b) {
  return distance(a, b, kMetric) / trajectory::solution_scale(a.table, kMetric);
}

scene::SceneSpec shortened(const std::string& file, double end_time) {
  scene::SceneSpec spec = spec_of(file);
  spec.end_time = std::min(spec.end_time, end_time);
  return spec;
}

/// book_toss's book (J = diag(1, 2, 2.8)) spun about its middle axis without the torque pulse,
/// with a small transverse rate instead: torque-free, close to the separatrix.
scene::SceneSpec free_book(double end_time, double transverse) {
  scene::SceneSpec spec = shortened("scenes/book_toss.toml", end_time);
  spec.loads.clear();
  spec.bodies[0].description.initial.w_WB_B = Eigen::Vector3d(transverse, 10.0, transverse);
  return spec;
}

using Quad = boost::multiprecision::float128;

TEST_CASE("the elliptic routines hold their identities in quad", "[precision][exact]") {
  // The generic AGM and Carlson forms instantiated in float128 (ε = 1.9e-34), down to
  // k' = 1e-20 (a separatrix distance double cannot represent next to k = 1). Identities
  // sn² + cn² = 1 and dn² = cn² + k'² sn²: a few roundings, 16 ε. Inversion F(am(u)) = u: one
  // AGM and one R_F, each a few ε relative, 64 ε·max(1, |u|)/dn (F is ill-conditioned in the
  // amplitude where dn is small, near u = K as k' → 0). Derivative sn' = cn dn by
  // central differences with h = 1e-11: truncation h² |sn⁽³⁾|/6 ≤ 1e-22 (|sn⁽³⁾| ≤ 5),
  // round-off ε/h = 2e-23; bound 1e-21. Asymptote K = ln(4/k') + O(k'² ln(1/k')): below
  // 1e-38 at k' = 1e-20, so the bound is the routine's own 16 ε.
  namespace elliptic = reference::elliptic;
  const Quad eps = std::numeric_limits<Quad>::epsilon();
  for (const Quad& k_prime : {Quad(0.6), Quad(1e-3), Quad(1e-9), Quad(1e-20)}) {
    CAPTURE(static_cast<double>(k_prime));
    const Quad k = sqrt((Quad(1) - k_prime) * (Quad(1) + k_prime));
    const Quad quarter = elliptic::complete_k<Quad>(k_prime);
    if (k_prime < Quad(1e-15)) {
      CHECK(static_cast<double>(abs(quarter - log(Quad(4) / k_prime))) <=
            static_cast<double>(16 * eps * quarter));
    }
    for (const double fraction : {-0.9, -0.3, 0.05, 0.7, 0.99}) {
      const Quad u = Quad(fraction) * quarter;
      const elliptic::JacobiValuesTpl<Quad> f = elliptic::jacobi<Quad>(u, k, k_prime);
      CHECK(static_cast<double>(abs(f.sn * f.sn + f.cn * f.cn - 1)) <=
            static_cast<double>(16 * eps));
      CHECK(static_cast<double>(abs(f.dn * f.dn - f.cn * f.cn - k_prime * k_prime * f.sn * f.sn)) <=
            static_cast<double>(16 * eps));
      const Quad back = elliptic::incomplete_f<Quad>(f.sn, f.cn, k_prime);
      // In units of ε; the amplitude's rounding reaches u divided by dn (dF/dam = 1/dn).
      CHECK(static_cast<double>(abs(back - u) * f.dn / eps) <=
            64 * std::max(1.0, static_cast<double>(abs(u))));
      const Quad h(1e-11);
      const Quad slope = (elliptic::jacobi<Quad>(u + h, k, k_prime).sn -
                          elliptic::jacobi<Quad>(u - h, k, k_prime).sn) /
                         (2 * h);
      CHECK(static_cast<double>(abs(slope - f.cn * f.dn)) <= 1e-21);
    }
  }
}

std::vector<double> times_of(const scene::SceneSpec& spec) {
  return core::output_times(spec.end_time, spec.output_step);
}

// Measured (relative distances in rotation+points, this file's scenes and horizons):
//                        quad exact vs quad BS   extended exact vs quad exact   double exact
//   free_spin (20 s)     4.4e-30                 3.9e-18                        5.9e-15
//   heavy_top (2 s)      1.4e-28 (3.2e-29 at     1.2e-17                        2.1e-14
//                        BS rtol 1e-30)
//   free book (10 s)     5.7e-26 (7.1e-26 at     1.1e-17                        1.7e-14
//                        BS rtol 1e-30)
// The extended exact solutions are within ~200 ulp (u = 5.4e-20) of quad on every scene, so
// the closed forms are well conditioned in their data; the quad distances are the
// Bulirsch–Stoer reference's errors (they shrink with its rtol on the heavy top).

TEST_CASE("quad exact solutions agree with the quad Bulirsch-Stoer reference",
          "[precision][exact]") {
  // The required bound for quad: 1e-25 relative (docs/precision.md). Bulirsch–Stoer at rtol 1e-28
  // over 200 outputs leaves 1000× for its global error growth; the exact solution's own error is
  // ~ε_quad × the ~200 ulp seen in extended, 2e-32, far below. Measured 4.4e-30, 1.4e-28 and, for
  // the compound pendulum released horizontal, 9.1e-28 absolute over 10 s (≈ 2e-28 relative).
  for (const char* file :
       {"scenes/free_spin.toml", "scenes/heavy_top.toml", "scenes/pendulum.toml"}) {
    CAPTURE(file);
    const scene::SceneSpec spec = shortened(file, 20.0);
    const std::vector<double> times = times_of(spec);
    const HighPrecisionRun exact = exact_high_precision(spec, times, Precision::kQuad);
    const HighPrecisionRun integrated = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
    REQUIRE(exact.columns == integrated.columns);
    CHECK(relative_distance(exact, integrated) <= 1e-25);
  }
}

TEST_CASE("extended exact solutions agree with quad to 1e-15", "[precision][exact]") {
  // The required bound for extended: 1e-15 relative, i.e. 2e4 u_ext; the closed forms are
  // measured ~200 u_ext from quad (1.2e-17 worst), and extended's Bulirsch–Stoer at its default
  // rtol 1e-16 is itself 1.4e-15 from quad on the heavy top, so the exact solution is the
  // better extended reference there. Against quad Bulirsch–Stoer (an independent quad answer,
  // itself ≤ 1.4e-28 from the exact one). Pendulum: 1.1e-17
  // absolute (≈ 2.4e-18 relative).
  for (const char* file :
       {"scenes/free_spin.toml", "scenes/heavy_top.toml", "scenes/pendulum.toml"}) {
    CAPTURE(file);
    const scene::SceneSpec spec = shortened(file, 20.0);
    const std::vector<double> times = times_of(spec);
    const HighPrecisionRun extended = exact_high_precision(spec, times, Precision::kExtended);
    const HighPrecisionRun quad = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
    CHECK(relative_distance(extended, quad) <= 1e-15);
  }
}

TEST_CASE("the asymmetric body near its separatrix in quad", "[precision][exact]") {
  // book_toss's book (J = diag(1, 2, 2.8)) spun at 10 rad/s about its middle axis with a
  // transverse rate 0.01 rad/s and no pulse: it flips every ~0.9 s and each flip amplifies a
  // perturbation. Quad Bulirsch–Stoer's round-off is amplified with it: measured 5.7e-26 at
  // rtol 1e-28 and 7.1e-26 at rtol 1e-30 (it does not shrink: round-off, not truncation),
  // while extended's exact solution is 1.1e-17 (200 u_ext) from quad's, so quad's exact
  // solution is good to ~2e-32 and the distance is the integrator's. Bound 1e-24: 15× the
  // measured round-off plateau, still 1e8 below double's accuracy on this body.
  const scene::SceneSpec spec = free_book(10.0, 1e-2);
  const std::vector<double> times = times_of(spec);
  const HighPrecisionRun exact = exact_high_precision(spec, times, Precision::kQuad);
  const HighPrecisionRun integrated = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
  CHECK(relative_distance(exact, integrated) <= 1e-24);
  const HighPrecisionRun extended = exact_high_precision(spec, times, Precision::kExtended);
  CHECK(relative_distance(extended, exact) <= 1e-15);  // as on the bundled scenes
}

TEST_CASE("quad exact solutions agree with the double exact solution", "[precision][exact]") {
  // reference::solve_exact (double, its own principal-axes code on core::Model, tabulated by
  // trajectory::tabulate) against the quad run rounded to double. The double solution's accuracy
  // (exact_torque_free.hpp, exact_heavy_top.hpp): θ to 6e-14 and 9e-14 rad over the bundled
  // scenes, at most 3e-14 relative to a solution scale ≥ π; 1e-13 leaves a factor 3. Measured
  // 5.9e-15 (free_spin), 2.1e-14 (heavy_top), 1.7e-14 (free book), 2.5e-14 absolute (≈ 6e-15
  // relative) for the pendulum.
  for (const scene::SceneSpec& spec :
       {shortened("scenes/free_spin.toml", 20.0), shortened("scenes/heavy_top.toml", 2.0),
        free_book(10.0, 1e-2), shortened("scenes/pendulum.toml", 10.0)}) {
    CAPTURE(spec.name);
    const std::vector<double> times = times_of(spec);
    const HighPrecisionRun quad = exact_high_precision(spec, times, Precision::kQuad);
    const core::Model model = scene::build_model(spec);
    const trajectory::TrajectoryTable dbl =
        trajectory::tabulate(model, reference::solve_exact(model, times).trajectory);
    REQUIRE(dbl.columns == quad.table.columns);
    const double relative =
        trajectory::metric_value(trajectory::compare_trajectories(dbl, quad.table), kMetric) /
        trajectory::solution_scale(dbl, kMetric);
    CHECK(relative <= 1e-13);
    CHECK(relative > 0.0);  // two different computations: exactly equal would mean one is not run
  }
}

TEST_CASE("a sign error in the initial rate is caught", "[precision][exact]") {
  // The comparison above can fail: the exact solution of the same body with ω̄₀ reversed, or
  // with only its x component reversed (a sign error in one term), is O(0.1–1) from the
  // integrated reference, 1e20 times the tolerance.
  const scene::SceneSpec spec = shortened("scenes/free_spin.toml", 5.0);
  const std::vector<double> times = times_of(spec);
  const HighPrecisionRun integrated = solve_high_precision(spec, times, Precision::kQuad, 1e-28);
  for (const Eigen::Vector3d& flip :
       {Eigen::Vector3d(-1.0, -1.0, -1.0), Eigen::Vector3d(-1.0, 1.0, 1.0)}) {
    scene::SceneSpec wrong = spec;
    Eigen::Vector3d& w = wrong.bodies[0].description.initial.w_WB_B;
    w = w.cwiseProduct(flip);
    const HighPrecisionRun exact = exact_high_precision(wrong, times, Precision::kQuad);
    CHECK(relative_distance(exact, integrated) > 1e-5);
  }
}

TEST_CASE("exact_high_precision refuses scenes without an exact solution", "[precision][exact]") {
  const auto message = [](const std::string& file) {
    const scene::SceneSpec spec = shortened(file, 0.1);
    try {
      (void)exact_high_precision(spec, times_of(spec), Precision::kQuad);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  CHECK_THAT(message("scenes/book_toss.toml"), Catch::Contains("the free body is loaded"));
  CHECK(message("scenes/pendulum.toml") == "no exception");  // all three exact solutions
}

}  // namespace
}  // namespace flexref::precision
