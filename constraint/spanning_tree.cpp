#include "constraint/spanning_tree.hpp"

#include <deque>
#include <string>

#include "rotation/euler_parameters.hpp"

namespace flexref::constraint {
namespace {

MobilizerKind mobilizer_kind(JointType type) {
  switch (type) {
    case JointType::kRevolute:
      return MobilizerKind::kRevolute;
    case JointType::kPrismatic:
      return MobilizerKind::kPrismatic;
    case JointType::kCylindrical:
      return MobilizerKind::kCylindrical;
    case JointType::kUniversal:
      return MobilizerKind::kUniversal;
    case JointType::kFixed:
      return MobilizerKind::kFixed;
    default:
      return MobilizerKind::kSpherical;
  }
}

/// An end's frame J in the world at a state: its axes and its point.
struct WorldEnd {
  Eigen::Matrix3d R_WJ;
  Eigen::Vector3d p_WJ;
};

WorldEnd world_end(const JointEnd& e, const std::vector<core::Body>& bodies,
                   const core::State& state) {
  if (e.body == kGround) return {e.R_BJ, e.p_BoP_B};
  const core::BodyState& s = state[static_cast<std::size_t>(e.body)];
  const core::Body& b = bodies[static_cast<std::size_t>(e.body)];
  const Eigen::Matrix3d R_WB = rotation::rotation_matrix(s.theta_WB);
  return {R_WB * e.R_BJ, s.p_WBr + R_WB * (e.p_BoP_B - b.p_BoBr_B())};
}

/// The mobilizer of tree joint j whose child end is `child_end` (the other end the parent's).
Mobilizer joint_mobilizer(const IdealJointSpec& joint, int j, bool child_is_a,
                          const std::vector<core::Body>& bodies, const core::State& assembled) {
  const JointEnd& parent = child_is_a ? joint.b : joint.a;
  const JointEnd& child = child_is_a ? joint.a : joint.b;
  Mobilizer m;
  m.kind = mobilizer_kind(joint.type);
  m.joint = j;
  m.parent = parent.body;
  m.child = child.body;
  // The joint's own end frames (ideal_joint.hpp), their points from each body's Br.
  m.R_PF = parent.R_BJ;
  m.p_PrF_P = parent.p_BoP_B;
  if (parent.body != kGround) {
    m.p_PrF_P -= bodies[static_cast<std::size_t>(parent.body)].p_BoBr_B();
  }
  m.R_CM = child.R_BJ;
  m.p_CrM_C = child.p_BoP_B - bodies[static_cast<std::size_t>(child.body)].p_BoBr_B();
  if (m.kind == MobilizerKind::kUniversal) {
    // C: R_FM assembled, its z turned exactly perpendicular to F's z and x re-orthogonalized.
    const Eigen::Matrix3d R_FM = world_end(parent, bodies, assembled).R_WJ.transpose() *
                                 world_end(child, bodies, assembled).R_WJ;
    Eigen::Vector3d z = R_FM.col(2);
    z.z() = 0.0;
    if (!(z.norm() > 0.5)) {
      throw std::invalid_argument("joint '" + joint.name +
                                  "': the universal joint's axes are not perpendicular in the "
                                  "assembled configuration");
    }
    z.normalize();
    Eigen::Vector3d x = R_FM.col(0) - R_FM.col(0).dot(z) * z;
    x.normalize();
    m.C << x, z.cross(x), z;
  }
  return m;
}

}  // namespace

bool can_be_tree_joint(const IdealJointSpec& joint) {
  if (joint.drive.active || joint.a.node >= 0 || joint.b.node >= 0) return false;
  return joint.type != JointType::kDistance;
}

SpanningTree spanning_tree(const std::vector<core::Body>& bodies,
                           const std::vector<IdealJointSpec>& joints,
                           const core::State& assembled) {
  for (const core::Body& b : bodies) {
    if (b.is_flexible()) {
      throw std::invalid_argument("body '" + b.name() +
                                  "' is flexible: the reduced (joint-coordinate) form describes "
                                  "rigid bodies only");
    }
    if (b.is_prescribed()) {
      throw std::invalid_argument("body '" + b.name() +
                                  "' has prescribed motion: the reduced form has no coordinates "
                                  "for a pose that is a law of time");
    }
  }
  SpanningTree tree;
  const int n = static_cast<int>(bodies.size());
  tree.body_mobilizer.assign(static_cast<std::size_t>(n), -1);
  std::vector<bool> used(joints.size(), false);
  std::deque<int> queue;
  const auto add = [&](Mobilizer m) {
    m.q_offset = tree.position_count;
    m.u_offset = tree.velocity_count;
    tree.position_count += position_count(m.kind);
    tree.velocity_count += velocity_count(m.kind);
    tree.body_mobilizer[static_cast<std::size_t>(m.child)] =
        static_cast<int>(tree.mobilizers.size());
    queue.push_back(m.child);
    tree.mobilizers.push_back(m);
  };
  const auto in_tree = [&](int body) {
    return body == kGround || tree.body_mobilizer[static_cast<std::size_t>(body)] >= 0;
  };
  const auto search = [&](int root) {
    queue.push_back(root);
    while (!queue.empty()) {
      const int x = queue.front();
      queue.pop_front();
      if (x == kGround) {
        for (int b = 0; b < n; ++b) {
          const core::Body& body = bodies[static_cast<std::size_t>(b)];
          if (body.motion() != core::MotionKind::kPivot || in_tree(b)) continue;
          // F: the world axes at the pivot (Br, fixed); M: the body's frame at Br.
          Mobilizer m;
          m.kind = MobilizerKind::kPivot;
          m.child = b;
          m.p_PrF_P = assembled[static_cast<std::size_t>(b)].p_WBr;
          add(m);
        }
      }
      for (std::size_t j = 0; j < joints.size(); ++j) {
        const IdealJointSpec& joint = joints[j];
        if (used[j] || !can_be_tree_joint(joint)) continue;
        const bool a_here = joint.a.body == x, b_here = joint.b.body == x;
        if (!(a_here || b_here)) continue;
        const int other = a_here ? joint.b.body : joint.a.body;
        if (in_tree(other)) continue;
        used[j] = true;
        add(joint_mobilizer(joint, static_cast<int>(j), /*child_is_a=*/b_here, bodies, assembled));
      }
    }
  };
  search(kGround);
  for (int b = 0; b < n; ++b) {
    if (in_tree(b)) continue;
    Mobilizer m;  // a free root: F = W at the origin, M = B at Br
    m.kind = MobilizerKind::kFree;
    m.child = b;
    add(m);
    queue.pop_back();
    search(b);
  }
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (!used[j]) tree.closures.push_back(static_cast<int>(j));
  }
  return tree;
}

}  // namespace flexref::constraint
