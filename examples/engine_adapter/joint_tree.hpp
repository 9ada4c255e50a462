#pragma once
/// \file joint_tree.hpp
/// A scene's ideal joints as an engine carries them (docs/engines.md, "Ideal joints"): a tree of
/// bodies whose edges are the engine's joints or mobilizers, each body below its parent by one
/// of them, and the joints left over, which close loops of that tree as the engine's
/// constraints. Reduced (tree) coordinates hold a joint exactly; a loop constraint is held by
/// the engine's constraint solver (soft in MuJoCo, projected in Simbody), so the tree takes as
/// many joints as it can.
///
/// The choice (a spanning forest of the graph whose nodes are the ground and the bodies and
/// whose edges are the joints, built joint by joint as Kruskal's algorithm does):
///   1. a pivot body is below the ground (its ball at the pivot) before any joint is placed;
///   2. joints the engine can carry only in the tree come first (a prismatic joint in MuJoCo,
///      which has no prismatic equality constraint; a driven joint in Simbody, whose Motion
///      prescribes a mobilizer), then the others in the scene's order; a joint whose two ends
///      are already connected closes a loop;
///   3. the ground is the root of every tree that reaches it; a tree that does not is hung from
///      its first body in the scene's order, a free body (MuJoCo's free joint, Simbody's Free
///      mobilizer) — "free for roots".
/// A joint the engine can carry neither way is refused (MappingError naming its scene key),
/// never dropped.
#include <functional>
#include <string>
#include <vector>

#include "constraint/ideal_joint.hpp"
#include "examples/engine_adapter/rigid_scene.hpp"
#include "scene/scene.hpp"

namespace flexref::engines {

/// What an engine can carry: each function returns why it cannot carry the joint that way, ""
/// when it can.
struct JointSupport {
  std::string engine;  ///< its name in messages
  std::function<std::string(const constraint::IdealJointSpec&)> as_tree;
  std::function<std::string(const constraint::IdealJointSpec&)> as_loop;
};

struct JointTree {
  std::vector<TreeLink> links;  ///< per body
  std::vector<int> order;       ///< bodies, every parent before its children
  std::vector<int> loops;       ///< ideal joints closing loops, in the scene's order
};

/// The ideal joints of the scene's model as built (their ends' joint frames, drive offsets and
/// distance lengths formed by build_model), in the scene's order; empty without ideal joints.
const std::vector<constraint::IdealJointSpec>& built_ideal_joints(const scene::Scene& scene);

/// The tree of the scene's bodies. Throws MappingError naming the key of the first joint the
/// engine can carry neither in the tree nor as a loop closure.
JointTree plan_joint_tree(const scene::Scene& scene, const JointSupport& support);

}  // namespace flexref::engines
