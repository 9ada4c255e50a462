/// \file constraint_tracker_test.cpp
/// The joints' tracker (core/constraint_tracker.hpp) and the multipliers an evaluation hands out
/// (core/joint_multipliers_tpl.hpp), on the four-bar started on rows that become ill-conditioned
/// as it turns (the tilt rows of A, B and C set aside: their pivot ratio falls 100-fold by
/// t ≈ 0.22 s while all rows keep their rank, tests/lie/genalpha_joints_test.cpp). An
/// evaluation there chooses other rows for itself: its multipliers belong to those rows, not to
/// the tracker's; it leaves the tracker as it was; and its result does not depend on what its
/// workspace evaluated before. (Here rather than in tests/core: the four-bar is a scene.)
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "scene/build_model.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/solver_options.hpp"

namespace flexref::constraint {
namespace {

/// The four-bar on its rows but the tilt rows of A, B and C (3, 8, 13), and its states at t = 0
/// and t = 0.22 s (CVODE at rtol 1e-10), where the rows' pivot ratio has fallen more than
/// tenfold from the start's (core::kReselectPivotFall; measured: 0.18 of it at 0.21 s, and the
/// rows chosen there keep 1.47 of it).
constexpr double kTurnedTime = 0.22;

struct TrackedFourBar {
  core::Model model;
  std::vector<int> rows;
  core::State start;
  core::State turned;  ///< at t = 0.22 s
};

TrackedFourBar tracked_four_bar() {
  const scene::Scene scene = scene::read_scene("scenes/four_bar.toml");
  std::vector<int> rows;
  for (int r = 0; r < 20; ++r) {
    if (r != 3 && r != 8 && r != 13) rows.push_back(r);
  }
  core::Model model = scene::build_model(scene.spec, core::FlexibleFormulation::kCoupled, rows);
  const reference::ReferenceRun run = reference::solve_reference(
      "cvode", model, core::output_times(kTurnedTime, 0.01), testing::with_rtol(1e-10));
  REQUIRE(run.trajectory.times.back() == kTurnedTime);
  core::State start = run.trajectory.states.front();
  core::State turned = run.trajectory.states.back();
  return {std::move(model), rows, std::move(start), std::move(turned)};
}

/// −Σ_i λ_i J_{rows[i]}ᵀ: the generalized reaction of multipliers λ read as those of `rows`.
Eigen::VectorXd tracker_test_force(const Eigen::MatrixXd& J, const std::vector<int>& rows,
                                   const Eigen::VectorXd& lambda) {
  Eigen::VectorXd force = Eigen::VectorXd::Zero(J.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    force -= lambda(static_cast<Eigen::Index>(i)) * J.row(rows[i]).transpose();
  }
  return force;
}

}  // namespace

TEST_CASE("constraint tracker: multipliers come with the rows they belong to", "[constraint]") {
  const TrackedFourBar four_bar = tracked_four_bar();
  const core::Model& model = four_bar.model;
  REQUIRE(model.independent_rows() == four_bar.rows);
  core::Workspace ws = model.make_workspace();
  core::Accelerations acc = model.make_accelerations();
  // The tracker accepted the start: the rows' pivot ratio there is the reference of the
  // tenfold fall (core/row_selection_tpl.hpp).
  core::ConstraintTracker tracker = model.make_constraint_tracker();
  model.advance_tracker(0.0, four_bar.start, tracker, ws);
  REQUIRE(tracker.rows == four_bar.rows);
  const core::ConstraintTracker accepted = tracker;

  const double t = kTurnedTime;
  model.compute_accelerations({t, t}, four_bar.turned, tracker, ws, acc);
  const core::JointMultipliers multipliers = model.joint_multipliers(ws);
  // The evaluation chose other rows for itself at the turned state ...
  CHECK(multipliers.rows() != tracker.rows);
  // ... and left the tracker as it was: only an accepted state moves it.
  CHECK(tracker.rows == accepted.rows);
  CHECK(tracker.selection_ratio == accepted.selection_ratio);
  CHECK(tracker.J_accepted == accepted.J_accepted);
  CHECK(tracker.accepted_time == accepted.accepted_time);

  const Eigen::VectorXd& F = multipliers.force();
  const double scale = F.cwiseAbs().maxCoeff();
  REQUIRE(scale > 0.0);
  // λ on the rows it belongs to gives the generalized reaction the solve applied: the same sums
  // in another order, round-off of the terms (reactions ~10 N, J entries ≤ 1): 1e-12 of |F|.
  const Eigen::VectorXd own =
      tracker_test_force(multipliers.J(), multipliers.rows(), multipliers.lambda());
  INFO("|F| " << scale << ", λ on its own rows off by " << (own - F).cwiseAbs().maxCoeff());
  CHECK((own - F).cwiseAbs().maxCoeff() < 1e-12 * scale);
  // The pairing of λ with the tracker's rows (what reading the solve's λ against any fixed row
  // set did) is another force altogether: off by O(1) of |F|.
  const Eigen::VectorXd paired_wrong =
      tracker_test_force(multipliers.J(), tracker.rows, multipliers.lambda());
  INFO("λ on the tracker's rows off by " << (paired_wrong - F).cwiseAbs().maxCoeff());
  CHECK((paired_wrong - F).cwiseAbs().maxCoeff() > 1e-2 * scale);
  // The same reactions as multipliers of the tracker's rows (on_rows): their normal equations
  // square the rows' condition (the pivot ratio fell ~1e2 from ~1e-3: cond(J_r)² ≲ 1e5), so
  // ~1e5 ε of |F|; 1e-9 leaves a margin of 500.
  const Eigen::VectorXd carried =
      tracker_test_force(multipliers.J(), tracker.rows, multipliers.on_rows(tracker.rows));
  CHECK((carried - F).cwiseAbs().maxCoeff() < 1e-9 * scale);

  // Accepting the turned state moves the tracker to the rows the evaluation chose.
  model.advance_tracker(t, four_bar.turned, tracker, ws);
  CHECK(tracker.rows == multipliers.rows());
  CHECK(tracker.has_accepted);
  CHECK(tracker.accepted_time == t);
  // λ of the old rows carried to the new ones at the accepted state: the same reaction (the
  // normal equations of both row sets, ~1e5 ε as above).
  const Eigen::VectorXd on_old = multipliers.on_rows(accepted.rows);
  const Eigen::VectorXd on_new = tracker.carry(on_old, accepted.rows);
  CHECK((tracker_test_force(tracker.J_accepted.dense(), tracker.rows, on_new) - F)
            .cwiseAbs()
            .maxCoeff() < 1e-9 * scale);
}

TEST_CASE("constraint tracker: an evaluation depends on its arguments, not on its workspace",
          "[constraint]") {
  // A workspace that evaluated the start first (where a workspace used to take the rows' pivot
  // ratio as its reference and so chose other rows at the turned state) and a fresh one give
  // the same accelerations at the turned state, bit for bit.
  const TrackedFourBar four_bar = tracked_four_bar();
  const core::Model& model = four_bar.model;
  const core::LoadContext turned{kTurnedTime, kTurnedTime};
  core::Workspace used = model.make_workspace();
  core::Accelerations acc_used = model.make_accelerations();
  model.compute_accelerations({0.0, 0.0}, four_bar.start, used, acc_used);
  model.compute_accelerations(turned, four_bar.turned, used, acc_used);
  core::Workspace fresh = model.make_workspace();
  core::Accelerations acc_fresh = model.make_accelerations();
  model.compute_accelerations(turned, four_bar.turned, fresh, acc_fresh);
  CHECK(model.joint_multipliers(used).rows() == model.joint_multipliers(fresh).rows());
  for (std::size_t b = 0; b < acc_used.size(); ++b) {
    INFO("body " << b);
    CHECK(acc_used[b].a_WBr == acc_fresh[b].a_WBr);
    CHECK(acc_used[b].alpha_WB_B == acc_fresh[b].alpha_WB_B);
  }
}

}  // namespace flexref::constraint
