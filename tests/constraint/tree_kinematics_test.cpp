/// \file tree_kinematics_test.cpp
/// Forward kinematics of a spanning tree (constraint/tree_kinematics.hpp) keeps the exact zeros
/// of a planar mechanism with axis-aligned frames: the out-of-plane rows of S (v_z, ω̄_x, ω̄_y) are
/// exactly zero, not at rounding level, so that the closures' rank-revealing row choice
/// (constraint/reduced_model.hpp) sees a planar loop's out-of-plane rows as the zero rows they
/// are. (Euler parameters composed by quaternion products, tried for speed, left ~1e-16 there;
/// the slider crank's choice then took a numerically zero row and its first evaluation failed
/// on the Schur pivot: docs/reduced_coordinates.md, "Cost".) Also: the state alone
/// (evaluate_state, the outputs') is evaluate's to the bit.
#include "constraint/tree_kinematics.hpp"

#include <catch2/catch.hpp>

#include "constraint/reduced_model.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::constraint {

TEST_CASE("tree kinematics: a planar mechanism's out-of-plane rows of S are exactly zero",
          "[reduced]") {
  const scene::Scene scene = scene::read_scene("scenes/slider_crank.toml");
  const ReducedModel reduced(*scene.model);
  const TreeKinematics& k = reduced.kinematics();
  TreeWorkspace ws = k.make_workspace();
  Eigen::VectorXd q, u, u_dot(k.velocity_count());
  reduced.coordinates(scene.model->initial_state(), q, u);
  ReducedWorkspace rws = reduced.make_workspace();
  for (const double h : {0.0, 1e-3, 7e-3, 2e-2}) {
    INFO("q ⊕ h u at h = " << h);
    Eigen::VectorXd q_h(q.size());
    k.advance(q, u, h, q_h);
    k.evaluate(q_h, u, ws);
    for (int b = 0; b < k.body_count(); ++b) {
      for (const int row : {2, 3, 4}) {
        CHECK(ws.S.row(6 * b + row).cwiseAbs().maxCoeff() == 0.0);
        CHECK(ws.bias(6 * b + row) == 0.0);
      }
    }
    // The closure rows it enforces are the loop's in-plane ones: the evaluation's Schur
    // pivots pass (a chosen out-of-plane row would throw SingularConfigurationError).
    CHECK_NOTHROW(reduced.accelerations({0.0, 0.0}, q_h, u, rws, u_dot, 150.0));
  }
}

TEST_CASE("tree kinematics: the state alone is evaluate's, bit for bit", "[reduced]") {
  // Andrews' revolute chains and the heavy top's pivot root; the workspace holds another
  // configuration's state first, so that a part evaluate_state forgot would show as stale.
  for (const char* path : {"scenes/andrews_squeezer.toml", "scenes/heavy_top_spherical.toml"}) {
    const scene::Scene scene = scene::read_scene(path);
    const ReducedModel reduced(*scene.model);
    const TreeKinematics& k = reduced.kinematics();
    Eigen::VectorXd q, u, q_other;
    reduced.coordinates(scene.model->initial_state(), q, u);
    u = Eigen::VectorXd::LinSpaced(k.velocity_count(), 1.0, 3.0);  // rad/s: every body moves
    q_other = q;
    k.advance(q, u, 0.1, q_other);
    TreeWorkspace full = k.make_workspace(), state_only = k.make_workspace();
    k.evaluate(q, u, full);
    k.evaluate(q_other, -u, state_only);
    k.evaluate_state(q, u, state_only);
    for (std::size_t b = 0; b < full.state.size(); ++b) {
      INFO(path << ", body " << b);
      CHECK(state_only.state[b].p_WBr == full.state[b].p_WBr);
      CHECK(state_only.state[b].theta_WB == full.state[b].theta_WB);
      CHECK(state_only.state[b].v_WBr == full.state[b].v_WBr);
      CHECK(state_only.state[b].w_WB_B == full.state[b].w_WB_B);
      CHECK(state_only.R_WB[b] == full.R_WB[b]);
    }
  }
}

}  // namespace flexref::constraint
