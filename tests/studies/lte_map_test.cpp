#include "studies/lte_map.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "studies/lte_map_grid.hpp"
#include "studies/lte_map_report.hpp"
#include "tests/support/flexible_models.hpp"

namespace flexref::studies {
namespace {

/// flexible_spinner (tests/support/flexible_models.hpp) with a grid point's changes: hub
/// inertia diag(0.5, 0.5, 1)·s, initial spin w0, torque 5·load_scale N·m. 2 bending modes
/// (one per plane) on 6 elements keep the test fast; the map's properties do not depend on it.
/// The level picks the formulation (LTE or coupled) and geometric stiffening (the truth).
core::Model spinner(LteMapLevel level, const std::optional<LteMapScaling>& scaling) {
  const LteMapScaling k = scaling.value_or(LteMapScaling{1.0, Eigen::Vector3d(0.0, 0.0, 1.0), 1.0});
  const core::FlexibleFormulation formulation = level == LteMapLevel::kLte
                                                    ? core::FlexibleFormulation::kLte
                                                    : core::FlexibleFormulation::kCoupled;
  core::RigidBodyDescription d = testing::flexible_body(
      "spinner", testing::beam_bending_modes(Eigen::Vector3d(0.1, 0.0, 0.0), 1.0, 3.2, 1e5, 1.0, 6,
                                             2, level == LteMapLevel::kStiffened));
  d.mass = 10.0 * k.hub_scale;
  d.I_Bcm_B = k.hub_scale * Eigen::Vector3d(0.5, 0.5, 1.0).asDiagonal();
  d.initial.w_WB_B = k.w0_WB_B;
  testing::FlexibleElements elements;
  elements.push_back(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d(0.0, 0.0, 5.0 * k.load_scale), core::LoadFrame::kWorld,
      core::TimeProfile::sin2_pulse(0.0, 0.5)));
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  return core::Model(std::move(bodies), std::move(elements), formulation);
}

}  // namespace

/// The small grid of the tests: spin ratios 0.02, 0.05, 0.1 and inertia ratios 1e-4 (hub
/// 4400× the scene's: the LTE limit of a heavy hub) and 0.1, over 3 s (three periods of the
/// first mode).
LteMapOptions small_grid(int jobs) {
  LteMapOptions options;
  options.spin_ratios = {0.02, 0.05, 0.1};
  options.inertia_ratios = {1e-4, 0.1};
  options.end_time = 3.0;
  options.jobs = jobs;
  // These tests measure LTE against the classical coupled model (the two-level map); the
  // three-level map has its own test below.
  options.stiffened_truth = false;
  return options;
}

const LteMapResult& small_grid_result() {
  static const LteMapResult result = run_lte_map(spinner, small_grid(2));
  return result;
}

TEST_CASE("lte-map base values of flexible_spinner", "[lte_map]") {
  const core::Model model = spinner(LteMapLevel::kClassical, std::nullopt);
  const LteMapBase base = lte_map_base(model, LteMapOptions{});
  CHECK(base.body == "spinner");
  CHECK(base.point == "tip");
  // Clamped-free beam: ω1 = 1.8751² √(EI/(ρA L⁴)) = 3.5160·√3.2 = 6.290 rad/s (6 elements: the
  // discretization error of the lowest mode is far below 0.1 %).
  CHECK(base.omega1 == Approx(6.290).epsilon(1e-3));
  // Tolerance: the spin and its ratio come from the scene's ω and ω1 (a modal eigenvalue,
  // O(1e-14) relative from the eigensolver on a 6-element beam): 1e-12 leaves a factor 100.
  CHECK(base.spin == Approx(1.0).epsilon(1e-12));
  CHECK(base.spin_ratio == Approx(1.0 / base.omega1).epsilon(1e-12));
  // Hub 10 kg at Bo, beam 1 kg centred at x = 0.6: Br at x = 0.6/11. The beam's inertia about
  // its centre is L²/12 = 1/12 (lumped nodes: within 2 %), plus 1·(0.6 − 0.6/11)²; the hub's
  // 1 + 10·(0.6/11)².
  const double xb = 0.6 / 11.0;
  CHECK(base.inertia_flex == Approx(1.0 / 12.0 + (0.6 - xb) * (0.6 - xb)).epsilon(0.02));
  CHECK(base.inertia_rigid == Approx(1.0 + 10.0 * xb * xb).epsilon(1e-12));
  CHECK(lte_map_inertia_ratio(base, 1.0) == Approx(base.inertia_ratio).epsilon(1e-12));
}

TEST_CASE("lte-map scaling reaches the requested ratios", "[lte_map]") {
  const core::Model model = spinner(LteMapLevel::kClassical, std::nullopt);
  const LteMapBase base = lte_map_base(model, LteMapOptions{});
  for (const double y : {1e-4, 0.1, base.inertia_ratio, 10.0}) {
    const LteMapScaling k = lte_map_scaling(base, 0.3, y, true);
    // Bisection on log s to a ratio 1 + 1e-14 of s: y(s) is smooth, so y is met to ~1e-13.
    CHECK(lte_map_inertia_ratio(base, k.hub_scale) == Approx(y).epsilon(1e-10));
    // Tolerance: |W0| = 0.3 ω1 by construction: one product and a norm of a vector along z, a few
    // roundings of O(1)-relative operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor ~10
    // over them.
    CHECK(k.w0_WB_B.norm() == Approx(0.3 * base.omega1).epsilon(1e-14));
    // A vector along z divided by its norm: z exactly, x and y zero.
    CHECK(k.w0_WB_B.normalized() == Eigen::Vector3d::UnitZ());
    // The scaled model has the requested ratio, read back from its body.
    const core::Model scaled = spinner(LteMapLevel::kClassical, k);
    CHECK(lte_map_base(scaled, LteMapOptions{}).inertia_ratio == Approx(y).epsilon(1e-10));
  }
  // The scene's own point: hub scale 1, and the load scale is the spin scale.
  const LteMapScaling same = lte_map_scaling(base, base.spin_ratio, base.inertia_ratio, true);
  CHECK(same.hub_scale == Approx(1.0).epsilon(1e-10));
  CHECK(same.load_scale == Approx(1.0).epsilon(1e-10));
  CHECK(lte_map_scaling(base, 2.0 * base.spin_ratio, base.inertia_ratio, true).load_scale ==
        Approx(2.0).epsilon(1e-10));
  CHECK(lte_map_scaling(base, 0.3, 0.1, false).load_scale == 1.0);
  CHECK_THROWS_AS(lte_map_scaling(base, 0.0, 0.1, true), std::invalid_argument);
  CHECK_THROWS_AS(lte_map_scaling(base, 0.1, -1.0, true), std::invalid_argument);
}

TEST_CASE("lte-map refuses scenes without a spinning free flexible body", "[lte_map]") {
  LteMapScaling still{1.0, Eigen::Vector3d::Zero(), 1.0};
  const core::Model no_spin = spinner(LteMapLevel::kClassical, still);
  CHECK_THROWS_AS(lte_map_base(no_spin, LteMapOptions{}), std::invalid_argument);
  core::RigidBodyDescription rigid;
  rigid.name = "brick";
  rigid.initial.w_WB_B = Eigen::Vector3d(0.0, 0.0, 1.0);
  std::vector<core::Body> bodies;
  bodies.emplace_back(rigid);
  const core::Model rigid_model(std::move(bodies), {});
  CHECK_THROWS_AS(lte_map_base(rigid_model, LteMapOptions{}), std::invalid_argument);
  LteMapOptions bad_point;
  bad_point.point = "hub_rim";  // not a node: it does not deform
  CHECK_THROWS_AS(lte_map_base(spinner(LteMapLevel::kClassical, std::nullopt), bad_point),
                  std::invalid_argument);
}

// The LTE model's error against the coupled one has two sources (docs/lte_map.md):
//   - spin: the coupled model's in-plane modal stiffness is ω1² − Ω² (centrifugal softening,
//     docs/design/model.md "Geometric stiffening"), the LTE model's ω1²: a relative frequency shift
//     1 − √(1 − x²) ≈ x²/2, hence a phase error, and a tip error, ∝ x² at small x;
//   - inertia coupling: the coupled model's free hub recoils from the beam (rotation and
//     translation), raising the elastic frequency by a shift that grows with y; the LTE model's
//     rigid motion ignores the beam.
// At y = 1e-4 the second is negligible, so the error must vanish like Ω² as Ω → 0.
TEST_CASE("lte-map: the LTE error vanishes like spin^2 for a heavy hub", "[lte_map]") {
  const LteMapResult& r = small_grid_result();
  REQUIRE(r.points.size() == 6);
  for (const LteMapPoint& p : r.points) {
    INFO("x = " << p.spin_ratio << ", y = " << p.inertia_ratio << ": " << p.status);
    REQUIRE(p.status == "ok");
    CHECK(p.resolved);
  }
  const double e1 = r.points[0].tip_error;
  const double e2 = r.points[1].tip_error;
  const double e3 = r.points[2].tip_error;
  INFO("tip errors at x = 0.02, 0.05, 0.1 (y = 1e-4): " << e1 << ", " << e2 << ", " << e3);
  // Monotone, and at least 4x smaller at the smallest than at the middle spin ratio.
  CHECK(e1 < e2);
  CHECK(e2 < e3);
  CHECK(e2 > 4.0 * e1);
  // Ω² scaling: ratios (0.05/0.02)² = 6.25 and (0.1/0.05)² = 4, within a factor 1.5 (the x⁴
  // term of the frequency shift and the residual inertia coupling, ≈ 0.1 % of error at y = 1e-4
  // by the linear growth in y seen at y = 0.1, move them by a few tens of percent at most).
  CHECK(e2 / e1 > 6.25 / 1.5);
  CHECK(e3 / e2 > 4.0 / 1.5);
  CHECK(e3 / e2 < 4.0 * 1.5);
  // And small: below 2 % at x = 0.02.
  CHECK(e1 < 0.02);
}

TEST_CASE("lte-map: the LTE error grows with the inertia ratio", "[lte_map]") {
  const LteMapResult& r = small_grid_result();
  for (std::size_t i = 0; i < 3; ++i) {
    const LteMapPoint& heavy_hub = r.points[i];
    const LteMapPoint& light_hub = r.points[3 + i];
    INFO("x = " << heavy_hub.spin_ratio << ": y = 1e-4: " << heavy_hub.tip_error
                << ", y = 0.1: " << light_hub.tip_error);
    CHECK(light_hub.tip_error > heavy_hub.tip_error);
    CHECK(light_hub.attitude_error > heavy_hub.attitude_error);
  }
  // At the smallest spin the inertia coupling dominates: an O(1) error at y = 0.1.
  CHECK(r.points[3].tip_error > 10.0 * r.points[0].tip_error);
}

TEST_CASE("lte-map: parallel and serial runs give identical numbers", "[lte_map]") {
  const LteMapResult serial = run_lte_map(spinner, small_grid(1));
  CHECK(lte_map_csv(serial) == lte_map_csv(small_grid_result()));
}

TEST_CASE("lte-map CSV and table", "[lte_map]") {
  const LteMapResult& r = small_grid_result();
  const std::string csv = lte_map_csv(r);
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  CHECK(line ==
        "spin_ratio,inertia_ratio,spin,omega1,hub_scale,load_scale,tip_error,envelope_error,"
        "frequency_shift,attitude_error,classical_tip_error,classical_envelope_error,"
        "classical_frequency_shift,max_deflection,truth_frequency,truth_estimate,lte_estimate,"
        "classical_estimate,resolved,classical_resolved,status");
  int rows = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::istringstream fs(line);
    std::string f;
    while (std::getline(fs, f, ',')) fields.push_back(f);
    REQUIRE(fields.size() == 21);
    const LteMapPoint& p = r.points[static_cast<std::size_t>(rows)];
    // csv_number writes the shortest text that reads back as the same double.
    CHECK(std::stod(fields[0]) == p.spin_ratio);
    CHECK(std::stod(fields[1]) == p.inertia_ratio);
    CHECK(std::stod(fields[6]) == p.tip_error);
    CHECK(std::stod(fields[7]) == p.envelope_error);
    CHECK(std::stod(fields[9]) == p.attitude_error);
    CHECK(fields[10].empty());  // two-level map: no classical-model metrics (never NaN)
    CHECK(fields[20] == "ok");
    ++rows;
  }
  CHECK(rows == 6);
  const std::string table = format_lte_map_table(r);
  CHECK(table.find("L-inf tip error, 5 % line at Omega0/omega1") != std::string::npos);
  CHECK(table.find("truth: the classical coupled model") != std::string::npos);
  CHECK(table.find("body 'spinner', point 'tip'") != std::string::npos);
}

TEST_CASE("lte-map: a frequency it cannot measure is a status and an empty cell and never NaN",
          "[lte_map]") {
  // Over 0.4 s the deflection (first period ~1 s: ω1 = 6.3 rad/s) cannot cross its mean three
  // times in the second half: no dominant frequency, which must not be written as `nan`
  // with status `ok`.
  LteMapOptions options = small_grid(1);
  options.spin_ratios = {0.02, 0.05};
  options.inertia_ratios = {1e-4};
  options.end_time = 0.4;
  const LteMapResult r = run_lte_map(spinner, options);
  for (const LteMapPoint& p : r.points) {
    INFO(p.status);
    CHECK(p.status.rfind("no frequency shift: the truth's deflection", 0) == 0);
    CHECK(std::isfinite(p.tip_error));
  }
  const std::string csv = lte_map_csv(r);
  CHECK(csv.find("nan") == std::string::npos);
  const std::string table = format_lte_map_table(r);
  CHECK(table.find("2 grid point(s) have no frequency shift") != std::string::npos);
}

TEST_CASE("lte-map with the stiffened truth: the classical coupled model's own error",
          "[lte_map]") {
  // Heavy hub (y = 1e-4: the rigid motion is the prescribed spin), beam from r = 0.1 to 1.1.
  // In-plane first mode: truth ω² = ω0² − Ω² + α Ω² (stiffening, α ≈ 1.19 + the hub-radius
  // share), classical ω0² − Ω², LTE ω0². So the classical model's frequency is low by about
  // α Ω²/(2 ω0²) and LTE's by (α − 1) Ω²/(2 ω0²): at x = Ω/ω1 = 0.3 the classical model's own
  // error is the larger (≈ 6 % against ≈ 1.5 %), its shift negative, and both shifts grow like
  // Ω² (x = 0.15 → 0.3: × 4, band [3, 5] for the O(Ω⁴) terms and the measurement over three
  // periods of the 6 s horizon's second half).
  LteMapOptions options;
  options.spin_ratios = {0.15, 0.3};
  options.inertia_ratios = {1e-4};
  options.end_time = 6.0;
  options.jobs = 2;
  const LteMapResult r = run_lte_map(spinner, options);
  REQUIRE(r.points.size() == 2);
  for (const LteMapPoint& p : r.points) {
    INFO("x = " << p.spin_ratio << ": " << p.status << "; LTE shift " << p.frequency_shift
                << ", classical shift " << p.classical_frequency_shift << "; tip errors "
                << p.tip_error << " / " << p.classical_tip_error << "; envelope "
                << p.envelope_error << " / " << p.classical_envelope_error);
    REQUIRE(p.status == "ok");
    CHECK(p.classical_frequency_shift < 0.0);
    CHECK(std::abs(p.classical_frequency_shift) > 2.0 * std::abs(p.frequency_shift));
    CHECK(std::isfinite(p.envelope_error));
    CHECK(std::isfinite(p.classical_envelope_error));
    CHECK(p.classical_resolved);
  }
  const double growth =
      r.points[1].classical_frequency_shift / r.points[0].classical_frequency_shift;
  INFO("classical shift growth x 0.15 → 0.3: " << growth);
  CHECK(growth > 3.0);
  CHECK(growth < 5.0);
  CHECK(std::abs(r.points[1].classical_frequency_shift) > 0.03);
  const std::string table = format_lte_map_table(r);
  CHECK(table.find("truth: the coupled model with geometric stiffening") != std::string::npos);
  CHECK(table.find("where the classical coupled model holds") != std::string::npos);
}

TEST_CASE("lte-map crossings interpolate log-log", "[lte_map]") {
  LteMapResult r;
  r.options.spin_ratios = {0.1, 1.0};
  r.options.inertia_ratios = {1.0, 2.0};
  r.points.resize(4);
  r.points[0].spin_ratio = 0.1;
  r.points[0].tip_error = 0.01;
  r.points[1].spin_ratio = 1.0;
  r.points[1].tip_error = 1.0;
  r.points[2].spin_ratio = 0.1;
  r.points[2].tip_error = 0.5;
  r.points[3].spin_ratio = 1.0;
  r.points[3].tip_error = 0.6;
  const std::vector<double> c = lte_map_crossings(r, 0.1);
  // e = 0.01·(x/0.1)² crosses 0.1 at x = 0.1·√10.
  // Tolerance: one log-log interpolation (two logs, a quotient, an exp, each ~1 ulp, amplified by
  // the slope 1/2 and the logs' size ~2.3): ~1e-15; 1e-13 leaves a factor ~100.
  CHECK(c[0] == Approx(0.1 * std::sqrt(10.0)).epsilon(1e-13));
  CHECK(std::isnan(c[1]));
}

}  // namespace flexref::studies
