#include "scene/calculix_dof_map.hpp"

#include <algorithm>
#include <bit>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "core/error.hpp"

namespace flexref::scene {
namespace {

/// "5, 6, 7, …" of the first few numbers of a list.
std::string first_few(const std::vector<int>& ids) {
  std::ostringstream s;
  for (std::size_t i = 0; i < ids.size() && i < 5; ++i) s << (i ? ", " : "") << ids[i];
  if (ids.size() > 5) s << ", …";
  return s.str();
}

/// "1-525" or "none": the range of a sorted list of node numbers.
std::string range_of(const std::vector<int>& sorted) {
  if (sorted.empty()) return "none";
  return std::to_string(sorted.front()) + "-" + std::to_string(sorted.back());
}

/// The rows of one node number of the .dof, in file order.
struct RowGroup {
  std::vector<int> rows;
  std::vector<int> directions;  // 0-based
};

bool is_xyz_repeated(const std::vector<int>& directions) {
  for (std::size_t i = 0; i < directions.size(); ++i) {
    if (directions[i] != static_cast<int>(i % 3)) return false;
  }
  return directions.size() % 3 == 0;
}

}  // namespace

CalculixDofMap map_calculix_dofs(const CalculixModes& frd, const CalculixMatrices& matrices,
                                 const CalculixDeck* deck) {
  const auto n_nodes = static_cast<int>(frd.node_ids.size());
  const auto n_rows = static_cast<int>(matrices.dof_node.size());
  const std::string& dof = matrices.dof_file;
  std::map<int, int> frd_index;
  for (int k = 0; k < n_nodes; ++k) frd_index.emplace(frd.node_ids[static_cast<std::size_t>(k)], k);

  CalculixDofMap map;
  map.kind.assign(static_cast<std::size_t>(n_rows), CalculixRow::kCondensed);
  map.node.assign(static_cast<std::size_t>(n_rows), -1);
  map.direction = matrices.dof_direction;
  map.owner.assign(static_cast<std::size_t>(n_nodes), 0);
  map.names.assign(static_cast<std::size_t>(n_nodes), "");

  // Rows by node number; rows of .frd nodes are mapped at once.
  std::map<int, RowGroup> others;
  std::vector<int> rows_of_node(static_cast<std::size_t>(n_nodes), 0);
  std::vector<unsigned> seen(static_cast<std::size_t>(n_nodes), 0);
  for (int r = 0; r < n_rows; ++r) {
    const int id = matrices.dof_node[static_cast<std::size_t>(r)];
    const int a = matrices.dof_direction[static_cast<std::size_t>(r)];
    const auto it = frd_index.find(id);
    if (it == frd_index.end()) {
      others[id].rows.push_back(r);
      others[id].directions.push_back(a);
      continue;
    }
    const auto k = static_cast<std::size_t>(it->second);
    if (seen[k] & (1u << a)) {
      throw core::InputError(dof, r + 1, "",
                             "node " + std::to_string(id) + " direction " + std::to_string(a + 1) +
                                 " is listed twice; " + frd.file + " shows node " +
                                 std::to_string(id) +
                                 " itself, so it is not a shell or beam node that ccx expanded "
                                 "(the .frd then shows the expanded nodes: *NODE FILE, "
                                 "OUTPUT=3D)");
    }
    seen[k] |= 1u << a;
    ++rows_of_node[k];
    map.kind[static_cast<std::size_t>(r)] = CalculixRow::kNode;
    map.node[static_cast<std::size_t>(r)] = it->second;
    map.owner[k] = id;
    map.names[k] = "n" + std::to_string(id);
  }
  for (int k = 0; k < n_nodes; ++k) {
    const int count = rows_of_node[static_cast<std::size_t>(k)];
    if (count != 0 && count != 3) {
      throw core::InputError(
          dof, 0, "",
          "node " + std::to_string(frd.node_ids[static_cast<std::size_t>(k)]) + " of " + frd.file +
              " has " + std::to_string(count) +
              " of its 3 degrees of freedom in the matrices: they must be those of the free "
              "solid (no boundary conditions in the matrix step: *BOUNDARY, OP=NEW)");
    }
  }

  // Nodes of the .dof that the .frd does not show: shell or beam nodes of the deck, or nodes
  // ccx adds (bubble amplitudes: three rows; a held rotation: one row).
  unsigned deck_rotations = 0;
  std::vector<int> expanded_owners;
  std::vector<int> unknown;
  for (auto& [id, group] : others) {
    const bool deck_node = deck != nullptr && deck->nodes.count(id) > 0;
    if (deck_node) {
      expanded_owners.push_back(id);
      const auto b = deck->boundary.find(id);
      if (b != deck->boundary.end()) deck_rotations |= b->second >> 3;
    } else if (group.rows.size() > 3 ||
               (group.rows.size() == 3 && !is_xyz_repeated(group.directions))) {
      throw core::InputError(
          dof, group.rows.front() + 1, "",
          "node " + std::to_string(id) + " has " + std::to_string(group.rows.size()) +
              " rows but is not a node of " + frd.file +
              (deck == nullptr
                   ? ": a shell or beam node that ccx expanded into solid nodes? Then the input "
                     "deck is needed to map its expansion (JOB.inp next to the .frd, or --inp)"
                   : " nor of " + deck->file));
    }
  }
  for (auto& [id, group] : others) {
    if (std::find(expanded_owners.begin(), expanded_owners.end(), id) != expanded_owners.end()) {
      continue;
    }
    if (group.rows.size() == 3) {
      map.internal.insert(map.internal.end(), group.rows.begin(), group.rows.end());
    } else if (deck_rotations != 0) {
      for (const int r : group.rows) map.kind[static_cast<std::size_t>(r)] = CalculixRow::kHeld;
      map.held_rows += static_cast<int>(group.rows.size());
    } else {
      unknown.push_back(id);
    }
  }
  if (!unknown.empty()) {
    throw core::InputError(dof, others[unknown.front()].rows.front() + 1, "",
                           "node(s) " + first_few(unknown) +
                               " have fewer than 3 rows and are not nodes of " + frd.file +
                               (deck == nullptr ? "" : " nor of " + deck->file) +
                               ": the matrices and the modes come from different meshes");
  }

  // Expanded nodes: the .frd nodes without rows, each to the nearest shell or beam node.
  std::vector<int> unclaimed;
  for (int k = 0; k < n_nodes; ++k) {
    if (rows_of_node[static_cast<std::size_t>(k)] == 0) unclaimed.push_back(k);
  }
  if (!unclaimed.empty() && expanded_owners.empty()) {
    std::vector<int> rowless;
    for (const int k : unclaimed) rowless.push_back(frd.node_ids[static_cast<std::size_t>(k)]);
    std::vector<int> dof_nodes(matrices.dof_node.begin(), matrices.dof_node.end());
    std::sort(dof_nodes.begin(), dof_nodes.end());
    dof_nodes.erase(std::unique(dof_nodes.begin(), dof_nodes.end()), dof_nodes.end());
    std::vector<int> frd_nodes(frd.node_ids.begin(), frd.node_ids.end());
    std::sort(frd_nodes.begin(), frd_nodes.end());
    std::vector<int> foreign;
    for (const auto& [id, group] : others) foreign.push_back(id);
    throw core::InputError(
        dof, 0, "",
        "the matrices and the modes come from different meshes: " + frd.file + " has " +
            std::to_string(n_nodes) + " nodes (" + range_of(frd_nodes) +
            "), the matrices rows of " + std::to_string(dof_nodes.size()) + " nodes (" +
            range_of(dof_nodes) + "); " + std::to_string(rowless.size()) +
            " nodes of the .frd have no row (" + first_few(rowless) + ")" +
            (foreign.empty()
                 ? std::string()
                 : ", " + std::to_string(foreign.size()) +
                       " nodes of the matrices are not in the .frd (" + first_few(foreign) + ")"));
  }
  std::map<int, std::vector<int>> expansion;  // owner → .frd node indices, ascending numbers
  for (const int k : unclaimed) {
    const Eigen::Vector3d x = frd.positions.col(k);
    int best = 0;
    double best_distance = std::numeric_limits<double>::infinity();
    for (const int id : expanded_owners) {
      const double d = (deck->nodes.at(id) - x).squaredNorm();
      if (d < best_distance) {
        best_distance = d;
        best = id;
      }
    }
    expansion[best].push_back(k);
  }
  double size = 0.0;
  for (int k = 0; k < n_nodes; ++k)
    size = std::max(size, frd.positions.col(k).cwiseAbs().maxCoeff());
  for (const int id : expanded_owners) {
    std::vector<int>& nodes = expansion[id];
    const RowGroup& group = others.at(id);
    if (nodes.empty()) {
      throw core::InputError(dof, group.rows.front() + 1, "",
                             "shell or beam node " + std::to_string(id) + " of " + deck->file +
                                 " has rows but no expanded node of " + frd.file +
                                 " lies nearer to it than to another node: the deck, the matrices "
                                 "and the modes are not of the same model");
    }
    std::sort(nodes.begin(), nodes.end(), [&](int a, int b) {
      return frd.node_ids[static_cast<std::size_t>(a)] < frd.node_ids[static_cast<std::size_t>(b)];
    });
    map.expanded_nodes += static_cast<int>(nodes.size());
    const Eigen::Vector3d& at = deck->nodes.at(id);
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      const auto k = static_cast<std::size_t>(nodes[j]);
      map.owner[k] = id;
      // The .frd prints 6 significant digits: a node at the owner agrees to 5e-6 of the size.
      const bool at_owner = (frd.positions.col(nodes[j]) - at).norm() <= 1e-5 * size;
      map.names[k] = "n" + std::to_string(id) + (at_owner ? "" : "-" + std::to_string(j + 1));
    }
    bool owner_is_node = false;
    for (std::size_t j = 0; j < nodes.size(); ++j) {
      owner_is_node = owner_is_node ||
                      map.names[static_cast<std::size_t>(nodes[j])] == "n" + std::to_string(id);
    }
    if (!owner_is_node) {
      // ccx's 1D/2D value of the node (map3dto1d2d): shells across the thickness, beams over the
      // corners of the section.
      CalculixAddedNode added{id, at, {}, {}};
      if (nodes.size() == 3) {
        added.nodes = nodes;
        added.weights = {1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0};
      } else if (nodes.size() == 2) {
        added.nodes = nodes;
        added.weights = {0.5, 0.5};
      } else if (nodes.size() == 4 || nodes.size() == 8) {
        added.nodes.assign(nodes.begin(), nodes.begin() + 4);
        added.weights.assign(4, 0.25);
      } else {
        throw core::InputError(dof, group.rows.front() + 1, "",
                               "node " + std::to_string(id) + " of " + deck->file + " has " +
                                   std::to_string(nodes.size()) + " expanded nodes in " + frd.file +
                                   " (ccx expands a shell node into 2 or 3, a beam node into 4 or "
                                   "8): not a shell or beam expansion flexref knows");
      }
      map.added.push_back(std::move(added));
    }
    const auto b = deck->boundary.find(id);
    const unsigned held = b == deck->boundary.end() ? 0u : (b->second & 7u);
    if (held == 0 && group.rows.size() == 3 * nodes.size() && is_xyz_repeated(group.directions)) {
      for (std::size_t i = 0; i < group.rows.size(); ++i) {
        const auto r = static_cast<std::size_t>(group.rows[i]);
        map.kind[r] = CalculixRow::kNode;
        map.node[r] = nodes[i / 3];
      }
      continue;
    }
    // Held: the deck node's own rows, one per held translation, ahead of the expanded ones.
    const int n_held = std::popcount(held);
    std::vector<int> expected;
    for (int a = 0; a < 3; ++a) {
      if (held & (1u << a)) expected.push_back(a);
    }
    if (static_cast<int>(group.rows.size()) < n_held ||
        !std::equal(expected.begin(), expected.end(), group.directions.begin())) {
      std::ostringstream msg;
      msg << "cannot tell the rows of shell or beam node " << id << " apart: " << group.rows.size()
          << " rows for " << nodes.size() << " expanded nodes, directions";
      for (const int a : group.directions) msg << " " << a + 1;
      msg << "; expected the held translations (";
      for (const int a : expected) msg << " " << a + 1;
      msg << " ) of its *BOUNDARY first";
      throw core::InputError(dof, group.rows.front() + 1, "", msg.str());
    }
    for (int i = 0; i < n_held; ++i) {
      map.kind[static_cast<std::size_t>(group.rows[static_cast<std::size_t>(i)])] =
          CalculixRow::kHeld;
    }
    map.held_rows += n_held;
    map.constrained_owners.push_back(id);
  }
  return map;
}

}  // namespace flexref::scene
