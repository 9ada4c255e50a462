/// The identity of a scene's physics (scene/scene_identity.hpp): the hash of the parsed scene
/// that every sidecar records, so that results of two different scenes are never compared.
#include "scene/scene_identity.hpp"

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "flexible/beam_model.hpp"
#include "scene/modal_data_reader.hpp"
#include "scene/scene_reader.hpp"
#include "scene/scene_toml.hpp"
#include "tests/support/scene_error_checks.hpp"
#include "tests/support/temp_dir.hpp"

namespace flexref::scene {
namespace {

using testing::replace_first;

const std::string kSpin =
    "[scene]\n"
    "name = \"spin\"\n"
    "end_time = 100.0\n"
    "output_step = 0.1\n"
    "[[body]]\n"
    "name = \"body\"\n"
    "mass = 1.0\n"
    "inertia = [3.0, 4.0, 5.0]\n"
    "angular_velocity = [0.2, 0.3, 2.0]\n";

toml::value parse_toml(const std::string& text) { return scene_toml::parse(text, "x.toml"); }

std::string hash_of(const std::string& text) { return parse_scene(text, "s.toml").hash; }

TEST_CASE("the scene hash is of the parsed physics", "[scene][identity]") {
  const std::string base = hash_of(kSpin);
  CHECK(base.starts_with("fnv1a64:"));
  CHECK(base.size() == 8 + 16);
  // Comments, layout, key order and the spelling of numbers are not the physics.
  CHECK(hash_of("# a comment\n" + replace_first(kSpin, "[3.0, 4.0, 5.0]", "[ 3, 4e0, 5.00 ]")) ==
        base);
  CHECK(hash_of(replace_first(kSpin, "mass = 1.0\ninertia = [3.0, 4.0, 5.0]\n",
                              "inertia = [3.0, 4.0, 5.0]\nmass = 1.0\n")) == base);
  // What is written, not integrated: the name, description, end time and output step.
  CHECK(hash_of(replace_first(kSpin, "name = \"spin\"",
                              "name = \"renamed\"\ndescription = \"x\"")) == base);
  CHECK(hash_of(replace_first(replace_first(kSpin, "100.0", "2.0"), "0.1", "0.01")) == base);
  // Every value of the physics changes it, also in the last digit.
  CHECK(hash_of(replace_first(kSpin, "[3.0, 4.0, 5.0]", "[3.0, 4.0, 5.000000000000001]")) != base);
  CHECK(hash_of(replace_first(kSpin, "mass = 1.0", "mass = 2.0")) != base);
  CHECK(hash_of(replace_first(kSpin, "name = \"body\"", "name = \"other\"")) != base);
  CHECK(hash_of(kSpin + "points = [{ name = \"corner\", at = [1.0, 0.0, 0.0] }]\n") != base);
  CHECK(hash_of(replace_first(kSpin, "[scene]\n", "[scene]\ngravity = [0.0, 0.0, -9.81]\n")) !=
        base);
}

TEST_CASE("the canonical text tells types and string boundaries apart", "[scene][identity]") {
  // An array of two strings and one string that concatenates them: different texts.
  const toml::value two = parse_toml("a = [\"x\", \"y\"]");
  const toml::value one = parse_toml("a = [\"xy\"]");
  CHECK(canonical_text(two) != canonical_text(one));
  // true and the string "true".
  CHECK(canonical_text(parse_toml("a = true")) != canonical_text(parse_toml("a = \"true\"")));
}

/// This test's own folder (tests/support/temp_dir.hpp).
using OwnFolder = testing::TempDir;

TEST_CASE("a modal-data file's content is part of the scene hash", "[scene][identity]") {
  const OwnFolder folder;
  flexible::BeamParameters p;
  p.origin = Eigen::Vector3d(0.1, 0.0, 0.0);
  p.length = 1.0;
  p.elements = 4;
  p.EA = 1e5;
  p.EI_y = p.EI_z = 3.2;
  const std::string scene_text =
      "[scene]\nname = \"f\"\nend_time = 1.0\noutput_step = 0.1\n"
      "[[body]]\nname = \"f\"\nmass = 10.0\ninertia = [0.5, 0.5, 1.0]\nmodal = \"m.toml\"\n";
  std::ofstream(folder.path() / "scene.toml") << scene_text;
  const std::string scene_file = (folder.path() / "scene.toml").string();
  write_modal_data(flexible::make_beam_modal_data(p, 3), (folder.path() / "m.toml").string());
  const std::string first = read_scene(scene_file).hash;
  // The same scene text with a stiffer beam in its modal file: another scene.
  p.EI_y = p.EI_z = 3.3;
  write_modal_data(flexible::make_beam_modal_data(p, 3), (folder.path() / "m.toml").string());
  CHECK(read_scene(scene_file).hash != first);
  // The scene and its file moved elsewhere together: the same scene.
  p.EI_y = p.EI_z = 3.2;
  std::filesystem::create_directory(folder.path() / "moved");
  std::ofstream(folder.path() / "moved" / "scene.toml") << scene_text;
  write_modal_data(flexible::make_beam_modal_data(p, 3),
                   (folder.path() / "moved" / "m.toml").string());
  CHECK(read_scene((folder.path() / "moved" / "scene.toml").string()).hash == first);
}

}  // namespace
}  // namespace flexref::scene
