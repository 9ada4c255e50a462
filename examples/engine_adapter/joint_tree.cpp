#include "examples/engine_adapter/joint_tree.hpp"

#include <algorithm>
#include <deque>
#include <numeric>

#include "constraint/ideal_joints.hpp"
#include "examples/engine_adapter/engine.hpp"

namespace flexref::engines {
namespace {

/// Union–find over the ground (node 0) and the bodies (node b + 1).
class Components {
 public:
  explicit Components(std::size_t nodes) : parent_(nodes) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  /// Joins the components of x and y; false when they were one already.
  bool join(std::size_t x, std::size_t y) {
    const std::size_t a = find(x), b = find(y);
    if (a == b) return false;
    parent_[std::max(a, b)] = std::min(a, b);
    return true;
  }

 private:
  std::vector<std::size_t> parent_;
};

std::size_t node(int body) { return static_cast<std::size_t>(body + 1); }

}  // namespace

const std::vector<constraint::IdealJointSpec>& built_ideal_joints(const scene::Scene& scene) {
  static const std::vector<constraint::IdealJointSpec> none;
  const auto* joints = dynamic_cast<const constraint::IdealJoints*>(scene.model->constraints());
  return joints == nullptr ? none : joints->joints();
}

JointTree plan_joint_tree(const scene::Scene& scene, const JointSupport& support) {
  const std::vector<constraint::IdealJointSpec>& joints = built_ideal_joints(scene);
  const std::size_t n = scene.spec.bodies.size();
  JointTree tree;
  tree.links.assign(n, TreeLink{});
  Components components(n + 1);
  std::vector<bool> pivot(n, false);
  for (std::size_t b = 0; b < n; ++b) {
    pivot[b] = scene.spec.bodies[b].description.motion == core::MotionKind::kPivot;
    if (pivot[b]) components.join(0, node(static_cast<int>(b)));
  }

  // Tree-only joints first, driven ones first within each tier; the scene's order otherwise.
  std::vector<std::size_t> candidates;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (support.as_tree(joints[j]).empty()) candidates.push_back(j);
  }
  const auto tier = [&](std::size_t j) {
    const bool loop_capable = support.as_loop(joints[j]).empty();
    return (loop_capable ? 2 : 0) + (joints[j].drive.active ? 0 : 1);
  };
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](std::size_t x, std::size_t y) { return tier(x) < tier(y); });
  std::vector<bool> in_tree(joints.size(), false);
  for (std::size_t j : candidates) {
    in_tree[j] = components.join(node(joints[j].a.body), node(joints[j].b.body));
  }
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (in_tree[j]) continue;
    const std::string why = support.as_loop(joints[j]);
    if (!why.empty()) {
      const std::string tree_why = support.as_tree(joints[j]);
      throw MappingError(
          scene.spec.ideal_joints[j].source,
          "ideal " + std::string(constraint::to_string(joints[j].type)) + " joint '" +
              joints[j].name + "': " +
              (tree_why.empty() ? "it closes a loop of " + support.engine +
                                      "'s tree of bodies (its two bodies are joined already), "
                                      "and as a loop closure " +
                                      why
                                : why));
    }
    tree.loops.push_back(static_cast<int>(j));
  }

  // Parents first: breadth-first from the ground (and the pivots, hung from it), then from the
  // first body of every tree the ground does not reach.
  std::vector<std::vector<std::size_t>> edges(n + 1);
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (!in_tree[j]) continue;
    edges[node(joints[j].a.body)].push_back(j);
    edges[node(joints[j].b.body)].push_back(j);
  }
  std::vector<bool> placed(n + 1, false);
  const auto hang_below = [&](std::size_t root) {
    std::deque<std::size_t> queue{root};
    placed[root] = true;
    while (!queue.empty()) {
      const std::size_t x = queue.front();
      queue.pop_front();
      if (x > 0) tree.order.push_back(static_cast<int>(x - 1));
      for (std::size_t j : edges[x]) {
        const bool child_is_a = node(joints[j].b.body) == x;
        const std::size_t child = node(child_is_a ? joints[j].a.body : joints[j].b.body);
        if (placed[child]) continue;
        placed[child] = true;
        tree.links[child - 1] = TreeLink{static_cast<int>(x) - 1, static_cast<int>(j), child_is_a};
        queue.push_back(child);
      }
    }
  };
  placed[0] = true;
  // The ground's tree joints, each child with its subtree; then the pivot bodies (roots below
  // the ground) with theirs; then the free roots.
  for (std::size_t j : edges[0]) {
    const bool child_is_a = joints[j].b.body == constraint::kGround;
    const std::size_t child = node(child_is_a ? joints[j].a.body : joints[j].b.body);
    if (placed[child]) continue;
    tree.links[child - 1] = TreeLink{-1, static_cast<int>(j), child_is_a};
    hang_below(child);
  }
  for (int pass = 0; pass < 2; ++pass) {
    for (std::size_t b = 0; b < n; ++b) {
      if ((pass == 0) != pivot[b] || placed[node(static_cast<int>(b))]) continue;
      hang_below(node(static_cast<int>(b)));
    }
  }
  return tree;
}

}  // namespace flexref::engines
