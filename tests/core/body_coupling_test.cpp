#include "core/body_coupling.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstddef>
#include <vector>

#include "scene/scene_reader.hpp"
#include "tests/support/chain_scene.hpp"

namespace flexref::core {
namespace {

TEST_CASE("body coupling: a chain's joints and a spring, not gravity", "[core]") {
  // 6 rods on spherical joints (rod k to rod k − 1), gravity on all, a spring from rod 1 to 4.
  const scene::Scene scene = scene::parse_scene(testing::chain_scene_text(6, 0.5, 1, 4), "chain");
  const std::vector<std::vector<int>> coupling = body_coupling(*scene.model);
  REQUIRE(coupling.size() == 6);
  CHECK(coupling[0] == std::vector<int>{0, 1});
  CHECK(coupling[1] == std::vector<int>{0, 1, 2, 4});
  CHECK(coupling[3] == std::vector<int>{2, 3, 4});
  CHECK(coupling[4] == std::vector<int>{1, 3, 4, 5});
  CHECK(coupling[5] == std::vector<int>{4, 5});
  // The elements' part alone: the spring's ends, every body itself, no joint.
  const std::vector<std::vector<int>> elements = element_coupling(*scene.model);
  REQUIRE(elements.size() == 6);
  CHECK(elements[0] == std::vector<int>{0});
  CHECK(elements[1] == std::vector<int>{1, 4});
  CHECK(elements[3] == std::vector<int>{3});
  CHECK(elements[4] == std::vector<int>{1, 4});
}

TEST_CASE("body colouring: no two bodies of a colour are read by one body", "[core]") {
  const scene::Scene scene = scene::parse_scene(testing::chain_scene_text(9, 0.5, 1, 4), "chain");
  const std::vector<std::vector<int>> coupling = body_coupling(*scene.model);
  const std::vector<int> colour = colour_bodies(coupling);
  // Every body's equations read at most one body of each colour (what lets the differences
  // move a whole colour at once).
  for (const std::vector<int>& read : coupling) {
    for (std::size_t a = 0; a < read.size(); ++a) {
      for (std::size_t b = a + 1; b < read.size(); ++b) {
        CHECK(colour[static_cast<std::size_t>(read[a])] !=
              colour[static_cast<std::size_t>(read[b])]);
      }
    }
  }
  // A plain chain needs three colours whatever its length.
  const scene::Scene chain = scene::parse_scene(testing::chain_scene_text(40), "chain_40");
  int colours = 0;
  for (const int c : colour_bodies(body_coupling(*chain.model))) colours = std::max(colours, c + 1);
  CHECK(colours == 3);
}

}  // namespace
}  // namespace flexref::core
