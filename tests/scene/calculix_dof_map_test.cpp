/// Tests of the rows of ccx's matrices that the .frd does not show (scene/calculix_dof_map.hpp,
/// scene/calculix_condensation.hpp) and of the deck's coordinates and boundary conditions
/// (scene/calculix_input_deck.hpp), on synthetic input laid out as ccx 2.20 writes it (measured
/// on its S8R, S4, B31, B32R and C3D8I decks: docs/calculix.md). tests/app/import_modes_test.cpp
/// runs ccx itself.
#include "scene/calculix_dof_map.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "scene/calculix_condensation.hpp"
#include "scene/calculix_input_deck.hpp"
#include "tests/support/temp_dir.hpp"

namespace fs = std::filesystem;
using namespace flexref;
using Catch::Matchers::Contains;
using scene::CalculixRow;

namespace {

/// .frd nodes (no modes: the map reads only nodes).
scene::CalculixModes frd_nodes(const std::vector<int>& ids,
                               const std::vector<Eigen::Vector3d>& positions) {
  scene::CalculixModes frd;
  frd.file = "job.frd";
  frd.node_ids = ids;
  frd.positions.resize(3, static_cast<Eigen::Index>(ids.size()));
  for (std::size_t k = 0; k < ids.size(); ++k) {
    frd.positions.col(static_cast<Eigen::Index>(k)) = positions[k];
  }
  return frd;
}

/// A .dof as "node.direction" pairs (directions 1-3).
scene::CalculixMatrices dof(const std::vector<std::pair<int, int>>& rows) {
  scene::CalculixMatrices m;
  m.dof_file = "job.dof";
  for (const auto& [node, direction] : rows) {
    m.dof_node.push_back(node);
    m.dof_direction.push_back(direction - 1);
  }
  return m;
}

std::vector<std::pair<int, int>> xyz(const std::vector<int>& nodes) {
  std::vector<std::pair<int, int>> out;
  for (const int n : nodes) {
    for (int a = 1; a <= 3; ++a) out.emplace_back(n, a);
  }
  return out;
}

scene::CalculixDeck deck_with(const std::vector<std::pair<int, Eigen::Vector3d>>& nodes) {
  scene::CalculixDeck deck;
  deck.file = "job.inp";
  for (const auto& [id, x] : nodes) deck.nodes[id] = x;
  return deck;
}

/// Requires a core::InputError from map_calculix_dofs naming job.dof with `fragment`.
void require_map_error(const scene::CalculixModes& frd, const scene::CalculixMatrices& matrices,
                       const scene::CalculixDeck* deck, const std::string& fragment) {
  try {
    (void)scene::map_calculix_dofs(frd, matrices, deck);
    FAIL("accepted");
  } catch (const core::InputError& e) {
    INFO(e.what());
    CHECK(e.file() == "job.dof");
    CHECK_THAT(std::string(e.what()), Contains(fragment));
  }
}

}  // namespace

TEST_CASE("dof map: solid nodes, and the bubble amplitudes ccx adds for C3D8I", "[calculix]") {
  const scene::CalculixModes frd =
      frd_nodes({1, 2}, {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0)});
  std::vector<std::pair<int, int>> rows = xyz({1, 2, 3});  // node 3: numbered after the mesh
  const scene::CalculixDofMap map = scene::map_calculix_dofs(frd, dof(rows), nullptr);
  for (int r = 0; r < 6; ++r) {
    CHECK(map.kind[static_cast<std::size_t>(r)] == CalculixRow::kNode);
    CHECK(map.node[static_cast<std::size_t>(r)] == r / 3);
  }
  CHECK(map.internal == std::vector<int>{6, 7, 8});
  CHECK(map.kind[6] == CalculixRow::kCondensed);
  CHECK(map.names == std::vector<std::string>{"n1", "n2"});
  CHECK(map.added.empty());

  SECTION("a .frd node without a row: the meshes differ, and the message says how") {
    rows = xyz({1});
    require_map_error(frd, dof(rows), nullptr, "job.frd has 2 nodes (1-2), the matrices rows of 1");
  }
  SECTION("a .frd node listed twice is not an expanded node") {
    rows.emplace_back(2, 1);
    require_map_error(frd, dof(rows), nullptr, "node 2 direction 1 is listed twice");
  }
  SECTION(
      "rows of a node that is not in the .frd, more than a bubble node's: a shell needs the deck") {
    rows = xyz({1, 2, 5, 5});
    require_map_error(frd, dof(rows), nullptr, "the input deck is needed");
  }
}

TEST_CASE("dof map: a shell node expanded through the thickness, free and held", "[calculix]") {
  // Shell node 1 at the origin, t = 0.01: ccx's expanded nodes 10 (bottom), 11 (mid), 12 (top)
  // and, for a mid-side node 2 at x = 1, 13 and 15 (its mid node 14 unused, not in the .frd).
  const scene::CalculixModes frd =
      frd_nodes({10, 11, 12, 13, 15}, {Eigen::Vector3d(0, 0, -0.005), Eigen::Vector3d(0, 0, 0),
                                       Eigen::Vector3d(0, 0, 0.005), Eigen::Vector3d(1, 0, -0.005),
                                       Eigen::Vector3d(1, 0, 0.005)});
  scene::CalculixDeck deck =
      deck_with({{1, Eigen::Vector3d(0, 0, 0)}, {2, Eigen::Vector3d(1, 0, 0)}});
  // The .dof names the expanded rows by the shell node, in the expanded nodes' order.
  std::vector<std::pair<int, int>> rows = xyz({1, 1, 1, 2, 2});
  SECTION("free: every row is an expanded node's") {
    const scene::CalculixDofMap map = scene::map_calculix_dofs(frd, dof(rows), &deck);
    for (std::size_t r = 0; r < rows.size(); ++r) {
      CHECK(map.kind[r] == CalculixRow::kNode);
      CHECK(map.node[r] == static_cast<int>(r / 3));
    }
    // The mid node lies at the shell node: it takes its name; node 2 is added back as the mean
    // of bottom and top (ccx's 2D value of a node without a mid node).
    CHECK(map.names == std::vector<std::string>{"n1-1", "n1", "n1-3", "n2-1", "n2-2"});
    REQUIRE(map.added.size() == 1);
    CHECK(map.added[0].number == 2);
    CHECK(map.added[0].nodes == std::vector<int>{3, 4});
    CHECK(map.added[0].weights == std::vector<double>{0.5, 0.5});
    CHECK(map.expanded_nodes == 5);
  }
  SECTION("held: the deck's node keeps the held translations, ahead of the expanded rows") {
    deck.boundary[1] = 0x3f;  // *BOUNDARY 1, 1, 6
    // ccx: rows 1.1-1.3 of node 1 itself, a dependent expanded node (no rows), one rotation
    // node of one row per held rotation (98, 99), numbered last.
    rows = {{1, 1}, {1, 2}, {1, 3}};
    for (const auto& r : xyz({1, 1, 2, 2})) rows.push_back(r);
    rows.insert(rows.end(), {{98, 1}, {99, 1}});
    const scene::CalculixDofMap map = scene::map_calculix_dofs(frd, dof(rows), &deck);
    for (int r = 0; r < 3; ++r) CHECK(map.kind[static_cast<std::size_t>(r)] == CalculixRow::kHeld);
    for (int r = 3; r < 9; ++r) {
      CHECK(map.kind[static_cast<std::size_t>(r)] == CalculixRow::kCondensed);
    }
    for (int r = 9; r < 15; ++r) CHECK(map.kind[static_cast<std::size_t>(r)] == CalculixRow::kNode);
    CHECK(map.kind[15] == CalculixRow::kHeld);
    CHECK(map.kind[16] == CalculixRow::kHeld);
    CHECK(map.held_rows == 5);
    CHECK(map.constrained_owners == std::vector<int>{1});
  }
  SECTION("held rows that are not the held translations cannot be told apart") {
    deck.boundary[1] = 0x4;  // direction 3 only
    require_map_error(frd, dof(rows), &deck, "cannot tell the rows of shell or beam node 1 apart");
  }
}

TEST_CASE("condensation: a mode's rows the .frd does not show are its own eigen-equation's",
          "[calculix]") {
  // A generalized eigenproblem of 5 rows, rows 3 and 4 not shown: the recovered eigenvector is
  // the exact one, to the rounding of the solves (condition of K − λM on the condensed rows).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd A(5, 5);
  Eigen::MatrixXd B(5, 5);
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j) {
      A(i, j) = u(rng);
      B(i, j) = u(rng);
    }
  }
  const Eigen::MatrixXd K = A * A.transpose() + 5.0 * Eigen::MatrixXd::Identity(5, 5);
  const Eigen::MatrixXd M = B * B.transpose() + 5.0 * Eigen::MatrixXd::Identity(5, 5);
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, M);
  scene::CalculixDofMap map;
  map.kind = {CalculixRow::kNode, CalculixRow::kNode, CalculixRow::kNode, CalculixRow::kCondensed,
              CalculixRow::kCondensed};
  map.node = {0, 0, 0, -1, -1};
  map.direction = {0, 1, 2, 0, 1};
  const Eigen::SparseMatrix<double> Ks = K.sparseView();
  const Eigen::SparseMatrix<double> Ms = M.sparseView();
  const scene::CalculixCondensation condensation(map, Ks, Ms);
  for (int i = 0; i < 5; ++i) {
    const Eigen::VectorXd phi = eig.eigenvectors().col(i);
    const Eigen::VectorXd recovered = condensation.mode(phi.head(3), eig.eigenvalues()(i));
    // Entries O(1), K and M well conditioned (shifted by 5 I): rounding ~1e-15, with the
    // eigen-solver's own residual; 1e-10 leaves room for λ near a condensed eigenvalue.
    CHECK((recovered - phi).norm() < 1e-10 * phi.norm());
  }
  // A field of the solid at rest: K_uu f_u = −K_uo f_o.
  const Eigen::VectorXd f_o = Eigen::Vector3d(1.0, -2.0, 0.5);
  const Eigen::MatrixXd f = condensation.static_fields(f_o);
  const Eigen::VectorXd residual = (K * f).col(0).tail(2);
  // K's entries O(10): rounding ~1e-14 of the solve.
  CHECK(residual.norm() < 1e-12);
}

TEST_CASE("input deck: coordinates and the directions *BOUNDARY holds", "[calculix]") {
  const testing::TempDir tmp("deck");
  const fs::path& dir = tmp.path();
  std::ofstream(dir / "job.inp") << "*NODE, NSET=ALL\n1, 0.5, -1e-2, +3.\n2, 1.0\n"
                                    "*NSET, NSET=ROOT\n1\n*BOUNDARY\nROOT, 1, 3\n2, 5\n"
                                    "*BOUNDARY, OP=NEW\n1, 11, 11\n";
  const scene::CalculixDeck deck = scene::read_calculix_deck((dir / "job.inp").string());
  REQUIRE(deck.nodes.size() == 2);
  CHECK(deck.nodes.at(1) == Eigen::Vector3d(0.5, -1e-2, 3.0));
  CHECK(deck.nodes.at(2) == Eigen::Vector3d(1.0, 0.0, 0.0));  // blank coordinates are 0
  CHECK(deck.boundary.at(1) == 0x7u);                         // the temperature (11) is not held
  CHECK(deck.boundary.at(2) == 0x10u);
  std::ofstream(dir / "bad.inp") << "*NODE\n1, 0, x, 0\n";
  try {
    (void)scene::read_calculix_deck((dir / "bad.inp").string());
    FAIL("accepted");
  } catch (const core::InputError& e) {
    CHECK(e.line() == 2);
    CHECK_THAT(std::string(e.what()), Contains("coordinate \"x\" is not a number"));
  }
}
