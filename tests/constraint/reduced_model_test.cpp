/// \file reduced_model_test.cpp
/// The reduced (joint-coordinate) form (constraint/reduced_model.hpp) against what is known
/// independently of it: its body-velocity Jacobian S and bias Ṡ u against central differences of
/// its own forward kinematics along q ⊕ h u, and the bodies' accelerations it gives against the
/// maximal model's (core::Model::compute_accelerations, the Schur complement of all joints'
/// rows: a different formulation sharing only the loads and the closures' rows) at consistent
/// states of Andrews' squeezer, a spatial chain on spherical joints, the heavy top on its
/// spherical joint, and the joint-kind scenes (prismatic, cylindrical, universal with a driven
/// closure, fixed, distance and driven revolute closures). Also: the tree it chooses on Andrews
/// (the IVP test set's), no allocation per evaluation, and the refusals.
#include "constraint/reduced_model.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "rotation/so3.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/chain_scene.hpp"
#include "tests/support/joint_kind_scenes.hpp"
#include "tests/support/solver_options.hpp"

namespace flexref::constraint {
namespace {

struct ReducedCase {
  std::string name;
  scene::Scene scene;
  double horizon;  ///< the maximal reference run the states are taken from (s)
};

/// Sliding joints on moving parents, which no bundled scene has: a tumbling free arm, a bead
/// on a prismatic joint along the arm's x axis, and a sleeve on a cylindrical joint about and
/// along the bead's y axis (the Coriolis and transport terms of the tree's bias), under gravity.
std::string reduced_slider_scene_text() {
  return R"([scene]
name = "sliders"
end_time = 0.1
output_step = 0.01
gravity = [0.0, 0.0, -9.81]
project_initial_state = true

[[body]]
name = "arm"
mass = 1.0
inertia = [0.01, 0.02, 0.03]
center_of_mass = [0.1, 0.0, 0.0]
velocity = [0.2, 0.0, 0.1]
angular_velocity = [0.5, -1.0, 3.0]

[[body]]
name = "bead"
mass = 0.2
inertia = [0.001, 0.002, 0.0015]
center_of_mass = [0.0, 0.01, 0.0]
position = [0.3, 0.0, 0.0]
angular_velocity = [0.5, -1.0, 3.0]

[[body]]
name = "sleeve"
mass = 0.1
inertia = [0.0005, 0.0004, 0.0006]
center_of_mass = [0.02, 0.0, 0.0]
position = [0.3, 0.05, 0.0]
angular_velocity = [0.5, 1.0, 3.0]

[[joint]]
name = "slide"
model = "ideal"
kind = "prismatic"
body_a = "bead"
point_a = [0.0, 0.0, 0.0]
body_b = "arm"
point_b = [0.3, 0.0, 0.0]
axis_a = [1.0, 0.0, 0.0]
axis_b = [1.0, 0.0, 0.0]

[[joint]]
name = "sleeve"
model = "ideal"
kind = "cylindrical"
body_a = "sleeve"
point_a = [0.0, 0.0, 0.0]
body_b = "bead"
point_b = [0.0, 0.05, 0.0]
axis_a = [0.0, 1.0, 0.0]
axis_b = [0.0, 1.0, 0.0]
)";
}

std::vector<ReducedCase> reduced_cases() {
  std::vector<ReducedCase> cases;
  cases.push_back({"andrews", scene::read_scene("scenes/andrews_squeezer.toml"), 3e-3});
  cases.push_back({"chain6", scene::parse_scene(testing::chain_scene_text(6), "chain6.toml"), 0.1});
  cases.push_back(
      {"heavy_top_spherical", scene::read_scene("scenes/heavy_top_spherical.toml"), 0.05});
  cases.push_back(
      {"sliders", scene::parse_scene(reduced_slider_scene_text(), "sliders.toml"), 0.1});
  for (const testing::JointKindScene& s : testing::joint_kind_scenes()) {
    cases.push_back({s.kind, scene::parse_scene(s.toml, s.kind + ".toml"), 0.1});
  }
  return cases;
}

/// Consistent states of a case: the maximal CVODE reference's at three times of its horizon,
/// projected onto all rows (Model::project: Newton to round-off), so that both formulations see
/// a state on the constraint manifold.
std::vector<core::State> reduced_states(const ReducedCase& c, std::vector<double>& times) {
  const core::Model& model = *c.scene.model;
  times = {0.0, c.horizon / 3.0, c.horizon};
  const reference::ReferenceRun run =
      reference::solve_reference("cvode", model, times, testing::with_rtol(1e-8));
  std::vector<core::State> states = run.trajectory.states;
  core::Workspace ws = model.make_workspace();
  for (std::size_t k = 0; k < states.size(); ++k) model.project(times[k], states[k], ws);
  return states;
}

/// The stacked (v_WBr, ω̄) central difference of the forward kinematics along q ⊕ h u: the
/// translation (p(+) − p(−))/2h, the rotation vee(log(R(−)ᵀ R(+)))/2h (body frame).
Eigen::VectorXd reduced_pose_difference(const TreeKinematics& k, const Eigen::VectorXd& q,
                                        const Eigen::VectorXd& u, double h) {
  Eigen::VectorXd q_plus = q, q_minus = q;
  k.advance(q, u, h, q_plus);
  k.advance(q, u, -h, q_minus);
  TreeWorkspace plus = k.make_workspace(), minus = k.make_workspace();
  k.evaluate(q_plus, u, plus);
  k.evaluate(q_minus, u, minus);
  Eigen::VectorXd out(6 * k.body_count());
  for (int b = 0; b < k.body_count(); ++b) {
    const auto i = static_cast<std::size_t>(b);
    out.segment<3>(6 * b) = (plus.state[i].p_WBr - minus.state[i].p_WBr) / (2.0 * h);
    out.segment<3>(6 * b + 3) =
        rotation::log_so3(minus.R_WB[i].transpose() * plus.R_WB[i]) / (2.0 * h);
  }
  return out;
}

/// The maximal state moved by δ along its own motion to first order: positions by its velocities
/// (p ± δ v, θ ⊗ exp(±δ ω̄)), velocities by the accelerations `acc` (v ± δ a, ω̄ ± δ α̅).
core::State reduced_moved_state(const core::State& state, const core::Accelerations& acc,
                                double delta) {
  core::State out = state;
  for (std::size_t i = 0; i < out.size(); ++i) {
    core::BodyState& s = out[i];
    s.p_WBr += delta * s.v_WBr;
    s.theta_WB =
        rotation::quaternion_multiply(s.theta_WB, rotation::exp_quaternion(delta * s.w_WB_B));
    s.v_WBr += delta * acc[i].a_WBr;
    s.w_WB_B += delta * acc[i].alpha_WB_B;
  }
  return out;
}

Eigen::VectorXd reduced_random_velocity(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd u(n);
  for (Eigen::Index k = 0; k < n; ++k) u(k) = unit(rng);
  return u;
}

TEST_CASE("reduced: S and the bias Ṡu against central differences of the forward kinematics",
          "[reduced]") {
  std::mt19937 rng(52);
  for (const ReducedCase& c : reduced_cases()) {
    const ReducedModel reduced(*c.scene.model);
    const TreeKinematics& k = reduced.kinematics();
    Eigen::VectorXd q, u;
    reduced.coordinates(c.scene.model->initial_state(), q, u);
    // Any u (S is defined off the closures' manifold too), |u_i| ≤ 1 in rad/s and m/s.
    u = reduced_random_velocity(k.velocity_count(), rng);
    TreeWorkspace ws = k.make_workspace();
    k.evaluate(q, u, ws);
    // Step h = 1e-5 s: the central difference's truncation h²/6 |x'''| ~ h² |u|² |ẋ| / 6 ≈ 2e-11
    // |ẋ| (rates |u| ≤ 1 per mobilizer, a few in series: |u|² ≲ 10) and its round-off
    // ε |x| / h ≈ 2e-11 |x| (the poses are O(1) m at most, speeds ≳ 1e-2 m/s on the smallest
    // scene, Andrews) stay below 1e-8 of the largest rate; 1e-7 leaves a margin of 10 for the
    // scene-to-scene spread of those scales.
    const double h = 1e-5, tolerance = 1e-7;
    const Eigen::VectorXd v = ws.S * u;
    const Eigen::VectorXd v_fd = reduced_pose_difference(k, q, u, h);
    INFO(c.name << ": S u " << v.transpose() << "\n FD " << v_fd.transpose());
    CHECK((v - v_fd).cwiseAbs().maxCoeff() <= tolerance * v.cwiseAbs().maxCoeff());
    // Ṡ u: d(S u)/dt along q ⊕ h u at constant u, (S(q ⊕ hu) − S(q ⊖ hu)) u / 2h; the same
    // truncation and round-off relative to the bias's own scale |u|² |x|.
    Eigen::VectorXd q_plus = q, q_minus = q;
    k.advance(q, u, h, q_plus);
    k.advance(q, u, -h, q_minus);
    TreeWorkspace plus = k.make_workspace(), minus = k.make_workspace();
    k.evaluate(q_plus, u, plus);
    k.evaluate(q_minus, u, minus);
    const Eigen::VectorXd bias_fd = (plus.S * u - minus.S * u) / (2.0 * h);
    INFO(c.name << ": Ṡu " << ws.bias.transpose() << "\n FD " << bias_fd.transpose());
    CHECK((ws.bias - bias_fd).cwiseAbs().maxCoeff() <=
          tolerance * std::max(ws.bias.cwiseAbs().maxCoeff(), v.cwiseAbs().maxCoeff()));
  }
}

TEST_CASE("reduced: the bodies' accelerations equal the maximal model's at consistent states",
          "[reduced]") {
  for (const ReducedCase& c : reduced_cases()) {
    const core::Model& model = *c.scene.model;
    const ReducedModel reduced(model);
    ReducedWorkspace rws = reduced.make_workspace();
    core::Workspace ws = model.make_workspace();
    core::Accelerations maximal = model.make_accelerations();
    core::Accelerations from_reduced = model.make_accelerations();
    std::vector<double> times;
    const std::vector<core::State> states = reduced_states(c, times);
    for (std::size_t s = 0; s < states.size(); ++s) {
      Eigen::VectorXd q, u, u_dot(reduced.velocity_count());
      reduced.coordinates(states[s], q, u);
      const core::LoadContext context{times[s], times[s]};
      reduced.accelerations(context, q, u, rws, u_dot);
      reduced.body_accelerations(rws, u_dot, from_reduced);
      reduced.attitudes(rws);
      // The maximal model at the very state the reduced one evaluated (its forward kinematics).
      model.compute_accelerations(context, rws.tree.state, ws, maximal);
      Eigen::VectorXd a(6 * model.num_bodies()), b(6 * model.num_bodies());
      for (int i = 0; i < model.num_bodies(); ++i) {
        const auto k = static_cast<std::size_t>(i);
        a.segment<3>(6 * i) = maximal[k].a_WBr;
        a.segment<3>(6 * i + 3) = maximal[k].alpha_WB_B;
        b.segment<3>(6 * i) = from_reduced[k].a_WBr;
        b.segment<3>(6 * i + 3) = from_reduced[k].alpha_WB_B;
      }
      // Both solve the same equations at the same state; they differ by the round-off of their
      // solves, ε κ of the largest acceleration with κ the condition of the constrained system.
      // The worst here is Andrews' (masses 0.004–0.07 kg on arms of 4–40 mm, its Schur pivot
      // ratio ~1e-5 at worst: core/schur_complement_tpl.hpp), κ ≲ 1e5, ε κ ≈ 2e-11; 1e-10
      // leaves a margin of 5. The scale has a floor of 1 (m/s², rad/s²): the scenes that start
      // from rest with their drives have no acceleration at t = 0.
      const double tolerance = 1e-10;
      const double scale = std::max(1.0, a.cwiseAbs().maxCoeff());
      INFO(c.name << " at t = " << times[s] << ":\n maximal " << a.transpose() << "\n reduced "
                  << b.transpose());
      CHECK((a - b).cwiseAbs().maxCoeff() <= tolerance * scale);
      // u̇ itself (a bias error that S u̇ absorbs leaves the bodies' accelerations right and u̇
      // wrong): the joint velocities of the maximal state moved by ±δ along the maximal
      // accelerations, differenced, d u/dt along that path = u̇ to O(δ²). δ = 1e-6 s: the
      // truncation δ² |u⃛|/6 ≲ 1e-12 |u̇|²/|u| (u⃛ ~ u̇²/u; Andrews |u̇|/|u| ≲ 1e4/s) ≈ 2e-9 |u̇|,
      // the round-off ε |u| / δ ≲ 2e-10 |u| s; 1e-7 of max(1, |u̇|) leaves a margin of 10 over
      // the larger.
      const core::State x = rws.tree.state;
      const double delta = 1e-6;
      Eigen::VectorXd q_plus, u_plus, q_minus, u_minus;
      reduced.coordinates(reduced_moved_state(x, maximal, delta), q_plus, u_plus);
      reduced.coordinates(reduced_moved_state(x, maximal, -delta), q_minus, u_minus);
      const Eigen::VectorXd u_dot_fd = (u_plus - u_minus) / (2.0 * delta);
      INFO(c.name << ": u̇ " << u_dot.transpose() << "\n FD " << u_dot_fd.transpose());
      CHECK((u_dot - u_dot_fd).cwiseAbs().maxCoeff() <=
            1e-7 * std::max(1.0, u_dot.cwiseAbs().maxCoeff()));
    }
  }
}

TEST_CASE("reduced: Baumgarte's term on the closures equals the maximal model's off the manifold",
          "[reduced]") {
  // Scenes whose closure rows are all independent (a distance rod, a driven hinge), so that both
  // forms enforce the same rows, also off the manifold where redundant rows would disagree.
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (const testing::JointKindScene& kind : testing::joint_kind_scenes()) {
    if (kind.kind != "distance" && kind.kind != "driven revolute") continue;
    const scene::Scene scene = scene::parse_scene(kind.toml, kind.kind + ".toml");
    const core::Model& model = *scene.model;
    const ReducedModel reduced(model);
    // The single body is a free root: its maximal state is its coordinates, moved off the
    // closure's manifold by 1e-3 m and 1e-2 m/s, rad/s.
    core::State state = model.initial_state();
    for (core::BodyState& b : state) {
      for (int k = 0; k < 3; ++k) {
        b.p_WBr(k) += 1e-3 * normal(rng);
        b.v_WBr(k) += 1e-2 * normal(rng);
        b.w_WB_B(k) += 1e-2 * normal(rng);
      }
    }
    Eigen::VectorXd q, u, u_dot(reduced.velocity_count());
    reduced.coordinates(state, q, u);
    ReducedWorkspace rws = reduced.make_workspace();
    const double t = 0.05, alpha = 30.0;
    reduced.accelerations({t, t}, q, u, rws, u_dot, alpha);
    reduced.attitudes(rws);
    core::Accelerations from_reduced = model.make_accelerations();
    reduced.body_accelerations(rws, u_dot, from_reduced);
    core::Workspace ws = model.make_workspace();
    core::Accelerations maximal = model.make_accelerations();
    model.compute_accelerations({t, t}, rws.tree.state, model.initial_tracker(), ws, maximal,
                                alpha);
    for (std::size_t i = 0; i < maximal.size(); ++i) {
      // The same equations at the same state: round-off of two small solves, ε κ with κ ≲ 1e3
      // for one body of unit-order data; 1e-11 of max(1, |a|) (m/s², rad/s²) leaves a margin of
      // 50. The stabilization's own share is α² |Φ| ~ 1 m/s², so a sign error in it is seen.
      const double scale = std::max(1.0, maximal[i].a_WBr.cwiseAbs().maxCoeff());
      INFO(kind.kind << ": maximal " << maximal[i].a_WBr.transpose() << ", "
                     << maximal[i].alpha_WB_B.transpose() << "\n reduced "
                     << from_reduced[i].a_WBr.transpose() << ", "
                     << from_reduced[i].alpha_WB_B.transpose());
      CHECK((maximal[i].a_WBr - from_reduced[i].a_WBr).cwiseAbs().maxCoeff() <= 1e-11 * scale);
      CHECK((maximal[i].alpha_WB_B - from_reduced[i].alpha_WB_B).cwiseAbs().maxCoeff() <=
            1e-11 * scale);
    }
  }
}

TEST_CASE("reduced: Andrews' tree is the IVP test set's, one evaluation allocates nothing",
          "[reduced]") {
  const scene::Scene andrews = scene::read_scene("scenes/andrews_squeezer.toml");
  const core::Model& model = *andrews.model;
  const ReducedModel reduced(model);
  const SpanningTree& tree = reduced.kinematics().tree();
  // Seven revolute joints (O, F, B, A5, A7, G, H) carry the seven angles; E3, E4, E6 close the
  // three loops: 15 rows of which 6 are independent (the planar loops' in-plane rows).
  REQUIRE(tree.mobilizers.size() == 7);
  for (const Mobilizer& m : tree.mobilizers) CHECK(m.kind == MobilizerKind::kRevolute);
  CHECK(reduced.velocity_count() == 7);
  std::vector<std::string> closures;
  for (const int j : tree.closures) closures.push_back(model.constraints()->joint_name(j));
  CHECK(closures == std::vector<std::string>{"E3", "E4", "E6"});
  CHECK(reduced.closure_joints()->row_count() == 15);
  CHECK(reduced.independent_rows().size() == 6);
  ReducedWorkspace ws = reduced.make_workspace();
  Eigen::VectorXd q, u, u_dot(reduced.velocity_count());
  reduced.coordinates(model.initial_state(), q, u);
  reduced.accelerations({0.0, 0.0}, q, u, ws, u_dot, 100.0);
  CHECK(testing::count_allocations([&] {
          reduced.accelerations({1e-4, 0.0}, q, u, ws, u_dot, 100.0);
        }) == 0);
  // On a tracker, with its orientation test and the accepted state's move.
  ClosureTracker tracker = reduced.make_tracker();
  reduced.accelerations({0.0, 0.0}, q, u, ws, u_dot, 100.0, &tracker);
  reduced.accept(0.0, ws, tracker);
  CHECK(testing::count_allocations([&] {
          reduced.accelerations({1e-4, 0.0}, q, u, ws, u_dot, 100.0, &tracker);
          reduced.accept(1e-4, ws, tracker);
        }) == 0);
}

TEST_CASE("reduced: the tracker's accepted rows are the full evaluation's, bit for bit",
          "[reduced]") {
  // An evaluation on a tracker evaluates the closure rows in force alone; where it chooses rows
  // (here forced by an unreachable reference ratio) it evaluates all. The tracker keeps J_c's rows
  // of the accepted evaluation, and where rows chosen later were not evaluated there, the
  // orientation test evaluates that state's closures again: the same bits as if all had been.
  const scene::Scene andrews = scene::read_scene("scenes/andrews_squeezer.toml");
  const ReducedModel reduced(*andrews.model);
  ReducedWorkspace ws = reduced.make_workspace();
  const int nu = reduced.velocity_count();
  Eigen::VectorXd q0, u0, q1, u_dot(nu);
  reduced.coordinates(andrews.model->initial_state(), q0, u0);  // at rest
  // Every angle turned by 0.05 rad (off the closures' manifold, which the evaluation allows),
  // and joint rates of 10 rad/s.
  q1 = q0;
  reduced.kinematics().advance(q0, Eigen::VectorXd::Ones(nu), 0.05, q1);
  const Eigen::VectorXd u1 = Eigen::VectorXd::Constant(nu, 10.0);
  const double alpha = 470.0;  // the reference's Baumgarte rate
  const double never = std::numeric_limits<double>::infinity();

  ClosureTracker in_force = reduced.make_tracker();
  reduced.accelerations({0.0, 0.0}, q0, u0, ws, u_dot, alpha, &in_force);
  CHECK_FALSE(ws.rows_chosen);
  reduced.accept(0.0, ws, in_force);
  ClosureTracker all = reduced.make_tracker();
  all.selection_ratio = never;
  reduced.accelerations({0.0, 0.0}, q0, u0, ws, u_dot, alpha, &all);
  REQUIRE(ws.rows_chosen);
  reduced.accept(0.0, ws, all);
  // Andrews' only independent rows are the loops' in-plane point rows: chosen again, the same.
  REQUIRE(all.rows == in_force.rows);
  const auto count = [](const std::vector<char>& v) { return std::count(v.begin(), v.end(), 1); };
  CHECK(count(in_force.evaluated) == 6);
  CHECK(count(all.evaluated) == 15);
  for (const int r : in_force.rows) CHECK(in_force.J_accepted.row(r) == all.J_accepted.row(r));

  // The next evaluation's orientation test on the three trackers: `all`; `in_force`; and a copy
  // of `in_force` that lacks one of its rows (stale: NaN), so that rows chosen at q1 need the
  // accepted state's closures evaluated again. Each must see the same X = J_a,accepted L⁻ᵀ.
  ClosureTracker gap = in_force;
  const int missing = gap.rows.front();
  gap.evaluated[static_cast<std::size_t>(missing)] = 0;
  gap.J_accepted.row(missing).setConstant(std::numeric_limits<double>::quiet_NaN());
  all.selection_ratio = never;
  gap.selection_ratio = never;
  const auto evaluate_on = [&](const ClosureTracker& tracker) {
    reduced.accelerations({2e-4, 0.0}, q1, u1, ws, u_dot, alpha, &tracker);
    return std::pair<Eigen::MatrixXd, Eigen::VectorXd>(ws.accepted_rows, u_dot);
  };
  const auto [x_all, u_dot_all] = evaluate_on(all);
  const auto [x_in_force, u_dot_in_force] = evaluate_on(in_force);
  CHECK_FALSE(ws.rows_chosen);
  const auto [x_gap, u_dot_gap] = evaluate_on(gap);
  CHECK(ws.rows_chosen);
  CHECK(x_all.allFinite());
  CHECK(x_in_force == x_all);
  CHECK(x_gap == x_all);
  CHECK(u_dot_in_force == u_dot_all);
  CHECK(u_dot_gap == u_dot_all);
  // The accepted state matters: accepted at q1 itself, X differs (so a gap filled from the
  // evaluated state instead of the accepted one would not pass).
  ClosureTracker at_q1 = reduced.make_tracker();
  reduced.accelerations({2e-4, 0.0}, q1, u1, ws, u_dot, alpha, &at_q1);
  reduced.accept(2e-4, ws, at_q1);
  CHECK(evaluate_on(at_q1).first != x_all);
}

TEST_CASE("reduced: an evaluation leaves the Euler parameters to attitudes(), to the same bits",
          "[reduced]") {
  // The evaluation poses the loads and the closures on the tree's attitude matrices and leaves
  // θ_WB NaN (a stale θ read by mistake shows); attitudes() forms them as the full forward
  // kinematics does. The heavy top's pivot root keeps its θ, its coordinates.
  for (const ReducedCase& c : reduced_cases()) {
    const core::Model& model = *c.scene.model;
    const ReducedModel reduced(model);
    ReducedWorkspace rws = reduced.make_workspace();
    Eigen::VectorXd q, u, u_dot(reduced.velocity_count());
    reduced.coordinates(model.initial_state(), q, u);
    reduced.accelerations({0.0, 0.0}, q, u, rws, u_dot);
    TreeWorkspace full = reduced.kinematics().make_workspace();
    reduced.kinematics().evaluate(q, u, full);
    for (const Mobilizer& m : reduced.kinematics().tree().mobilizers) {
      const auto b = static_cast<std::size_t>(m.child);
      const bool root = m.kind == MobilizerKind::kFree || m.kind == MobilizerKind::kPivot;
      INFO(c.name << ", body " << b);
      CHECK(rws.tree.state[b].theta_WB.hasNaN() == !root);
      CHECK(rws.tree.R_WB[b] == full.R_WB[b]);
    }
    reduced.attitudes(rws);
    for (std::size_t b = 0; b < full.state.size(); ++b) {
      INFO(c.name << ", body " << b);
      CHECK(rws.tree.state[b].theta_WB == full.state[b].theta_WB);
    }
  }
}

TEST_CASE("reduced: flexible bodies and contacts are refused with their reason", "[reduced]") {
  const scene::Scene flexible = scene::read_scene("scenes/flexible_spinner.toml");
  CHECK_THROWS_WITH(ReducedModel(*flexible.model), Catch::Contains("is flexible"));
  const scene::Scene contact = scene::read_scene("scenes/bouncing_ball.toml");
  CHECK_THROWS_WITH(ReducedModel(*contact.model), Catch::Contains("contact element"));
}

}  // namespace
}  // namespace flexref::constraint
