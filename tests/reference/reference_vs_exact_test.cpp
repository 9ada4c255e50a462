/// \file reference_vs_exact_test.cpp
/// The four reference solvers against the exact solutions (docs/design/schemes.md, "Exact
/// solutions: references for the references"): the torque-free body in both circulation cases
/// and near the separatrix, the symmetric heavy top (on its pivot and on an ideal spherical
/// joint), and the compound pendulum; at a tight tolerance, and at rtol 1e-10 against the
/// tolerance's promise (docs/references.md, "Error weights").
#include <Eigen/Core>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/body.hpp"
#include "core/gravity.hpp"
#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/exact_heavy_top.hpp"
#include "reference/exact_pendulum.hpp"
#include "reference/exact_torque_free.hpp"
#include "reference/reference_solver.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/exact_scenes.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

using Exact = std::function<RigidAttitude(double)>;

const Eigen::Vector3d kGravity_W(0.0, 0.0, -9.81);

using testing::free_body;

core::Model pendulum() { return testing::compound_pendulum(); }

/// One scene with an exact solution.
struct Case {
  std::string name;
  std::function<core::Model()> model;
  std::function<Exact()> exact;
  double end_time;
};

std::vector<Case> cases() {
  const rotation::EulerParameters identity = rotation::identity_euler_parameters();
  const rotation::EulerParameters tilted =
      rotation::EulerParameters(0.9, 0.1, -0.3, 0.2).normalized();
  std::vector<Case> all;
  {
    // free_spin: |π|² > 2E I_mid, the momentum circles the max-inertia axis. 100 s, the scene.
    const Eigen::Vector3d inertia(3.0, 4.0, 5.0), w0(0.2, 0.3, 2.0);
    all.push_back({"torque-free, circulation about the max axis",
                   [=] { return free_body(inertia, identity, w0); },
                   [=] {
                     const auto exact = std::make_shared<TorqueFreeExact>(inertia, identity, w0);
                     return Exact([exact](double t) { return exact->at(t); });
                   },
                   100.0});
  }
  {
    // |π|² < 2E I_mid: the momentum circles the min-inertia axis; a tilted initial attitude.
    const Eigen::Vector3d inertia(3.0, 4.0, 5.0), w0(2.0, 0.3, 0.2);
    all.push_back({"torque-free, circulation about the min axis",
                   [=] { return free_body(inertia, tilted, w0); },
                   [=] {
                     const auto exact = std::make_shared<TorqueFreeExact>(inertia, tilted, w0);
                     return Exact([exact](double t) { return exact->at(t); });
                   },
                   100.0});
  }
  {
    // Near the separatrix: spin 5e-3 (relative) off the intermediate axis of the book,
    // modulus k' ≈ 7e-3, first flip at ~1 s, then flips every ~1.6 s. Perturbations grow like
    // e^{5.3 t} (5.3/s = 10·√((2 − 1)(2.8 − 2)/(1 · 2.8))) until a flip: errors are amplified
    // ~1/(5e-3) = 200 per flip, so 3 s (two flips) tests the elliptic functions near k = 1
    // without reaching round-off. (The book toss's own 1e-4 offset amplifies by ~1e4: CVODE's
    // error there is round-off-limited and erratic in rtol — 2e-10 … 6e-8 over 1e-13 … 1e-15 —
    // so that case is checked against long-double RKF78 in exact_torque_free_test.cpp.)
    const Eigen::Vector3d inertia(1.0, 2.0, 2.8), w0(0.05, 10.0, 0.05);
    all.push_back({"torque-free, near the separatrix",
                   [=] { return free_body(inertia, identity, w0); },
                   [=] {
                     const auto exact = std::make_shared<TorqueFreeExact>(inertia, identity, w0);
                     return Exact([exact](double t) { return exact->at(t); });
                   },
                   3.0});
  }
  // heavy_top (docs/design/scenes.md, tests/support/test_problems.hpp): the exact solution takes
  // the inertia about the pivot, J_C + m l² on the transverse axes (l = 1).
  const double mass = 15.0;
  const Eigen::Vector3d w0(0.0, 150.0, -4.61538);
  const auto heavy_top_exact = [=] {
    const auto exact = std::make_shared<HeavyTopExact>(mass, 1.0, Eigen::Vector3d(0.0, 1.0, 0.0),
                                                       0.234375 + mass * 1.0, 0.46875, kGravity_W,
                                                       rotation::identity_euler_parameters(), w0);
    return Exact([exact](double t) { return exact->at(t); });
  };
  all.push_back({"heavy top", [] { return testing::heavy_top(); }, heavy_top_exact, 2.0});
  // The same top as a free body held at its frame origin by an ideal spherical joint
  // (scenes/heavy_top_spherical.toml): the same motion through the constrained equations.
  all.push_back(
      {"heavy top on a spherical joint",
       [] { return std::move(*scene::read_scene("scenes/heavy_top_spherical.toml").model); },
       heavy_top_exact, 2.0});
  {
    // pendulum: the exact solution takes the inertia about the pivot.
    const Eigen::Vector3d inertia_cm(1e-3, 1e-3, 1e-3), com(1.0, 0.0, 0.0);
    all.push_back({"pendulum", [] { return pendulum(); },
                   [=] {
                     const Eigen::Matrix3d j_pivot = core::shift_inertia_from_com<double>(
                         Eigen::Matrix3d(inertia_cm.asDiagonal()), 1.0, com);
                     const auto exact = std::make_shared<PendulumExact>(
                         1.0, com, j_pivot, kGravity_W, rotation::identity_euler_parameters());
                     return Exact([exact](double t) { return exact->at(t); });
                   },
                   10.0});
  }
  // The driven parallelogram (testing::driven_parallelogram_toml) up to 1 s, 0.57 rad before
  // its dead point: an index-2 mechanism (four ideal revolute joints, 3 bodies) whose drive sets
  // the motion, body 0 the left crank turning by π/2 − t about +z.
  all.push_back({"driven parallelogram",
                 [] {
                   return std::move(*scene::parse_scene(testing::driven_parallelogram_toml("1.0"),
                                                        "parallelogram.toml")
                                         .model);
                 },
                 [] {
                   return Exact([](double t) {
                     const double angle = std::numbers::pi / 2.0 - t;
                     return RigidAttitude{
                         Eigen::Vector4d(std::cos(angle / 2.0), 0.0, 0.0, std::sin(angle / 2.0)),
                         Eigen::Vector3d(0.0, 0.0, -1.0)};
                   });
                 },
                 1.0});
  return all;
}

/// Largest errors against the exact solution over the output times, relative to the
/// reference's range (docs/design/schemes.md, "Error metrics"): |Δω̄| / max|ω̄|, and the geodesic
/// attitude error / the angle turned by t_end (at least 1 rad), the natural scale of a phase
/// error.
struct RelativeError {
  double angular_velocity = 0.0;
  double attitude = 0.0;
  double attitude_rad = 0.0;  ///< absolute, for the record
};

RelativeError relative_error(const ReferenceRun& run, const std::vector<RigidAttitude>& exact) {
  const std::vector<double>& t = run.trajectory.times;
  double w_max = 0.0, turned = 0.0, w_error = 0.0, angle = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    w_max = std::max(w_max, exact[k].w_B.norm());
    if (k > 0) turned += 0.5 * (exact[k].w_B.norm() + exact[k - 1].w_B.norm()) * (t[k] - t[k - 1]);
    const core::BodyState& s = run.trajectory.states[k][0];
    w_error = std::max(w_error, (s.w_WB_B - exact[k].w_B).norm());
    angle = std::max(angle, rotation::geodesic_angle(s.theta_WB, exact[k].theta));
  }
  return {w_error / w_max, angle / std::max(1.0, turned), angle};
}

/// Every reference solver on `c` at rtol, with its largest errors against the exact solution.
std::vector<std::pair<ReferenceRun, RelativeError>> run_all_solvers(const Case& c, double rtol) {
  const core::Model model = c.model();
  const Exact exact = c.exact();
  const std::vector<double> times = core::output_times(c.end_time, 0.01);
  std::vector<RigidAttitude> exact_values;
  exact_values.reserve(times.size());
  for (double t : times) exact_values.push_back(exact(t));
  SolverOptions options;
  options.rtol = rtol;
  std::vector<std::pair<ReferenceRun, RelativeError>> runs;
  for (ReferenceRun run :
       {solve_ida(model, times, options), solve_cvode(model, times, options),
        solve_arkode(model, times, options), solve_odeint(model, times, options)}) {
    const RelativeError e = relative_error(run, exact_values);
    runs.emplace_back(std::move(run), e);
  }
  return runs;
}

}  // namespace

TEST_CASE("the reference solvers match the exact solutions at rtol 1e-13",
          "[ida][cvode][arkode][odeint][exact]") {
  for (const Case& c : cases()) {
    CAPTURE(c.name);
    for (const auto& [run, e] : run_all_solvers(c, 1e-13)) {
      CAPTURE(run.solver, run.stats.steps, e.angular_velocity, e.attitude, e.attitude_rad);
      // Acceptance (issue 51): within 1e-10 rad of the exact attitude, and 2e-10 relative (ω̄ to
      // its largest size, the attitude to the angle turned). Measured, attitude in rad
      // (IDA, CVODE, ARKODE, Odeint):
      //   max axis          2.0e-12  2.1e-12  3.5e-13  5.8e-12
      //   min axis          2.5e-12  4.1e-13  6.5e-13  4.9e-12
      //   separatrix        4.6e-12  7.2e-12  6.2e-14  1.6e-12
      //   heavy top         4.4e-11  4.4e-12  4.3e-12  2.9e-12  (before: 9.9e-10 2.1e-9, IDA and
      //                                                          CVODE at 1e-13, issue 51)
      //   on the joint      5.2e-13  1.1e-13  1.5e-12  6.9e-13  (before: IDA 1.2e-11)
      //   pendulum          1.4e-11  1.9e-13  3.6e-13  1.4e-12
      //   parallelogram     3.9e-14  6.6e-15  1.2e-15  2.8e-15
      // and relative ω̄ ≤ 6.2e-12, relative attitude ≤ 5.5e-13.
      CHECK(e.attitude_rad <= 1e-10);
      CHECK(e.angular_velocity <= 2e-10);
      CHECK(e.attitude <= 2e-10);
      // IDA keeps the rotation's per-step share throughout (ida_solver.cpp: it drops it only
      // where its Newton iteration cannot converge to it; with the index-2 floor at 8 ε instead
      // of ErrorWeights::kIndex2Roundoff ε it did, on the spherical joint).
      CHECK(run.method_reason.find("SUNDIALS' error weights from") == std::string::npos);
    }
  }
}

TEST_CASE("the reference solvers keep the tolerance's promise at rtol 1e-10",
          "[ida][cvode][arkode][odeint][exact]") {
  // The promise of rtol on a rotation: an attitude error of rtol × the angle turned (at least
  // 1 rad), i.e. e.attitude ≤ K rtol (docs/references.md, "Error weights").
  const double rtol = 1e-10;
  for (const Case& c : cases()) {
    CAPTURE(c.name);
    for (const auto& [run, e] : run_all_solvers(c, rtol)) {
      const double ratio = e.attitude / rtol;
      CAPTURE(run.solver, run.stats.steps, e.attitude_rad, ratio);
      // K = 2: measured ratios at rtol 1e-10 (IDA, CVODE, ARKODE, Odeint)
      //   max axis    0.033  0.011  0.0065 0.25     separatrix   0.046 0.16  0.041  0.16
      //   min axis    0.028  0.022  0.094  0.27     heavy top    0.050 0.16  0.41   0.17
      //   on the joint 0.0018 0.0031 0.0040 0.0031  pendulum     0.15  0.044 0.28   0.93
      //   parallelogram 0.019 0.039 0.0092 0.016
      // (IDA on the ideal joints before their per-step weights: 0.33 on the joint, 4.6 on the
      // parallelogram.)
      // The explicit 7(8) pairs meet the promise by local extrapolation (their order-8 steps'
      // errors are well below the order-7 estimate); CVODE and IDA by the per-unit-step weights
      // on the rotation, without which the heavy top was at 60 (CVODE) and 80 (IDA) × the
      // promise at rtol 1e-11. 2 leaves the largest measured ratio (0.93) a factor 2 and fails
      // any solver whose error grows with the number of its steps rather than the angle turned.
      CHECK(ratio <= 2.0);
    }
  }
}

}  // namespace flexref::reference
