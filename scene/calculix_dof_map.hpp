#pragma once
/// \file calculix_dof_map.hpp
/// What each row of the matrices that CalculiX stores (calculix_matrices.hpp) is, in terms of
/// the nodes of its .frd (calculix_frd.hpp) — docs/calculix.md, "Internal and expanded nodes".
///
/// ccx's matrices hold the independent degrees of freedom of its *internal* model, which has
/// nodes the .frd does not show:
///  - an incompatible-mode element (C3D8I, and the C3D8I that S4 and B31 become) has three
///    nodes of its own whose three directions are the amplitudes of its bubble modes; they are
///    numbered after every node of the mesh and listed in the .dof under their own numbers;
///  - a shell (S4, S8R, …) or beam (B31, B32R, …) node is expanded into solid nodes through the
///    thickness (shells: bottom, mid, top) or around the section (beams: 4 or 8 points), numbered
///    consecutively after the deck's nodes; the .frd shows these expanded nodes, the .dof names
///    their rows by the deck's node (repeated), in the order of the expanded nodes' numbers;
///  - a boundary condition on a shell or beam node makes ccx keep the deck's node for each held
///    translation (its row comes first, the node's number being below every expanded one), add
///    a node of one direction per held rotation (numbered last), and make some expanded degrees
///    of freedom dependent on these through its constraints (they have no row). The rows of the
///    deck's node and of the added nodes are zero in the modes of the frequency step.
/// The map therefore needs the deck (calculix_input_deck.hpp) when the .dof names nodes that are
/// not in the .frd: its nodes say which rows are shell or beam nodes, where they are (each
/// expanded node belongs to the nearest of them: it lies on the node's normal or in its section
/// plane, so every other node is farther), and its *BOUNDARY lines which of their rows are held.
///
/// A shell or beam node that no expanded node coincides with (a shell node between its bottom and
/// top nodes, a beam node inside its section) is given back to the body as a node of its own,
/// moving as ccx defines it for 1D/2D output (map3dto1d2d): a shell node as the mean across the
/// thickness (bottom, mid, top weighted 1/6, 2/3, 1/6 — Simpson's rule; bottom and top 1/2 each
/// where there is no mid node), a beam node as the mean of the four corners of its section (the
/// first four of its expanded nodes in ccx's numbering). It carries the section's inner mass:
/// nodes on the section's boundary alone cannot have its second moment with positive masses
/// (two layers at ±t/2 give m t²/4, the solid m t²/12).
///
/// Every problem is a core::InputError naming the .dof and saying what differs: .frd nodes with
/// no row, rows of nodes that are neither in the .frd nor the deck's, a node listed twice, an
/// expansion whose rows cannot be told apart, expanded nodes without the deck.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "scene/calculix_frd.hpp"
#include "scene/calculix_input_deck.hpp"
#include "scene/calculix_matrices.hpp"

namespace flexref::scene {

enum class CalculixRow {
  kNode,       ///< a direction of a .frd node: its value in a mode is the .frd's
  kCondensed,  ///< not shown by the .frd (a bubble amplitude, an expanded node tied by ccx's
               ///< constraints): its value in a mode solves its own rows of (K − λM)φ = 0
  kHeld,       ///< held by a boundary condition of the frequency step: zero in every mode
};

/// A shell or beam node of the deck added to the body's nodes (see the file comment).
struct CalculixAddedNode {
  int number = 0;               ///< the deck's node number
  Eigen::Vector3d position;     ///< the deck's coordinates
  std::vector<int> nodes;       ///< .frd node indices of its expansion
  std::vector<double> weights;  ///< its displacement: Σ weights[j] u(nodes[j])
};

struct CalculixDofMap {
  std::vector<CalculixRow> kind;  ///< per matrix row
  std::vector<int> node;          ///< per row: the .frd node index (kNode), −1 otherwise
  std::vector<int> direction;     ///< per row: 0, 1, 2 (x, y, z) as the .dof says
  /// Per .frd node: the deck node it belongs to — its own number for a solid node, the shell or
  /// beam node for an expanded one.
  std::vector<int> owner;
  /// Per .frd node: "n<number>" for a solid node; for an expanded node "n<owner>" when it lies
  /// at the owner (the mid node of a shell's corner), else "n<owner>.<k>", k = 1, 2, … its rank
  /// among the owner's expanded nodes in ccx's numbering (shells: bottom, mid, top).
  std::vector<std::string> names;
  /// Condensed rows of nodes ccx adds inside elements (three rows each, not in the .frd nor
  /// the deck): bubble amplitudes, zero on rigid motions (the import checks that).
  std::vector<int> internal;
  int expanded_nodes = 0;  ///< .frd nodes that are expanded shell or beam nodes
  /// Shell or beam nodes held by a boundary condition: their expansions' rows are condensed.
  std::vector<int> constrained_owners;
  int held_rows = 0;
  /// Shell and beam nodes that the body keeps as nodes of their own, after the .frd's.
  std::vector<CalculixAddedNode> added;
  bool all_nodes() const { return internal.empty() && held_rows == 0 && expanded_nodes == 0; }
};

/// Maps the rows of `matrices` onto the nodes of `frd`; `deck` may be nullptr (then only solid
/// elements, with or without incompatible modes, are mapped). Throws core::InputError.
CalculixDofMap map_calculix_dofs(const CalculixModes& frd, const CalculixMatrices& matrices,
                                 const CalculixDeck* deck);

}  // namespace flexref::scene
