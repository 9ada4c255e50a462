/// Tests of studies/modal_truncation on a small case: flexible_spinner (10 elements) for 0.6 s
/// (through the end of the torque pulse) with 2, 4 and 8 modes. The truncation error shrinks
/// as modes are added and is far above the integration error; the reference row is exact; the
/// numbers do not depend on the number of threads; truncation keeps the lowest modes of the same
/// finite-element model (beam) or the first modes of a file basis, with the initial modal
/// coordinates; bad options are refused with a message.
#include "studies/modal_truncation.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "scene/build_model.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::studies {
namespace {

const char* const kSpinner = R"(
[scene]
name = "small_spinner"
end_time = 0.6
output_step = 0.02

[[body]]
name = "spinner"
mass = 10.0
inertia = [0.5, 0.5, 1.0]
angular_velocity = [0.0, 0.0, 1.0]
points = [
  { name = "tip", node = "node10" },
  { name = "hub_rim", at = [0.0, 0.1, 0.0] },
]

[body.beam]
origin = [0.1, 0.0, 0.0]
length = 1.0
elements = 10
EA = 1e5
EI = 3.2
rho_A = 1.0
boundary = "clamped-free"
modes = 8
families = ["bending-xy", "bending-xz"]

[[load]]
kind = "torque"
body = "spinner"
value = [0.0, 0.0, 5.0]
frame = "world"
profile = { shape = "sin2_pulse", start = 0.0, duration = 0.5 }
)";

scene::SceneSpec spinner_spec() { return scene::parse_scene(kSpinner, "small_spinner.toml").spec; }

ModalTruncationOptions small_options() {
  ModalTruncationOptions o;
  o.mode_counts = {8, 2, 4};  // unsorted on purpose
  o.end_time = 0.6;
  o.output_step = 0.02;
  o.solver = "odeint";
  o.rtol = 1e-9;
  o.jobs = 1;
  return o;
}

TEST_CASE("modal truncation: errors shrink with the mode count, above the integration error",
          "[studies][modes]") {
  const ModalTruncationResult r = run_modal_truncation(spinner_spec(), small_options());
  REQUIRE(r.rows.size() == 3);
  CHECK(r.body == "spinner");
  CHECK(r.point == "tip");  // the only node point
  CHECK(r.reference_modes == 8);
  CHECK(r.rows[0].modes == 2);
  CHECK(r.rows[1].modes == 4);
  CHECK(r.rows[2].modes == 8);
  for (const ModalTruncationRow& row : r.rows) {
    INFO(row.modes << " modes: " << row.status);
    CHECK(row.status == "ok");
    CHECK(row.resolved);
    CHECK(row.max_deflection > 1e-3);  // the pulse bends the beam by millimetres at least
    CHECK(row.steps > 0);
    // Honest estimates: the check run takes other steps (Odeint's are capped by the output
    // grid, which the check halves), so its difference is never zero by construction.
    CHECK(row.tip_estimate > 0.0);
    CHECK(row.attitude_estimate > 0.0);
    CHECK(row.tip_estimate < 1e-6);
  }
  // The reference against itself.
  CHECK(r.rows[2].tip_error == 0.0);
  CHECK(r.rows[2].attitude_error == 0.0);
  // Higher modes change the answer less and less: the 2-mode basis (first bending mode per
  // plane) misses more than the 4-mode one.
  CHECK(r.rows[0].tip_error > r.rows[1].tip_error);
  CHECK(r.rows[0].attitude_error > r.rows[1].attitude_error);
  CHECK(r.rows[1].tip_error > 0.0);
  // Relative and absolute errors agree through the reference's largest deflection.
  // Tolerance: one product of the two numbers the study stores: a few roundings of O(1)-relative
  // operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor ~10 over them.
  CHECK(r.rows[0].tip_error_m ==
        Approx(r.rows[0].tip_error * r.rows[2].max_deflection).epsilon(1e-14));
  // Frequencies: the retained maximum grows with the count.
  CHECK(r.rows[0].omega_max < r.rows[1].omega_max);
  CHECK(r.rows[1].omega_max < r.rows[2].omega_max);

  const std::string csv = modal_truncation_csv(r);
  CHECK(csv.rfind("modes,omega_max,tip_error,tip_error_m,attitude_error,", 0) == 0);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 4);
  const std::string table = format_modal_truncation_table(r);
  CHECK(table.find("reference") != std::string::npos);
}

TEST_CASE("modal truncation: the numbers do not depend on the number of threads",
          "[studies][modes]") {
  ModalTruncationOptions one = small_options();
  one.mode_counts = {2, 4};
  ModalTruncationOptions two = one;
  two.jobs = 2;
  const ModalTruncationResult a = run_modal_truncation(spinner_spec(), one);
  const ModalTruncationResult b = run_modal_truncation(spinner_spec(), two);
  for (std::size_t k = 0; k < 2; ++k) {
    CHECK(a.rows[k].tip_error == b.rows[k].tip_error);
    CHECK(a.rows[k].attitude_error == b.rows[k].attitude_error);
    CHECK(a.rows[k].tip_estimate == b.rows[k].tip_estimate);
    CHECK(a.rows[k].steps == b.rows[k].steps);
  }
}

TEST_CASE("modal truncation keeps the lowest modes and the initial modal state",
          "[studies][modes]") {
  scene::SceneSpec spec = spinner_spec();
  core::FlexiblePart& part = *spec.bodies[0].description.flexible;
  part.q0 = Eigen::VectorXd::LinSpaced(8, 0.01, 0.08);
  const scene::SceneSpec four = truncate_modes(spec, 0, 4);
  const core::FlexiblePart& truncated = *four.bodies[0].description.flexible;
  CHECK(truncated.modal.mode_count() == 4);
  CHECK(truncated.q0 == part.q0.head(4));
  // The same finite-element model: the 4 modes are the 8-mode basis's first 4.
  const core::Model m4 = scene::build_model(four);
  const core::Model m8 = scene::build_model(spec);
  CHECK((m4.body(0).natural_frequencies() - m8.body(0).natural_frequencies().head(4))
            .cwiseAbs()
            .maxCoeff() <= 1e-12 * m8.body(0).natural_frequencies()(3));
  // Initial modal coordinates cannot be extended to more modes than they were given for.
  CHECK_THROWS_WITH(truncate_modes(spec, 0, 12),
                    Catch::Contains("initial modal coordinates for 8 modes"));
  // A modal-data basis (no beam to solve again): its first columns, and no more than it has.
  scene::SceneSpec file_basis = spinner_spec();
  file_basis.bodies[0].beam.reset();
  const scene::SceneSpec three = truncate_modes(file_basis, 0, 3);
  const flexible::ModalData& m = three.bodies[0].description.flexible->modal;
  const flexible::ModalData& full = file_basis.bodies[0].description.flexible->modal;
  CHECK(m.mode_count() == 3);
  CHECK(m.phi == full.phi.leftCols(3));
  CHECK(m.stiffness == full.stiffness.head(3));
  CHECK_THROWS_WITH(truncate_modes(file_basis, 0, 9),
                    Catch::Contains("has 8 modes in its modal-data file"));
}

TEST_CASE("modal truncation refuses bad options", "[studies][modes]") {
  const scene::SceneSpec spec = spinner_spec();
  ModalTruncationOptions o = small_options();
  o.mode_counts = {4};
  CHECK_THROWS_WITH(run_modal_truncation(spec, o), Catch::Contains("at least two mode counts"));
  o.mode_counts = {0, 4};
  CHECK_THROWS_WITH(run_modal_truncation(spec, o), Catch::Contains("at least 1"));
  o.mode_counts = {4, 4};
  CHECK_THROWS_WITH(run_modal_truncation(spec, o), Catch::Contains("distinct"));
  o.mode_counts = {2, 4};
  o.point = "hub_rim";
  CHECK_THROWS_WITH(run_modal_truncation(spec, o), Catch::Contains("not a node"));
  o.point = "nowhere";
  CHECK_THROWS_WITH(run_modal_truncation(spec, o), Catch::Contains("has no point 'nowhere'"));
  o.point.clear();
  scene::SceneSpec rigid = spec;
  rigid.bodies[0].description.flexible.reset();
  rigid.bodies[0].beam.reset();
  CHECK_THROWS_WITH(run_modal_truncation(rigid, o), Catch::Contains("no flexible body"));
}

}  // namespace
}  // namespace flexref::studies
