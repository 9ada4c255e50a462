/// Cost of the references of scenes with ideal joints (docs/joints.md, "Cost"): Andrews'
/// squeezing mechanism (the IVP test set's andrews, t in [0, 0.03] s, outputs every 1e-4 s) and
/// the heavy top on a spherical joint (2 s of heavy_top_spherical, outputs every 0.01 s), each
/// solver at rtol 1e-8, 1e-10 and 1e-12. CVODE runs with its automatic choice (Adams with
/// Baumgarte stabilization on both scenes) and forced BDF with projection; IDA on the GGL
/// index-2 form; ARKODE and Odeint with Baumgarte stabilization (docs/joints.md, "References").
/// `andrews/evaluation`: one constrained evaluation (Model::compute_accelerations with
/// Baumgarte's term, as CVODE's Adams evaluates it) at the output state t = 2e-4 s on a tracker
/// accepted at t = 1e-4 s (so that the orientation test compares two different row sets, as
/// between a solver's accepted state and its trial points): the cost per evaluation alone.
/// `andrews/reduced_evaluation`: the same state's evaluation in joint coordinates
/// (constraint/reduced_model.hpp: seven angles, M_r 7 × 7, the three loops' 6 independent rows,
/// Baumgarte's term as above), from its coordinates: the cost per evaluation of the reduced form.
/// Counters: steps, right-hand-side (or residual) evaluations, the solver's own CPU time of the
/// integration and its output states (solver_cpu_s), and the error of the result, computed once
/// outside the timed loop: on Andrews the largest difference of the seven angles at t = 0.03
/// from the values an independent RK4 of the test set's own equations gives (docs/joints.md:
/// the published PSIDE reference is off by 1.2e-9 in β and 1.4e-9 in Θ, so it is not used
/// here); on the heavy top the L∞ geodesic attitude angle against the exact Lagrange top.
///
/// For scale: the IVP test set reports for andrews at rtol 1e-10 (its Fig. "work-precision",
/// RADAU5, DASSL, MEBDFDAE, PSIDE on a 1998 workstation) fractions of a second; the figures of
/// this benchmark are in docs/performance.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "constraint/reduced_model.hpp"
#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/exact_solution.hpp"
#include "reference/reduced_cvode.hpp"
#include "reference/reference_solver.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/scene_reader.hpp"

namespace {

namespace ref = flexref::reference;
using flexref::core::Model;

struct JointedScene {
  flexref::scene::Scene scene;
  std::vector<double> times;
};

const JointedScene& andrews() {
  static const JointedScene s{
      flexref::scene::read_scene(FLEXREF_SOURCE_DIR "/scenes/andrews_squeezer.toml"),
      flexref::core::output_times(0.03, 1e-4)};
  return s;
}

const JointedScene& heavy_top_spherical() {
  static const JointedScene s{
      flexref::scene::read_scene(FLEXREF_SOURCE_DIR "/scenes/heavy_top_spherical.toml"),
      flexref::core::output_times(2.0, 0.01)};
  return s;
}

/// β (the absolute angle of K1) and β + Θ (K2's) at t = 0.03 from an RK4 of the test set's own
/// equations at h = 5e-7 s, agreeing with h = 1e-6 s to 5e-12 (docs/joints.md, "Andrews'
/// squeezing mechanism").
constexpr double kBetaRk4 = 15.810771195153839;
constexpr double kK2AngleRk4 = 15.810771195153839 - 15.756371058412032;

/// |angle of body `body` about +z at the last output − `expected`|, modulo 2π (planar motion:
/// the angle is 2 atan2(e3, e0)).
double planar_angle_error(const flexref::core::State& last, std::size_t body, double expected) {
  const auto& q = last[body].theta_WB;
  return std::abs(std::remainder(2.0 * std::atan2(q[3], q[0]) - expected, 2.0 * M_PI));
}

double heavy_top_error(const ref::ReferenceRun& run) {
  static const ref::ReferenceRun exact = [] {
    const flexref::scene::Scene top =
        flexref::scene::read_scene(FLEXREF_SOURCE_DIR "/scenes/heavy_top.toml");
    return ref::solve_exact(*top.model, heavy_top_spherical().times);
  }();
  double e = 0.0;
  for (std::size_t k = 0; k < run.trajectory.states.size(); ++k) {
    e = std::max(e, flexref::rotation::geodesic_angle(run.trajectory.states[k][0].theta_WB,
                                                      exact.trajectory.states[k][0].theta_WB));
  }
  return e;
}

/// `solver`: "cvode" (the product's choice: joint coordinates where they apply), "cvode-maximal"
/// (Adams on the maximal form), "cvode-bdf", "ida", "arkode", "odeint".
void BM_JointedReference(benchmark::State& state, const JointedScene& (*scene)(),
                         std::string solver, double rtol) {
  const JointedScene& s = scene();
  ref::SolverOptions options;
  options.rtol = rtol;
  if (solver == "cvode-bdf") {
    solver = "cvode";
    options.cvode_method = ref::CvodeMethod::kBdf;
  } else if (solver == "cvode-maximal") {
    solver = "cvode";
    options.coordinates = ref::Coordinates::kMaximal;
  }
  ref::ReferenceRun run;
  for (auto _ : state) {
    run = ref::solve_reference(solver, *s.scene.model, s.times, options);
    benchmark::DoNotOptimize(run.trajectory.states.back()[0].w_WB_B.data());
  }
  state.counters["rtol"] = rtol;
  state.counters["steps"] = static_cast<double>(run.stats.steps);
  state.counters["rhs_evals"] = static_cast<double>(run.stats.rhs_evaluations);
  state.counters["solver_cpu_s"] = run.stats.cpu_seconds;
  if (scene == &heavy_top_spherical) {
    state.counters["error_rad"] = heavy_top_error(run);
  } else {
    // K1 and K2 are bodies 0 and 1 of the scene (scripts/scenes/make_andrews_squeezer.py).
    state.counters["beta_error"] = planar_angle_error(run.trajectory.states.back(), 0, kBetaRk4);
    state.counters["k2_error"] = planar_angle_error(run.trajectory.states.back(), 1, kK2AngleRk4);
  }
  state.SetLabel(run.method + ", " + run.coordinates);
}

void BM_AndrewsEvaluation(benchmark::State& state) {
  const Model& model = *andrews().scene.model;
  ref::SolverOptions options;
  options.rtol = 1e-10;
  const ref::ReferenceRun run = ref::solve_reference("cvode", model, andrews().times, options);
  const flexref::core::State& accepted = run.trajectory.states[1];
  const flexref::core::State& x = run.trajectory.states[2];
  const double t = run.trajectory.times[2];
  flexref::core::Workspace ws = model.make_workspace();
  flexref::core::ConstraintTracker tracker = model.make_constraint_tracker();
  model.advance_tracker(run.trajectory.times[1], accepted, tracker, ws);
  flexref::core::Accelerations acc = model.make_accelerations();
  const flexref::core::LoadContext context{t, 0.0};
  // Baumgarte's rate: any positive value takes the same path (its term is O(m)).
  const double stabilization = 100.0;
  for (auto _ : state) {
    model.compute_accelerations(context, x, tracker, ws, acc, stabilization);
    benchmark::DoNotOptimize(acc[0].alpha_WB_B.data());
  }
}

void BM_AndrewsReducedEvaluation(benchmark::State& state) {
  const Model& model = *andrews().scene.model;
  ref::SolverOptions options;
  options.rtol = 1e-10;
  const ref::ReferenceRun run = ref::solve_reference("cvode", model, andrews().times, options);
  const flexref::constraint::ReducedModel reduced(model);
  flexref::constraint::ReducedWorkspace ws = reduced.make_workspace();
  Eigen::VectorXd q, u, u_dot(reduced.velocity_count());
  reduced.coordinates(run.trajectory.states[2], q, u);
  const flexref::core::LoadContext context{run.trajectory.times[2], 0.0};
  const double stabilization = 100.0;
  for (auto _ : state) {
    reduced.accelerations(context, q, u, ws, u_dot, stabilization);
    benchmark::DoNotOptimize(u_dot.data());
  }
}

/// The reduced reference (reference/reduced_cvode.hpp) on Andrews at rtol, its setup (the
/// spanning tree, the rank analysis, the spectrum) in the timed loop as the maximal reference's.
void BM_AndrewsReducedReference(benchmark::State& state, double rtol) {
  const Model& model = *andrews().scene.model;
  ref::SolverOptions options;
  options.rtol = rtol;
  ref::ReferenceRun run;
  for (auto _ : state) {
    run = ref::solve_reduced_cvode(model, andrews().times, options);
    benchmark::DoNotOptimize(run.trajectory.states.back()[0].w_WB_B.data());
  }
  state.counters["rtol"] = rtol;
  state.counters["steps"] = static_cast<double>(run.stats.steps);
  state.counters["rhs_evals"] = static_cast<double>(run.stats.rhs_evaluations);
  state.counters["beta_error"] = planar_angle_error(run.trajectory.states.back(), 0, kBetaRk4);
  state.counters["k2_error"] = planar_angle_error(run.trajectory.states.back(), 1, kK2AngleRk4);
}

void register_all() {
  benchmark::RegisterBenchmark("andrews/evaluation", BM_AndrewsEvaluation)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("andrews/reduced_evaluation", BM_AndrewsReducedEvaluation)
      ->Unit(benchmark::kMicrosecond);
  for (double rtol : {1e-8, 1e-10, 1e-12}) {
    const std::string tol = rtol == 1e-8 ? "1e-8" : rtol == 1e-10 ? "1e-10" : "1e-12";
    benchmark::RegisterBenchmark(("andrews/reduced_cvode/" + tol).c_str(),
                                 BM_AndrewsReducedReference, rtol)
        ->Unit(benchmark::kMillisecond);
  }
  for (const char* solver : {"cvode", "cvode-maximal", "cvode-bdf", "ida", "arkode", "odeint"}) {
    for (double rtol : {1e-8, 1e-10, 1e-12}) {
      const std::string tol = rtol == 1e-8 ? "1e-8" : rtol == 1e-10 ? "1e-10" : "1e-12";
      benchmark::RegisterBenchmark(("andrews/" + std::string(solver) + "/" + tol).c_str(),
                                   BM_JointedReference, &andrews, solver, rtol)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(
          ("heavy_top_spherical/" + std::string(solver) + "/" + tol).c_str(), BM_JointedReference,
          &heavy_top_spherical, solver, rtol)
          ->Unit(benchmark::kMillisecond);
    }
  }
}

const bool kRegistered = (register_all(), true);

}  // namespace
