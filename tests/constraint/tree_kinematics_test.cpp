/// \file tree_kinematics_test.cpp
/// Forward kinematics of a spanning tree (constraint/tree_kinematics.hpp) keeps the exact zeros
/// of a planar mechanism with axis-aligned frames: the out-of-plane rows of S (v_z, ω̄_x, ω̄_y) are
/// exactly zero, not at rounding level, so that the closures' rank-revealing row choice
/// (constraint/reduced_model.hpp) sees a planar loop's out-of-plane rows as the zero rows they
/// are. (Euler parameters composed by quaternion products, tried for speed, left ~1e-16 there;
/// the slider crank's choice then took a numerically zero row and its first evaluation failed
/// on the Schur pivot: docs/reduced_coordinates.md, "Cost".)
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

}  // namespace flexref::constraint
