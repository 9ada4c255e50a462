/// \file joint_trust_test.cpp
/// What a jointed solution promises (docs/joints.md): rank decisions relative to each row's
/// scale, data double cannot resolve refused at its key, a singular start told apart from a
/// redundant row, a projection that cannot reach the joints refused with each joint's residual,
/// every output row checked against the bound its tolerance implies, and the work of drives in
/// the energy balance.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/constrained_solve_tpl.hpp"
#include "core/error.hpp"
#include "core/invariants.hpp"
#include "core/joint_check.hpp"
#include "core/output_times.hpp"
#include "reference/exact_solution.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/mechanism_scene_texts.hpp"
#include "tests/support/scene_error_checks.hpp"
#include "tests/support/solver_options.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::constraint {
namespace {

using Matrix = Eigen::MatrixXd;

// The line of the `[[joint]]` header of the joint named `name` in `text`, and its 1-based index
// among the joint tables (0, 0 when absent).
std::pair<int, int> joint_table(const std::string& text, const std::string& name) {
  int line = 1, header = 0, index = 0;
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = text.find('\n', at);
    const std::string l = text.substr(at, end == std::string::npos ? end : end - at);
    if (l == "[[joint]]") {
      header = line;
      ++index;
    }
    if (l == "name = \"" + name + "\"" && header > 0) return {header, index};
    if (end == std::string::npos) break;
    at = end + 1;
    ++line;
  }
  return {0, 0};
}

// Requires the scene reader to refuse `text` at the table of a joint it names ("joint 'X'"),
// with `fragment` in the message: the file, the joint table's line and key.
void require_joint_refusal(const std::string& text, const std::string& fragment) {
  INFO("input text:\n" << text);
  try {
    (void)scene::parse_scene(text, "bad.toml");
  } catch (const core::InputError& e) {
    const std::string message = e.what();
    INFO("what(): " << message);
    CHECK_THAT(message, Catch::Matchers::Contains(fragment));
    const std::size_t quote = message.find("joint '");
    REQUIRE(quote != std::string::npos);
    const std::size_t start = quote + 7;
    const std::string name = message.substr(start, message.find('\'', start) - start);
    const auto [line, index] = joint_table(text, name);
    CHECK(e.file() == "bad.toml");
    CHECK(e.line() == line);
    CHECK(e.key() == "joint[" + std::to_string(index) + "]");
    return;
  }
  FAIL("parse_scene accepted the input");
}

// The scene's reference by `solver` at rtol on its output grid.
reference::ReferenceRun trust_reference(const scene::Scene& scene, const std::string& solver,
                                        double rtol) {
  return reference::solve_reference(solver, *scene.model,
                                    core::output_times(scene.end_time, scene.output_step),
                                    testing::with_rtol(rtol));
}

}  // namespace

TEST_CASE("joint trust: rank decisions are relative to each row's own scale", "[constraint]") {
  // Two independent rows 1e12 apart in size: a threshold relative to the largest row (1e-10)
  // would take the small one for round-off of the large one.
  Matrix J(2, 3);
  J << 1e6, 0.0, 0.0,  //
      0.0, 1e-6, 0.0;
  CHECK(core::independent_rows<double>(J) == std::vector<int>{0, 1});
  // A dependency c = 1e-3 a + b among the rows a = e1, b = e2, c: whatever their sizes, one row
  // is set aside, and not b — the row with the smallest share in the dependency, whose removal
  // leaves a and c, 1e-3 rad apart (as far from dependent as the share is small).
  Matrix K(3, 2);
  K << 1e3, 0.0,  //
      0.0, 1.0,   //
      1e-3, 1.0;
  const std::vector<int> kept = core::independent_rows<double>(K);
  REQUIRE(kept.size() == 2);
  CHECK(kept != std::vector<int>{0, 2});
}

TEST_CASE("joint trust: a singular start is refused naming the joint, redundant rows are kept",
          "[constraint]") {
  SECTION("a slider-crank driven at the slider from its dead centre") {
    // The guide's drive depends on the revolute rows only at the dead centre: moving the crank
    // makes it independent. The joint named is the row set aside (its dependency's largest
    // share), with the joints it depends on.
    require_joint_refusal(testing::driven_slider_scene_text(0.0, -0.75, 0.1),
                          "starts at a singular configuration");
  }
  SECTION("a ball at the tangent point of two distance joints") {
    require_joint_refusal(testing::tangent_distances_scene_text(),
                          "starts at a singular configuration");
  }
  SECTION("structurally redundant rows pass: planar loops, Bricard's sixth row") {
    // Each has rows set aside at t = 0 that stay dependent and satisfied along the motion.
    for (const char* name : {"andrews_squeezer", "slider_crank", "four_bar", "bricard"}) {
      INFO(name);
      const scene::Scene s = scene::read_scene(std::string("scenes/") + name + ".toml");
      CHECK(s.model->independent_rows().size() <
            static_cast<std::size_t>(s.model->constraints()->row_count()));
    }
  }
}

TEST_CASE("joint trust: a projection that cannot reach the joints names each joint's residual",
          "[constraint]") {
  const std::string head =
      "[scene]\nname = \"x\"\nend_time = 0.5\noutput_step = 0.01\n"
      "gravity = [0.0, 0.0, -9.81]\nproject_initial_state = true\n"
      "[[body]]\nname = \"box\"\nmass = 1.0\ninertia = [0.01, 0.01, 0.01]\n"
      "position = [0.0, 0.0, -1.0]\n";
  SECTION("a body fixed to the ground at two places") {
    const std::string text = head +
                             testing::ideal_joint_text("F", "fixed", "box", "[0.0, 0.0, 0.0]",
                                                       "ground", "[0.0, 0.0, -1.0]") +
                             testing::ideal_joint_text("K", "fixed", "box", "[0.0, 0.0, 0.0]",
                                                       "ground", "[1.0, 0.0, -1.0]");
    // K's six rows repeat F's: set aside, never reached by the projection onto F.
    require_joint_refusal(text, "joint 'K' 1 m");
    require_joint_refusal(text, "cannot reach them all");
  }
  SECTION("two distances that cannot both hold") {
    const std::string text =
        head +
        testing::ideal_joint_text("D1", "distance", "box", "[0.0, 0.0, 0.0]", "ground",
                                  "[0.0, 0.0, 0.0]", "length = 1.0\n") +
        testing::ideal_joint_text("D2", "distance", "box", "[0.0, 0.0, 0.0]", "ground",
                                  "[5.0, 0.0, 0.0]", "length = 1.0\n");
    require_joint_refusal(text, "cannot reach them all");
  }
}

TEST_CASE("joint trust: a joint point double cannot resolve is refused at its key",
          "[constraint]") {
  const std::string text =
      "[scene]\nname = \"far\"\nend_time = 0.5\noutput_step = 0.01\n"
      "[[body]]\nname = \"ball\"\nmass = 1.0\ninertia = [0.01, 0.01, 0.01]\n"
      "position = [0.0, 0.0, 0.0]\n" +
      testing::ideal_joint_text("J", "spherical", "ball", "[1e160, 0.0, 0.0]", "ground",
                                "[1e160, 0.0, 0.0]");
  // The point line of the joint table: line 9 of the text above.
  testing::require_scene_error(text, 15, "joint[1].point_a", "beyond what double precision");
  // 1e6 radii of gyration (0.1 m) is past the limit of 1e5 radii, 1e4 within it.
  const std::string far =
      testing::replace_first(testing::replace_first(text, "[1e160", "[1e5"), "[1e160", "[1e5");
  testing::require_scene_error(far, 15, "joint[1].point_a", "beyond what double precision");
  const std::string near =
      testing::replace_first(testing::replace_first(text, "[1e160", "[1e3"), "[1e160", "[1e3");
  CHECK_NOTHROW(scene::parse_scene(near, "near.toml"));
}

TEST_CASE("joint trust: every output row is checked, redundant rows included", "[constraint]") {
  const scene::Scene scene = scene::read_scene("scenes/slider_crank.toml");
  const core::Model& model = *scene.model;
  const double rtol = 1e-10;
  reference::ReferenceRun run = trust_reference(scene, "cvode", rtol);
  const double bound = core::joint_violation_bound(rtol, run.options.absolute_tolerance(),
                                                   model.joint_length_scale());
  // 1e3 × max(rtol, atol/ℓ), atol = rtol and ℓ = 0.15 m (the crank's arm to P): 6.7e-7 relative,
  // exact up to the rounding of the quotient.
  CHECK(bound == Approx(1e3 * 1e-10 / 0.15).epsilon(1e-12));
  CHECK_FALSE(core::find_joint_breach(model, run.trajectory, bound).has_value());
  // The slider lifted off its guide by 1e-3 m at one output: the guide's out-of-plane row (set
  // aside as redundant: the planar loop repeats it) is violated there, relative 1e-3 / ℓ.
  core::Trajectory moved = run.trajectory;
  const std::size_t k = moved.times.size() / 2;
  const int slider = model.body_index("slider");
  moved.states[k][static_cast<std::size_t>(slider)].p_WBr.z() += 1e-3;
  const std::optional<core::JointBreach> breach = core::find_joint_breach(model, moved, bound);
  REQUIRE(breach.has_value());
  CHECK(breach->t == moved.times[k]);
  CHECK_FALSE(breach->velocity);
  CHECK(breach->absolute == Approx(1e-3).epsilon(1e-6));
  CHECK((breach->joint == "guide" || breach->joint == "Q"));
  // Through solve_reference: the same check on what the solver returned (nothing to break
  // there: the intact run passes).
  CHECK_NOTHROW(reference::check_joints(run, model));
  run.trajectory = moved;
  CHECK_THROWS_AS(reference::check_joints(run, model), core::SolverError);
}

TEST_CASE("joint trust: the drive's work closes the energy balance", "[constraint]") {
  // The slider-crank's crank is driven and nothing else does work (no gravity, ideal joints):
  // E(t) − E(0) = W_drive(t) exactly, and the balance column E − E(0) + W_d − W_a − W_drive is
  // zero up to the integration error of E and W_drive.
  const scene::Scene scene = scene::read_scene("scenes/slider_crank.toml");
  const core::Model& model = *scene.model;
  REQUIRE(model.tracks_drive_work());
  for (const std::string solver : {"cvode", "ida", "odeint"}) {
    INFO(solver);
    const double rtol = 1e-10;
    const reference::ReferenceRun run = trust_reference(scene, solver, rtol);
    const trajectory::TrajectoryTable table = trajectory::tabulate(model, run.trajectory);
    const int balance = table.column("energy_balance");
    const int drive = table.column("drive_work");
    const int energy = table.column("energy");
    REQUIRE(balance >= 0);
    REQUIRE(drive >= 0);
    double worst = 0.0, scale = 0.0;
    for (const std::vector<double>& row : table.rows) {
      worst = std::max(worst, std::abs(row[static_cast<std::size_t>(balance)]));
      scale = std::max(scale, std::abs(row[static_cast<std::size_t>(drive)]));
    }
    const double e0 = table.rows.front()[static_cast<std::size_t>(energy)];
    INFO("largest |balance| " << worst << " J, largest |W_drive| " << scale << " J, E(0) " << e0
                              << " J");
    // The drive's work is the kinetic energy's swing (rod and slider: ~3 J over a crank turn).
    CHECK(scale > 1.0);
    // Each integral errs by what the solver lets its local errors accumulate: rtol relative per
    // step over ~1e3 steps, on terms of the size of E (~4 J): 1e3 × 1e-10 × 4 J = 4e-7 J bounds
    // both with margin (without W_drive the balance is the swing itself, ~3 J).
    CHECK(worst < 1e3 * rtol * 4.0);
  }
}

TEST_CASE("joint trust: the invariant monitor knows what joints do", "[constraint]") {
  SECTION("a joint to the ground is a load from outside; a drive's work is tracked") {
    const core::ModelInvariants in =
        core::model_invariants(*scene::read_scene("scenes/slider_crank.toml").model);
    CHECK_FALSE(in.momentum());
    CHECK_THAT(in.momentum_reason, Catch::Matchers::Contains("ideal joint 'O'"));
    CHECK(in.energy());
  }
  SECTION("two free bodies on a spherical joint keep their momentum") {
    const std::string text =
        "[scene]\nname = \"pair\"\nend_time = 0.5\noutput_step = 0.01\n"
        "project_initial_state = true\n"
        "[[body]]\nname = \"a\"\nmass = 1.0\ninertia = [0.01, 0.02, 0.03]\n"
        "position = [0.0, 0.0, 0.0]\nangular_velocity = [1.0, 2.0, 3.0]\n"
        "[[body]]\nname = \"b\"\nmass = 2.0\ninertia = [0.02, 0.01, 0.03]\n"
        "position = [0.2, 0.0, 0.0]\nangular_velocity = [1.0, 2.0, 3.0]\n"
        "velocity = [0.0, 0.3, -0.2]\n" +
        testing::ideal_joint_text("S", "spherical", "b", "[-0.1, 0.0, 0.0]", "a",
                                  "[0.1, 0.0, 0.0]");
    const scene::Scene s = scene::parse_scene(text, "pair.toml");
    const core::ModelInvariants in = core::model_invariants(*s.model);
    CHECK(in.momentum());
    CHECK(in.energy());
  }
}

TEST_CASE("joint trust: no exact solution is claimed for a body on joints", "[constraint]") {
  // One free body, no load, on a driven slide: the torque-free closed form would leave it at
  // rest while its drive moves it (written with exit 0 before).
  const std::string text =
      "[scene]\nname = \"slide\"\nend_time = 1.0\noutput_step = 0.01\n"
      "[[body]]\nname = \"block\"\nmass = 1.0\ninertia = [0.01, 0.01, 0.01]\n"
      "position = [0.0, 0.0, 0.0]\n" +
      testing::ideal_joint_text("S", "prismatic", "block", "[0.0, 0.0, 0.0]", "ground",
                                "[0.0, 0.0, 0.0]",
                                "axis_a = [1.0, 0.0, 0.0]\naxis_b = [1.0, 0.0, 0.0]\n"
                                "drive = { law = \"spin-up\", rate = 0.5, spin_up_time = 0.5 }\n");
  const scene::Scene s = scene::parse_scene(text, "slide.toml");
  const reference::ExactSolutionKind kind = reference::classify_exact_solution(*s.model);
  CHECK(kind.kind.empty());
  CHECK_THAT(kind.reason, Catch::Matchers::Contains("ideal joints"));
}

TEST_CASE("joint trust: Bricard's set-aside row keeps the rest well conditioned over the motion",
          "[constraint]") {
  // The Bricard linkage's single dependency among its 30 rows: the row set aside is the one with
  // the largest share in it. Setting aside another (J1's y row, which pivoting order chose) left
  // 29 rows whose conditioning fell by ~1e8 near t = 1.25 s, where the unenforced row drifted
  // beyond the output check at rtol 1e-10 (CVODE, ARKODE) and IDA's corrector failed.
  scene::Scene scene = scene::read_scene("scenes/bricard.toml");
  scene.end_time = 3.0;
  for (const std::string solver : {"cvode", "ida"}) {
    INFO(solver);
    CHECK_NOTHROW(trust_reference(scene, solver, 1e-10));
  }
}

}  // namespace flexref::constraint
