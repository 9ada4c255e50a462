#pragma once
/// \file spanning_tree.hpp
/// The spanning tree of a model's ideal joints that the reduced (joint-coordinate) form
/// integrates along (docs/reduced_coordinates.md, "Spanning tree"): one mobilizer per body
/// (constraint/mobilizer.hpp), parents before children, and the joints left out of the tree, the
/// loop closures, whose rows the reduced form enforces with multipliers.
///
/// The choice is breadth-first from the ground: the ground's children first (the pivot bodies
/// on their pivots in body order, then the bodies its joints reach in scene order), then each
/// body's in the order it was reached; a body no joint reaches from the ground becomes a free
/// root (in body order) and the search goes on from it. A joint enters the tree when it reaches a
/// body not yet in it and it is a spherical, revolute, prismatic, cylindrical, universal or
/// fixed joint that is not driven; every other joint (distance, driven, or between two bodies
/// already in the tree) is a closure. On Andrews' squeezer this is the IVP test set's own choice:
/// the seven joints O, F, B, A5, A7, G, H in the tree, E3, E4, E6 (the three loops) closing it.
#include <stdexcept>
#include <vector>

#include "constraint/ideal_joint.hpp"
#include "constraint/mobilizer.hpp"
#include "core/body.hpp"
#include "core/state.hpp"

namespace flexref::constraint {

struct SpanningTree {
  std::vector<Mobilizer> mobilizers;  ///< one per body, every parent before its children
  std::vector<int> closures;          ///< the joints outside the tree, in scene order
  std::vector<int> body_mobilizer;    ///< per body: its mobilizer's index
  int position_count = 0;             ///< size of q
  int velocity_count = 0;             ///< size of u
};

/// Whether a joint can be a tree joint (kind and drive, both ends rigid points).
bool can_be_tree_joint(const IdealJointSpec& joint);

/// The spanning tree of `joints` on `bodies`; `assembled` is a state satisfying the joints (the
/// model's consistent initial state): it fixes a pivot root's world point and a universal joint's
/// C. Throws std::invalid_argument naming the body for what the reduced form cannot represent: a
/// flexible body (its modal coordinates and node ends are not part of the rigid tree) and a body
/// whose motion is prescribed (its pose a law of time, not coordinates).
SpanningTree spanning_tree(const std::vector<core::Body>& bodies,
                           const std::vector<IdealJointSpec>& joints, const core::State& assembled);

}  // namespace flexref::constraint
