/// Tests of app/modal_data_reader: the documented example reads as documented, the beam
/// model's modal data survives write → read exactly, and each class of bad input gives a
/// core::InputError with the file, the line and the key (docs/modal_data.md, docs/design/scenes.md
/// "Bad input").
#include "scene/modal_data_reader.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "flexible/beam_model.hpp"
#include "tests/support/input_error_checks.hpp"
#include "tests/support/temp_dir.hpp"

namespace flexref::app {
namespace {

using Catch::Matchers::Contains;

// A valid file; the tests below change one line at a time (line numbers count from 1).
const std::vector<std::string> kExample = {
    R"(format = "flexref-modal-data")",                                 // 1
    R"(version = 1)",                                                   // 2
    R"(nodes = [)",                                                     // 3
    R"(  { name = "root", mass = 1.0, position = [0.0, 0.0, 0.0] },)",  // 4
    R"(  { name = "mid", mass = 2.0, position = [0.5, 0.0, 0.0] },)",   // 5
    R"(  { name = "tip", mass = 1.0, position = [1.0, 0.0, 0.0] },)",   // 6
    R"(])",                                                             // 7
    R"()",                                                              // 8
    R"([[mode]])",                                                      // 9
    R"(name = "bend-1")",                                               // 10
    R"(omega = 2.0)",                                                   // 11
    R"(damping_ratio = 0.01)",                                          // 12
    R"(shape = [)",                                                     // 13
    R"(  [0.0, 0.0, 0.0],)",                                            // 14
    R"(  [0.0, 0.25, 0.0],)",                                           // 15
    R"(  [0.0, 0.5, 0.0],)",                                            // 16
    R"(])",                                                             // 17
    R"()",                                                              // 18
    R"([[mode]])",                                                      // 19
    R"(name = "axial-1")",                                              // 20
    R"(frequency_hz = 10)",                                             // 21
    R"(modal_mass = 0.75)",                                             // 22
    R"(shape = [)",                                                     // 23
    R"(  [0.0, 0.0, 0.0],)",                                            // 24
    R"(  [0.5, 0.0, 0.0],)",                                            // 25
    R"(  [0.5, 0.0, 0.0],)",                                            // 26
    R"(])",                                                             // 27
};

std::string join(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  return text;
}

// The example with line `line` replaced (several lines: a list of {line, text}).
std::string with(std::initializer_list<std::pair<int, std::string>> changes) {
  std::vector<std::string> lines = kExample;
  for (const auto& [line, text] : changes) lines[static_cast<std::size_t>(line - 1)] = text;
  return join(lines);
}

// The example without lines first..last.
std::string without(int first, int last) {
  std::vector<std::string> lines = kExample;
  lines.erase(lines.begin() + (first - 1), lines.begin() + last);
  return join(lines);
}

// parse_modal_data(text) throws an InputError for "bad.toml" at `line` naming `key`, with
// the file, line and key in what() and, when given, `fragment` too.
void require_modal_data_error(const std::string& text, int line, const std::string& key,
                              const std::string& fragment = "") {
  flexref::testing::require_input_error(
      [](const std::string& t, const std::string& file) {
        return scene::parse_modal_data(t, file);
      },
      "parse_modal_data", text, line, key, fragment);
}

void require_equal(const flexible::ModalData& a, const flexible::ModalData& b) {
  // Exact: every number is written in the shortest form that reads back as the same double.
  CHECK(a.mass == b.mass);
  CHECK(a.p_BoNode_B == b.p_BoNode_B);
  CHECK(a.phi == b.phi);
  CHECK(a.stiffness == b.stiffness);
  CHECK(a.damping_ratio == b.damping_ratio);
  CHECK(a.node_names == b.node_names);
  CHECK(a.mode_names == b.mode_names);
}

TEST_CASE("the documented example reads as documented", "[app][modal]") {
  const flexible::ModalData data = scene::parse_modal_data(join(kExample), "example.toml");
  REQUIRE(data.node_count() == 3);
  REQUIRE(data.mode_count() == 2);
  CHECK(data.node_names == std::vector<std::string>{"root", "mid", "tip"});
  CHECK(data.mode_names == std::vector<std::string>{"bend-1", "axial-1"});
  CHECK(data.mass == Eigen::Vector3d(1.0, 2.0, 1.0));
  CHECK(data.p_BoNode_B.col(2) == Eigen::Vector3d(1.0, 0.0, 0.0));
  CHECK(data.mode_rows(1).col(0) == Eigen::Vector3d(0.0, 0.25, 0.0));
  CHECK(data.mode_rows(2).col(1) == Eigen::Vector3d(0.5, 0.0, 0.0));
  // K_i = μ_i ω_i² with μ_1 = 2·0.25² + 1·0.5² = 0.375, ω_1 = 2; μ_2 = 2·0.5² + 0.5² = 0.75,
  // ω_2 = 2π·10. Rounding of a few products: 4 ε.
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  CHECK(data.stiffness(0) == Approx(0.375 * 4.0).epsilon(4 * kEps));
  const double omega2 = 2.0 * std::numbers::pi * 10.0;
  CHECK(data.stiffness(1) == Approx(0.75 * omega2 * omega2).epsilon(4 * kEps));
  CHECK(data.damping_ratio == Eigen::Vector2d(0.01, 0.0));
  // Names are optional (all or none), as are damping ratios and modal masses.
  const flexible::ModalData unnamed =
      scene::parse_modal_data(with({{4, R"(  { mass = 1.0, position = [0.0, 0.0, 0.0] },)"},
                                    {5, R"(  { mass = 2.0, position = [0.5, 0.0, 0.0] },)"},
                                    {6, R"(  { mass = 1.0, position = [1.0, 0.0, 0.0] },)"},
                                    {10, ""},
                                    {20, ""},
                                    {22, ""}}),
                              "example.toml");
  CHECK(unnamed.node_names.empty());
  CHECK(unnamed.mode_names.empty());
  CHECK(unnamed.stiffness == data.stiffness);
  // [[nodes]] tables are the same as the inline array.
  const flexible::ModalData tables = scene::parse_modal_data(
      R"(format = "flexref-modal-data"
version = 1
[[nodes]]
mass = 3.0
position = [0.0, 1.0, 0.0]
[[mode]]
stiffness = 5.0
shape = [[1.0, 0.0, 0.0]]
)",
      "tables.toml");
  CHECK(tables.mass(0) == 3.0);
  CHECK(tables.stiffness(0) == 5.0);
}

TEST_CASE("beam modal data: write then read is exact", "[app][modal]") {
  flexible::BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.0, 0.0);
  p.length = 1.0;
  p.elements = 20;
  p.EA = 1e5;
  p.EI_y = 4.0;
  p.EI_z = 3.2;
  p.rho_A = 1.0;
  for (const flexible::BeamBoundary boundary :
       {flexible::BeamBoundary::kClampedFree, flexible::BeamBoundary::kFreeFree}) {
    p.boundary = boundary;
    flexible::ModalData data =
        flexible::make_beam_modal_data(p, 8, {},
                                       boundary == flexible::BeamBoundary::kFreeFree
                                           ? flexible::BeamModeNormalization::kUnitTipDisplacement
                                           : flexible::BeamModeNormalization::kUnitModalMass);
    for (int i = 0; i < data.mode_count(); ++i) data.damping_ratio(i) = 0.001 * (i + 1);
    const std::string text = scene::format_modal_data(data, "a \"beam\" \\ with\tescapes\n");
    require_equal(scene::parse_modal_data(text, "beam.toml"), data);
  }
  // Through a file; without names; with integral and extreme values.
  p.boundary = flexible::BeamBoundary::kClampedFree;
  flexible::ModalData data = flexible::make_beam_modal_data(p, 3);
  data.node_names.clear();
  data.mode_names.clear();
  data.mass(0) = 1.2345678901234567e17;  // the clamped root: no modal displacement
  data.mass(1) = 2.0;
  data.mass(2) = 1e-300;
  data.p_BoNode_B(2, 3) = -0.0;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  // Digits beyond the beam's (the root, rows 0..2, stays still).
  for (Eigen::Index r = 3; r < data.phi.rows(); ++r) data.phi(r, 1) += 1e-3 * uniform(rng);
  const testing::TempDir dir("modal-data-reader");
  const std::filesystem::path path = dir / "modes.toml";
  scene::write_modal_data(data, path.string());
  require_equal(scene::read_modal_data(path.string()), data);
}

TEST_CASE("unwritable data is refused", "[app][modal]") {
  flexible::ModalData data = flexible::make_beam_modal_data(flexible::BeamParameters{}, 2);
  data.mode_names[0] = "has space";
  CHECK_THROWS_AS(scene::format_modal_data(data), std::invalid_argument);
  data = flexible::make_beam_modal_data(flexible::BeamParameters{}, 2);
  data.mass(0) = -1.0;
  CHECK_THROWS_AS(scene::format_modal_data(data), std::invalid_argument);
}

TEST_CASE("bad files: syntax, header and top-level keys", "[app][modal]") {
  require_modal_data_error(
      with({{5, R"(  { name = "mid", mass = , position = [0.5, 0.0, 0.0] },)"}}), 5, "",
      "TOML syntax error");
  require_modal_data_error(without(1, 1), 1, "format", "required key is missing");
  require_modal_data_error(with({{1, R"(format = "flexref-scene")"}}), 1, "format",
                           "modal-data file");
  require_modal_data_error(with({{2, R"(version = 2)"}}), 2, "version", "unsupported version");
  require_modal_data_error(with({{2, R"(version = "1")"}}), 2, "version", "a string");
  require_modal_data_error(with({{8, R"(colour = "red")"}}), 8, "colour", "unknown key");
  require_modal_data_error(with({{8, R"(modal_mass_tolerance = 0)"}}), 8, "modal_mass_tolerance",
                           "> 0");
  require_modal_data_error(without(3, 7), 1, "nodes", "required key is missing");
  require_modal_data_error(without(9, 27), 1, "mode", "at least one mode");
}

TEST_CASE("bad files: nodes", "[app][modal]") {
  const auto node = [](const std::string& fields) { return "  { " + fields + " },"; };
  require_modal_data_error(
      with({{5, node(R"(name = "mid", mass = 0.0, position = [0.5, 0.0, 0.0])")}}), 5,
      "nodes[2].mass", "> 0");
  require_modal_data_error(
      with({{5, node(R"(name = "mid", mass = -1.0, position = [0.5, 0.0, 0.0])")}}), 5,
      "nodes[2].mass", "> 0");
  require_modal_data_error(
      with({{5, node(R"(name = "mid", mass = inf, position = [0.5, 0.0, 0.0])")}}), 5,
      "nodes[2].mass", "infinite and NaN values are not allowed");
  require_modal_data_error(
      with({{5, node(R"(name = "mid", mass = nan, position = [0.5, 0.0, 0.0])")}}), 5,
      "nodes[2].mass", "infinite and NaN values are not allowed");
  require_modal_data_error(
      with({{5, node(R"(name = "mid", mass = "2", position = [0.5, 0.0, 0.0])")}}), 5,
      "nodes[2].mass", "a string");
  require_modal_data_error(with({{5, node(R"(name = "mid", position = [0.5, 0.0, 0.0])")}}), 5,
                           "nodes[2].mass", "required key is missing");
  require_modal_data_error(with({{5, node(R"(name = "mid", mass = 2.0, position = [0.5, 0.0])")}}),
                           5, "nodes[2].position", "[x, y, z]");
  require_modal_data_error(
      with({{5, node(R"(name = "mid", mass = 2.0, position = [0.5, nan, 0.0])")}}), 5,
      "nodes[2].position", "infinite and NaN");
  require_modal_data_error(
      with({{5, node(R"(name = "mid", mass = 2.0, position = [0.5, 0.0, 0.0], colour = 1)")}}), 5,
      "nodes[2].colour", "unknown key");
  require_modal_data_error(
      with({{6, node(R"(name = "mid", mass = 1.0, position = [1.0, 0.0, 0.0])")}}), 6,
      "nodes[3].name", "duplicate node name \"mid\" (first used at line 5)");
  require_modal_data_error(with({{5, node(R"(mass = 2.0, position = [0.5, 0.0, 0.0])")}}), 5,
                           "nodes[2]", "give every node a name or none");
  require_modal_data_error(
      with({{5, node(R"(name = "m id", mass = 2.0, position = [0.5, 0.0, 0.0])")}}), 5,
      "nodes[2].name", "letters, digits");
}

TEST_CASE("bad files: modes", "[app][modal]") {
  require_modal_data_error(with({{12, R"(damping = 0.01)"}}), 12, "mode[1].damping", "unknown key");
  require_modal_data_error(with({{11, ""}}), 9, "mode[1]", "one of stiffness");
  require_modal_data_error(with({{12, R"(stiffness = 1.0)"}}), 11, "mode[1].omega", "only one of");
  require_modal_data_error(with({{11, R"(stiffness = -1.0)"}}), 11, "mode[1].stiffness", "≥ 0");
  require_modal_data_error(with({{11, R"(omega = -2.0)"}}), 11, "mode[1].omega", "≥ 0");
  require_modal_data_error(with({{21, R"(frequency_hz = nan)"}}), 21, "mode[2].frequency_hz",
                           "NaN");
  require_modal_data_error(with({{12, R"(damping_ratio = -0.1)"}}), 12, "mode[1].damping_ratio",
                           "≥ 0");
  require_modal_data_error(with({{12, R"(damping_ratio = inf)"}}), 12, "mode[1].damping_ratio",
                           "infinite");
  require_modal_data_error(with({{10, R"(name = 3)"}}), 10, "mode[1].name", "an integer");
  require_modal_data_error(with({{20, ""}}), 19, "mode[2]", "give every mode a name or none");
  // Shapes: missing, wrong row count, wrong row length, non-finite or non-numeric entries.
  require_modal_data_error(without(13, 17), 9, "mode[1].shape", "required key is missing");
  require_modal_data_error(with({{13, R"(shape = 0.0)"}, {14, ""}, {15, ""}, {16, ""}, {17, ""}}),
                           13, "mode[1].shape", "rows [ux, uy, uz]");
  require_modal_data_error(with({{16, ""}}), 13, "mode[1].shape", "got 2 rows");
  require_modal_data_error(with({{15, R"(  [0.0, 0.25],)"}}), 15, "mode[1].shape[2]", "node 2");
  require_modal_data_error(with({{15, R"(  [0.0, nan, 0.0],)"}}), 15, "mode[1].shape[2]", "NaN");
  require_modal_data_error(with({{15, R"(  [0.0, "x", 0.0],)"}}), 15, "mode[1].shape[2]",
                           "a string");
  require_modal_data_error(with({{15, R"(  [0.0, 0.0, 0.0],)"}, {16, R"(  [0.0, 0.0, 0.0],)"}}), 13,
                           "mode[1].shape", "no displacement");
  // The modal mass check, and modes that are linear combinations of others.
  require_modal_data_error(with({{22, R"(modal_mass = 1.0)"}}), 22, "mode[2].modal_mass",
                           "Σ m_k |Φ_k|² = 0.75");
  require_modal_data_error(
      with({{22, ""}, {25, R"(  [0.0, 0.5, 0.0],)"}, {26, R"(  [0.0, 1.0, 0.0],)"}}), 19, "mode[2]",
      "linear combination");
}

// The example with a [geometric_stiffness] section (lines 28-): its lines appended.
std::string with_geometric(const std::vector<std::string>& lines) {
  std::vector<std::string> all = kExample;
  all.push_back("");                       // 28
  all.push_back("[geometric_stiffness]");  // 29
  all.insert(all.end(), lines.begin(), lines.end());
  return join(all);
}

TEST_CASE("geometric stiffness: round trip, the documented section, bad sections", "[app][modal]") {
  // A stiffened beam's data survive write → read exactly (only the non-zero matrices are
  // written; the others read back as zero).
  flexible::BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.02, 0.0);
  p.elements = 6;
  flexible::ModalData data = flexible::make_beam_modal_data(
      p, 4, {}, flexible::BeamModeNormalization::kUnitModalMass, true);
  const flexible::ModalData back =
      scene::parse_modal_data(scene::format_modal_data(data), "beam.toml");
  require_equal(back, data);
  REQUIRE(back.geometric.has_value());
  for (std::size_t c = 0; c < 3; ++c) CHECK(back.geometric->E[c] == data.geometric->E[c]);
  for (std::size_t ab = 0; ab < 9; ++ab) CHECK(back.geometric->F[ab] == data.geometric->F[ab]);

  const flexible::ModalData read =
      scene::parse_modal_data(with_geometric({"E_x = [[1.0, 0.5], [0.5, 2.0]]"}), "g.toml");
  REQUIRE(read.geometric.has_value());
  CHECK(read.geometric->E[0](0, 1) == 0.5);
  CHECK(read.geometric->F[0].norm() == 0.0);
  CHECK_FALSE(scene::parse_modal_data(join(kExample), "g.toml").geometric.has_value());

  require_modal_data_error(with_geometric({"E_x = [[1.0, 0.5], [0.4, 2.0]]"}), 30,
                           "geometric_stiffness.E_x", "not symmetric");
  require_modal_data_error(with_geometric({"F_xy = [[1.0, 0.5]]"}), 30, "geometric_stiffness.F_xy",
                           "2 rows of 2 numbers");
  require_modal_data_error(with_geometric({"F_zz = [[1.0], [0.5, 2.0]]"}), 30,
                           "geometric_stiffness.F_zz[1]", "a row of 2 numbers");
  require_modal_data_error(with_geometric({"E_y = [[1.0, nan], [0.5, 2.0]]"}), 30,
                           "geometric_stiffness.E_y[1]", "NaN");
  require_modal_data_error(with_geometric({"G_xx = [[1.0, 0.0], [0.0, 2.0]]"}), 30,
                           "geometric_stiffness.G_xx", "unknown key");
  require_modal_data_error(with_geometric({}), 29, "geometric_stiffness", "no matrix given");
}

TEST_CASE("unreadable files name the path", "[app][modal]") {
  const std::string path = "/nonexistent/flexref/modes.toml";
  try {
    (void)scene::read_modal_data(path);
    FAIL("read_modal_data accepted a missing file");
  } catch (const core::InputError& e) {
    CHECK(e.file() == path);
    CHECK_THAT(std::string(e.what()), Contains("cannot open"));
  }
  const testing::TempDir dir("modal-data-folder");
  CHECK_THROWS_AS(scene::read_modal_data(dir.path().string()), core::InputError);
}

}  // namespace
}  // namespace flexref::app
