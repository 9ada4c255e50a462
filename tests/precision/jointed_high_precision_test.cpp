/// \file jointed_high_precision_test.cpp
/// Ideal joints in extended and quad precision (precision/ode_system.hpp with
/// constraint::IdealJointsTpl<S>): the heavy top on its spherical joint against the exact
/// Lagrange top, Andrews' squeezer against the double reference, its constraint violation at
/// quad's round-off, and its joint reactions against double's.
#include <array>
#include <boost/multiprecision/float128.hpp>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "precision/exact_high_precision.hpp"
#include "precision/high_precision_reference.hpp"
#include "precision/ode_system.hpp"
#include "reference/reference_solver.hpp"
#include "scene/build_model.hpp"
#include "tests/precision/precision_order.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {
namespace {

using Quad = boost::multiprecision::float128;

/// A value of a quad run's text row, parsed in quad.
Quad jointed_value(const HighPrecisionRun& run, std::size_t row, const std::string& name) {
  return Quad(run.text[row][column(run, name)]);
}

/// The largest geodesic angle between body `body`'s attitudes in two quad runs (2 |q_a ∓ q_b|,
/// exact to third order in the angle) and the largest distance between its point `point`.
std::array<Quad, 2> jointed_distance(const HighPrecisionRun& a, const HighPrecisionRun& b,
                                     const std::string& body, const std::string& point) {
  REQUIRE(a.text.size() == b.text.size());
  Quad angle(0), distance_m(0);
  for (std::size_t r = 0; r < a.text.size(); ++r) {
    Quad plus(0), minus(0), d(0);
    for (const char* e : {".e0", ".e1", ".e2", ".e3"}) {
      const Quad qa = jointed_value(a, r, body + e);
      const Quad qb = jointed_value(b, r, body + e);
      plus += (qa + qb) * (qa + qb);
      minus += (qa - qb) * (qa - qb);
    }
    for (const char* c : {".x", ".y", ".z"}) {
      const Quad pa = jointed_value(a, r, body + "." + point + c);
      const Quad pb = jointed_value(b, r, body + "." + point + c);
      d += (pa - pb) * (pa - pb);
    }
    angle = std::max(angle, Quad(2 * sqrt(std::min(plus, minus))));
    distance_m = std::max(distance_m, Quad(sqrt(d)));
  }
  return {angle, distance_m};
}

TEST_CASE("quad carries the heavy top's ideal spherical joint to the exact Lagrange top",
          "[precision][joints]") {
  // heavy_top_spherical is heavy_top's body as a free body held at its frame origin by an
  // ideal spherical joint: the same motion through 6 coordinates and 3 multipliers, over the
  // issue's 2 s. Before the extended/quad model carried joints, solve_high_precision refused
  // the scene (std::invalid_argument).
  const scene::SceneSpec jointed = spec_of("scenes/heavy_top_spherical.toml");
  const scene::SceneSpec pivot = spec_of("scenes/heavy_top.toml");
  REQUIRE(jointed.end_time == pivot.end_time);
  const std::vector<double> times = core::output_times(jointed.end_time, jointed.output_step);
  constexpr double kRtol = 1e-24;
  const HighPrecisionRun run = solve_high_precision(jointed, times, Precision::kQuad, kRtol);
  const HighPrecisionRun exact = exact_high_precision(pivot, times, Precision::kQuad);
  const std::array<Quad, 2> d = jointed_distance(run, exact, "top", "tip");
  Quad drift(0);
  for (std::size_t r = 0; r < run.text.size(); ++r) {
    drift = std::max(drift, jointed_value(run, r, "pivot.phi"));
  }
  INFO("attitude " << static_cast<double>(d[0]) << " rad, tip " << static_cast<double>(d[1])
                   << " m, pivot drift " << static_cast<double>(drift) << " m, " << run.steps
                   << " steps, " << run.cpu_seconds << " s");
  // Bulirsch–Stoer at rtol R keeps each step's local error below R (relative to the state, of
  // size ~1: unit quaternion, 1 m arm); the top's precession is stable (errors grow at most
  // linearly, by the phase), so over its N steps the global error is at most N R (7e-21 at
  // R = 1e-24, N ≈ 7e3: 1e11 below double's 1e-9 rad). The exact solution's own error is
  // ~1e-28 (its estimate). Measured: 3.3e-26 rad and 2.5e-26 m.
  const double bound = static_cast<double>(run.steps) * kRtol;
  CHECK(static_cast<double>(d[0]) < bound);
  CHECK(static_cast<double>(d[1]) < bound);
  // The pivot's drift off the joint: Baumgarte damps what the steps leave off the manifold, so
  // it stays within the same bound (measured 4.9e-28 m; 1.8e-24 m without stabilization).
  CHECK(static_cast<double>(drift) < bound);
}

/// Andrews' squeezer over its first 3 ms (the whole 0.03 s takes 3.6 min per quad solve at
/// rtol 1e-28: docs/joints.md): quad at its default rtol, extended at its default, and the
/// double CVODE reference at rtol 1e-12 with its certified estimate. Computed once for the
/// sections below.
struct JointedAndrews {
  scene::SceneSpec spec;
  std::vector<double> times;
  HighPrecisionRun quad;
  HighPrecisionRun extended;
  trajectory::CertifiedReference double_reference;
};

const JointedAndrews& jointed_andrews() {
  static const JointedAndrews a = [] {
    JointedAndrews r;
    r.spec = spec_of("scenes/andrews_squeezer.toml");
    r.spec.end_time = 0.003;
    r.times = core::output_times(r.spec.end_time, r.spec.output_step);
    r.quad =
        solve_high_precision(r.spec, r.times, Precision::kQuad, default_rtol(Precision::kQuad));
    r.extended = solve_high_precision(r.spec, r.times, Precision::kExtended,
                                      default_rtol(Precision::kExtended));
    const core::Model model = scene::build_model(r.spec);
    reference::SolverOptions o;
    o.rtol = 1e-12;
    r.double_reference = trajectory::certified_reference(model, r.times, "cvode", o, "rotation",
                                                         {.use_exact_solution = false});
    return r;
  }();
  return a;
}

/// One test case for the three properties, so that one process computes the three solutions
/// (ctest runs each test case in a process of its own; quad takes ~70 s here).
TEST_CASE("Andrews' squeezer in extended and quad: agreement with double, joints, reactions",
          "[precision][joints][long_quad]") {
  const JointedAndrews& a = jointed_andrews();
  SECTION("extended and quad agree with double within its estimate") {
    const trajectory::CertifiedReference& d = a.double_reference;
    REQUIRE(std::isfinite(d.estimate.value));
    const double double_vs_quad = trajectory::metric_value(
        trajectory::compare_trajectories(d.table, a.quad.table), "rotation");
    const double double_vs_extended = trajectory::metric_value(
        trajectory::compare_trajectories(d.table, a.extended.table), "rotation");
    const double extended_vs_quad = distance(a.extended, a.quad, "rotation");
    INFO("double estimate " << d.estimate.value << ", double vs quad " << double_vs_quad
                            << ", double vs extended " << double_vs_extended
                            << ", extended vs quad " << extended_vs_quad << "; quad "
                            << a.quad.cpu_seconds << " s");
    // The double reference's certified estimate bounds its distance to the truth, which quad and
    // extended are far closer to (below): each is within it of double.
    CHECK(double_vs_quad <= d.estimate.value);
    CHECK(double_vs_extended <= d.estimate.value);
    // Extended at rtol 1e-16 over its N steps: at most N × 1e-16 × the angles' size (K1 turns
    // ~0.35 rad in 3 ms, the others < π): the bound N × 1e-16 × π; it must also beat double.
    // Measured: double 3.6e-11 from quad and from extended (estimate 7.3e-11), extended 3.0e-18
    // from quad.
    CHECK(extended_vs_quad <= static_cast<double>(a.extended.steps) * 1e-16 * std::numbers::pi);
    CHECK(extended_vs_quad < double_vs_quad);
  }

  SECTION("quad keeps its joints to quad's round-off") {
    // The largest |Φ| (m for the point rows, the sine of an angle for the axis rows) and
    // |J v + Φ_t| over the joints and outputs.
    Quad position(0), velocity(0);
    for (std::size_t r = 0; r < a.quad.text.size(); ++r) {
      for (std::size_t c = 1; c < a.quad.columns.size(); ++c) {
        const std::string& name = a.quad.columns[c];
        if (name.size() > 4 && name.substr(name.size() - 4) == ".phi") {
          position = std::max(position, abs(Quad(a.quad.text[r][c - 1])));
        } else if (name.size() > 8 && name.substr(name.size() - 8) == ".phi_dot") {
          velocity = std::max(velocity, abs(Quad(a.quad.text[r][c - 1])));
        }
      }
    }
    INFO("max |phi| " << static_cast<double>(position) << ", max |phi_dot| "
                      << static_cast<double>(velocity));
    // The initial state is projected in quad to 8 ε relative; afterwards each step of rtol R =
    // 1e-28 leaves at most R × the state's size off the manifold (positions ≤ 0.1 m: 1e-29;
    // velocities ≤ 40 m/s, K1's 1140 rad/s × its 35 mm: 4e-27 m/s) and Baumgarte damps it
    // instead of letting it grow. Measured: 2.0e-33 m and 3.3e-31 m/s over these 3 ms, 9.9e-33 m
    // and 1.7e-30 m/s over 0.03 s — ~1e3 ε of the lengths and speeds, round-off, 1e17 below
    // double's ~1e-15.
    CHECK(static_cast<double>(position) < 1e-29);
    CHECK(static_cast<double>(velocity) < 4e-27);
    CHECK(position > Quad(0));  // the columns are computed, not zero-filled
  }

  SECTION("the joint reactions in quad agree with double's") {
    const trajectory::TrajectoryTable& d = a.double_reference.table;
    const trajectory::TrajectoryTable& q = a.quad.table;
    REQUIRE(d.columns == q.columns);
    double largest = 0.0;
    double worst = 0.0;
    int compared = 0;
    for (std::size_t c = 0; c < q.columns.size(); ++c) {
      const std::string& name = q.columns[c];
      const std::string tail = name.size() > 3 ? name.substr(name.size() - 3) : "";
      if (tail != ".fx" && tail != ".fy" && tail != ".tz") continue;  // the planar reactions
      ++compared;
      for (std::size_t r = 0; r < q.rows.size(); ++r) {
        largest = std::max(largest, std::abs(q.rows[r][c]));
        worst = std::max(worst, std::abs(q.rows[r][c] - d.rows[r][c]));
      }
    }
    REQUIRE(compared == 30);  // ten revolute joints
    const double relative = worst / largest;
    INFO("largest reaction " << largest << ", worst difference " << worst << " (" << relative
                             << " relative); double estimate "
                             << a.double_reference.estimate.value);
    // The reactions solve (J M⁻¹ Jᵀ) λ = J M⁻¹ Q − γ: a relative perturbation δ of the data moves
    // them by at most κ δ relative, κ ≤ 1/(the smallest pivot ratio of the Schur complement's
    // LDLᵀ) ≈ 1e5 on this mechanism (core/constrained_solve_tpl.hpp). The double state is off by
    // its certified estimate e (rad), a relative perturbation of the data (trigonometric in the
    // angles) of ~e, plus double's round-off in forming them, ~1e-16 κ. Bound κ (e + 1e-15).
    // Measured: 1.6e-9 N of 107 N, 1.5e-11 relative.
    CHECK(relative <= 1e5 * (a.double_reference.estimate.value + 1e-15));
    // At t = 0 both start from the same consistent state (quad refines double's projection by
    // ~1e-16): κ × 1e-15.
    double initial = 0.0;
    for (std::size_t c = 0; c < q.columns.size(); ++c) {
      const std::string& name = q.columns[c];
      if (name.size() > 3 && name.substr(name.size() - 3) == ".fx") {
        initial = std::max(initial, std::abs(q.rows[0][c] - d.rows[0][c]));
      }
    }
    CHECK(initial / largest <= 1e5 * 1e-15);
  }
}

}  // namespace
}  // namespace flexref::precision
