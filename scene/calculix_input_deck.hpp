#pragma once
/// \file calculix_input_deck.hpp
/// What `flexref import-modes` reads from a CalculiX input deck (JOB.inp): the nodes with their
/// coordinates (`*NODE`), the node sets (`*NSET, NSET=name [, GENERATE]`, data lines of node
/// numbers and names of sets defined before, or "first, last, increment" with GENERATE; the sets
/// named by `*NODE, NSET=name`) and which directions `*BOUNDARY` holds at which node (data lines
/// "node or set, first direction[, last direction[, value]]"). `*INCLUDE, INPUT=file` is followed
/// (relative to the including file). Keywords and set names are case-insensitive, as in ccx;
/// `**` starts a comment line. The .frd holds no sets, and the deck is the only place that says
/// where a shell or beam node that ccx expanded into solid nodes lies and which of its
/// directions a boundary condition holds (docs/calculix.md, "Shells and beams").
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

namespace flexref::scene {

struct CalculixDeck {
  std::string file;
  std::map<int, Eigen::Vector3d> nodes;          ///< *NODE: number → coordinates
  std::map<std::string, std::vector<int>> sets;  ///< upper-case name → node numbers (as listed)
  /// *BOUNDARY: node number → bit d−1 set for each held direction d = 1…6 (every *BOUNDARY of
  /// the deck: the boundary conditions of its frequency steps).
  std::map<int, unsigned> boundary;
};

/// Reads the deck at `path`. Throws core::InputError naming the file and line of a malformed
/// line (a node number or coordinate that is not a number, *BOUNDARY directions that are not
/// first ≤ last from 1, a set used before it is defined). Directions above 6 (temperatures,
/// pressures) are not recorded.
CalculixDeck read_calculix_deck(const std::string& path);

/// The node numbers of set `name` in the deck at `path`, sorted, without repeats. Throws
/// core::InputError naming the file and line of a malformed line, or the deck when the set is
/// not defined (listing the sets that are).
std::vector<int> read_calculix_node_set(const std::string& path, const std::string& name);

}  // namespace flexref::scene
