#include "trajectory/column_layout.hpp"

#include <catch2/catch.hpp>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "scene/build_model.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/temp_dir.hpp"
#include "trajectory/trajectory_contract.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::trajectory {
namespace {

/// Bundled scenes that between them have every kind of column: tracked points (book_toss),
/// modes and a drive torque (rotating_cantilever), ideal joints (double_pendulum_ideal),
/// dissipation with applied work and named contacts (tube_support_impact), a driven joint's work
/// (slider_crank), worn depths and volume (wear_block).
const std::vector<std::string> kLayoutScenes = {
    "scenes/book_toss.toml",           "scenes/rotating_cantilever.toml",
    "scenes/double_pendulum_ideal.toml", "scenes/tube_support_impact.toml",
    "scenes/slider_crank.toml",        "scenes/wear_block.toml"};

core::Model layout_scene_model(const std::string& path) {
  const scene::Scene scene = scene::read_scene(path);
  return scene::build_model(scene.spec);
}

void require_same_column(const Column& parsed, const Column& written) {
  CAPTURE(written.name, parsed.name);
  CHECK(parsed.name == written.name);
  CHECK(parsed.kind == written.kind);
  CHECK(parsed.owner == written.owner);
  CHECK(parsed.point == written.point);
  CHECK(parsed.component == written.component);
}

TEST_CASE("a model's header parses back to the same typed columns", "[trajectory]") {
  std::set<ColumnKind> seen;
  for (const std::string& path : kLayoutScenes) {
    CAPTURE(path);
    const core::Model model = layout_scene_model(path);
    const ColumnLayout written = ColumnLayout::of(model);
    const std::vector<std::string> header = trajectory_columns(model);
    REQUIRE(header == written.names());
    REQUIRE(trajectory_units(model).size() == header.size());
    const ColumnLayout parsed = ColumnLayout::parse(header);
    REQUIRE(parsed.size() == written.size());
    for (std::size_t i = 0; i < written.size(); ++i) {
      require_same_column(parsed[i], written[i]);
      CHECK(parsed[i].kind != ColumnKind::unknown);
      seen.insert(written[i].kind);
    }
  }
  // Every kind but unknown appears in one of the scenes: the round trip covers them all.
  for (int k = 0; k < static_cast<int>(ColumnKind::unknown); ++k) {
    CAPTURE(k);
    CHECK(seen.count(static_cast<ColumnKind>(k)) == 1);
  }
}

TEST_CASE("a column's component is the position of its suffix in its group", "[trajectory]") {
  // Each suffix of a group at its own index: a table that swapped two would measure e1 as e2.
  const std::vector<std::pair<std::string, Column>> cases = {
      {"t", {ColumnKind::time, "", "", 0, "t"}},
      {"book.x", {ColumnKind::position, "book", "", 0, "book.x"}},
      {"book.z", {ColumnKind::position, "book", "", 2, "book.z"}},
      {"book.e0", {ColumnKind::rotation, "book", "", 0, "book.e0"}},
      {"book.e1", {ColumnKind::rotation, "book", "", 1, "book.e1"}},
      {"book.e2", {ColumnKind::rotation, "book", "", 2, "book.e2"}},
      {"book.e3", {ColumnKind::rotation, "book", "", 3, "book.e3"}},
      {"book.vy", {ColumnKind::velocity, "book", "", 1, "book.vy"}},
      {"book.W3", {ColumnKind::angular_velocity, "book", "", 2, "book.W3"}},
      {"book.corner.y", {ColumnKind::point, "book", "corner", 1, "book.corner.y"}},
      {"beam.q12", {ColumnKind::mode, "beam", "", 12, "beam.q12"}},
      {"beam.qd3", {ColumnKind::mode_rate, "beam", "", 3, "beam.qd3"}},
      {"beam.drive_torque", {ColumnKind::drive_torque, "beam", "", 0, "beam.drive_torque"}},
      {"hinge.fz", {ColumnKind::reaction_force, "hinge", "", 2, "hinge.fz"}},
      {"hinge.tx", {ColumnKind::reaction_torque, "hinge", "", 0, "hinge.tx"}},
      {"hinge.phi", {ColumnKind::violation, "hinge", "", 0, "hinge.phi"}},
      {"hinge.phi_dot", {ColumnKind::violation_rate, "hinge", "", 0, "hinge.phi_dot"}},
      {"energy_balance", {ColumnKind::energy_balance, "", "", 0, "energy_balance"}},
      {"support.fn", {ColumnKind::normal_force, "support", "", 0, "support.fn"}},
      {"support.wear_work", {ColumnKind::wear_work, "support", "", 0, "support.wear_work"}},
      {"support.wear_depth", {ColumnKind::wear_depth, "support", "", 0, "support.wear_depth"}},
      {"support.wear_volume", {ColumnKind::wear_volume, "support", "", 0, "support.wear_volume"}},
      {"support.depth1", {ColumnKind::depth, "support", "", 1, "support.depth1"}},
      {"support.depth36", {ColumnKind::depth, "support", "", 36, "support.depth36"}},
  };
  for (const auto& [name, expected] : cases) {
    require_same_column(parse_column(name), expected);
    CHECK(column_name(expected.kind, expected.owner, expected.component, expected.point) == name);
  }
  // The lookup of a model's layout finds each Euler parameter at the column of its name.
  const core::Model model = layout_scene_model("scenes/book_toss.toml");
  const ColumnLayout layout = ColumnLayout::of(model);
  const std::vector<std::string> header = layout.names();
  const std::string& body = layout[1].owner;
  for (int k = 0; k < 4; ++k) {
    const int i = layout.find(ColumnKind::rotation, body, k);
    REQUIRE(i > 0);
    CHECK(header[static_cast<std::size_t>(i)] == body + ".e" + std::to_string(k));
  }
}

TEST_CASE("names that are no column stay unknown, an out-of-range component is refused",
          "[trajectory]") {
  for (const std::string name : {"book.e4", "book.foo", "book.q", "book.qx1", "book.corner.e0",
                                 ".x", "iterations", "book.corner.x.y"}) {
    CAPTURE(name);
    CHECK(parse_column(name).kind == ColumnKind::unknown);
  }
  CHECK_THROWS_WITH(column_name(ColumnKind::rotation, "book", 4),
                    Catch::Contains("component 4 outside Euler parameters"));
  CHECK_THROWS_AS(column_name(ColumnKind::mode, "beam", 0), std::invalid_argument);
}

TEST_CASE("a malformed header is refused with the column it names", "[trajectory]") {
  testing::TempDir dir("column-layout");
  SECTION("an unknown suffix in a trajectory table") {
    const std::string path = dir.write("suffix.csv", "t,book.x,book.e5\n0,1,2\n").string();
    try {
      (void)read_csv(path);
      FAIL("expected an InputError");
    } catch (const core::InputError& e) {
      CHECK(e.line() == 1);
      CHECK(e.key() == "book.e5");
      CHECK_THAT(std::string(e.what()), Catch::Contains("not a trajectory column"));
    }
  }
  SECTION("a body the reference does not have") {
    const core::Model model = layout_scene_model("scenes/book_toss.toml");
    const std::vector<std::string> header = trajectory_columns(model);
    const TrajectoryTable reference{header, {std::vector<double>(header.size(), 0.0)}};
    std::vector<std::string> names = header;
    names.push_back("plate.e0");
    std::vector<std::vector<double>> columns(names.size(), std::vector<double>{0.0});
    const RunData run = run_from_columns("memory", names, columns);
    try {
      (void)compare_run(run, reference);
      FAIL("expected an InputError");
    } catch (const core::InputError& e) {
      CHECK(e.key() == "plate.e0");
      CHECK_THAT(std::string(e.what()), Catch::Contains("unknown body 'plate'"));
    }
  }
}

}  // namespace
}  // namespace flexref::trajectory
