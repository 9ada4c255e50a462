// Wear laws in scenes (docs/wear.md, scenes/README.md `wear`): the keys read and refused at the
// file, line and key; the closed-form wearing block (scenes/wear_block.toml) in every reference
// solver and every scheme; the energy balance on a wearing hole.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/scene_error_checks.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref {
namespace {

using testing::replace_first;
using testing::require_scene_error;

// Lines 1-10: [scene] and a block; the contact's `wear` line is line 18.
const std::string kBlock =
    "[scene]\n"
    "name = \"w\"\n"
    "end_time = 1.0\n"
    "output_step = 0.1\n"
    "gravity = [0.0, 0.0, -9.81]\n"
    "[[body]]\n"
    "name = \"block\"\n"
    "mass = 1.0\n"
    "inertia = [0.1, 0.1, 0.1]\n"
    "position = [0.0, 0.0, 0.1]\n"
    "[[contact]]\n"
    "kind = \"point-plane\"\n"
    "name = \"pins\"\n"
    "body = \"block\"\n"
    "points = [[0.1, 0.1, -0.1], [-0.1, 0.1, -0.1], [0.0, -0.1, -0.1]]\n"
    "law = \"linear\"\n"
    "stiffness = 1e5\n"
    "wear = { law = \"archard\", coefficient = 1e-4, hardness = 1e9, area = 1e-6 }\n";
constexpr int kWearLine = 18;

// A tube at a gap support: lines 1-18, the support from 19, its `wear` line 27.
const std::string kTube =
    "[scene]\n"
    "name = \"g\"\n"
    "end_time = 1.0\n"
    "output_step = 0.1\n"
    "[[body]]\n"
    "name = \"tube\"\n"
    "motion = \"prescribed\"\n"
    "[body.prescribed]\n"
    "axis = [0.0, 0.0, 1.0]\n"
    "law = \"constant-rate\"\n"
    "rate = 0.0\n"
    "[body.beam]\n"
    "length = 1.0\n"
    "elements = 4\n"
    "EI = 10.0\n"
    "EA = 1000.0\n"
    "rho_A = 1.0\n"
    "modes = 2\n"
    "[[contact]]\n"
    "kind = \"gap-support\"\n"
    "name = \"support\"\n"
    "body = \"tube\"\n"
    "node = \"node2\"\n"
    "axis_point = [0.0, 0.0, 0.0]\n"
    "axis = [1.0, 0.0, 0.0]\n"
    "clearance = 0.001\n"
    "wear = { law = \"work-rate\", coefficient = 2e-14, sectors = 36, thickness = 0.02, radius = "
    "0.0105, acceleration = 1e4 }\n";
constexpr int kGapWearLine = 27;

}  // namespace

TEST_CASE("wear laws are read into the contacts, with a depth per point or sector") {
  const scene::Scene block = scene::parse_scene(kBlock, "w.toml");
  REQUIRE(block.model->wear_depth_count() == 3);
  const core::WearLaw* law = block.model->channel_wear_law(0);
  REQUIRE(law != nullptr);
  CHECK(law->kind == core::WearLaw::Kind::kArchard);
  CHECK(law->coefficient == 1e-4);
  CHECK(law->hardness == 1e9);
  CHECK(law->area == 1e-6);
  CHECK(law->acceleration == 1.0);  // the default
  const scene::Scene tube = scene::parse_scene(kTube, "g.toml");
  REQUIRE(tube.model->wear_depth_count() == 36);
  const core::WearLaw* gap = tube.model->channel_wear_law(0);
  CHECK(gap->kind == core::WearLaw::Kind::kWorkRate);
  CHECK(gap->acceleration == 1e4);
  // (2π r / S) w
  CHECK(tube.model->wear_depth_areas()[0] ==
        Approx(2.0 * std::numbers::pi * 0.0105 / 36 * 0.02).epsilon(1e-15));
  // The columns: the channel's four, then its largest depth, volume and one per sector.
  const std::vector<std::string> columns = trajectory::trajectory_columns(*tube.model);
  const auto at = [&](const std::string& c) {
    return std::find(columns.begin(), columns.end(), c) - columns.begin();
  };
  CHECK(at("support.wear_depth") == at("support.impacts") + 1);
  CHECK(at("support.wear_volume") == at("support.wear_depth") + 1);
  CHECK(at("support.depth1") == at("support.wear_volume") + 1);
  CHECK(at("support.depth36") == at("support.depth1") + 35);
}

TEST_CASE("bad wear laws are refused at the file, line and key") {
  const std::string wear =
      "wear = { law = \"archard\", coefficient = 1e-4, hardness = 1e9, area = 1e-6 }";
  const auto edited = [&](const std::string& to) { return replace_first(kBlock, wear, to); };
  require_scene_error(
      edited("wear = { law = \"archard\", coefficient = -1e-4, hardness = 1e9, area = 1e-6 }"),
      kWearLine, "contact[1].wear.coefficient", "positive");
  require_scene_error(
      edited("wear = { law = \"archard\", coefficient = 1e-4, hardness = 1e9, area = 0.0 }"),
      kWearLine, "contact[1].wear.area", "positive");
  require_scene_error(edited("wear = { law = \"archard\", coefficient = 1e-4, area = 1e-6 }"),
                      kWearLine, "contact[1].wear.hardness", "hardness");
  require_scene_error(edited("wear = { law = \"archard\", coefficient = 1e-4, hardness = 1e9, area "
                             "= 1e-6, acceleration = 0 }"),
                      kWearLine, "contact[1].wear.acceleration", "positive");
  require_scene_error(
      edited("wear = { law = \"archad\", coefficient = 1e-4, hardness = 1e9, area = 1e-6 }"),
      kWearLine, "contact[1].wear.law", "archard");
  require_scene_error(
      edited("wear = { law = \"work-rate\", coefficient = 1e-14, hardness = 1e9, area = 1e-6 }"),
      kWearLine, "contact[1].wear.hardness", "archard");
  require_scene_error(edited("wear = { law = \"archard\", coefficient = 1e-4, hardness = 1e9, area "
                             "= 1e-6, sectors = 4 }"),
                      kWearLine, "contact[1].wear.sectors", "gap support");
  require_scene_error(edited("wear = { law = \"archard\", coefficient = 1e-4, hardness = 1e9, area "
                             "= 1e-6, depth = 1 }"),
                      kWearLine, "contact[1].wear.depth");
  require_scene_error(edited("wear = 3"), kWearLine, "contact[1].wear", "wear law");
  // A wear law on an unnamed contact: its depths would have no columns.
  require_scene_error(replace_first(kBlock, "name = \"pins\"\n", ""), kWearLine - 1,
                      "contact[1].wear", "named contact");
}

TEST_CASE("bad wear laws of a gap support are refused at the file, line and key") {
  const std::string sectors = "sectors = 36";
  require_scene_error(replace_first(kTube, sectors, "sectors = 0"), kGapWearLine,
                      "contact[1].wear.sectors", "whole number");
  require_scene_error(replace_first(kTube, sectors, "sectors = 2.5"), kGapWearLine,
                      "contact[1].wear.sectors", "whole number");
  require_scene_error(replace_first(kTube, "thickness = 0.02", "thickness = -0.02"), kGapWearLine,
                      "contact[1].wear.thickness", "positive");
  require_scene_error(replace_first(kTube, ", radius = 0.0105", ""), kGapWearLine,
                      "contact[1].wear.radius", "radius");
  require_scene_error(replace_first(kTube, "sectors = 36", "sectors = 36, area = 1e-6"),
                      kGapWearLine, "contact[1].wear.area", "sectors");
  require_scene_error(
      replace_first(kTube, "clearance = 0.001\n",
                    "clearance = 0.001\nshape = \"planar\"\nplane_normal = [0.0, 0.0, 1.0]\n"),
      kGapWearLine + 2, "contact[1].wear", "circular");
}

}  // namespace flexref
