/// scenes/tube_support_impact.toml: the tube hits and rubs its support at a deforming
/// node. Checked on its first 0.3 s (24 forcing periods, the tube reaches the support within the
/// first periods):
///  - the energy balance E − E₀ + W_d − W_a (W_a the harmonic forces' work, integrated with the
///    state like W_d) ≤ 1e-6 of the energy scale in every reference;
///  - the wear outputs: columns, impacts counted, wear work positive and equal across references
///    to their tolerance;
///  - the LTE and coupled models agree (the frame is fixed: the same equations).
#include <Eigen/Core>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "reference/reference_solver.hpp"
#include "scene/build_model.hpp"
#include "scene/scene_reader.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref {
namespace {

const std::string kScene = "scenes/tube_support_impact.toml";

std::vector<double> tube_grid(double end, double step) {
  std::vector<double> t;
  for (int k = 0; k * step <= end + 1e-12; ++k) t.push_back(k * step);
  return t;
}

struct Columns {
  std::vector<double> balance, scale, wear, impacts, mid_y;
};

Columns columns(const core::Model& model, const reference::ReferenceRun& run) {
  const trajectory::TrajectoryTable table = trajectory::tabulate(model, run.trajectory);
  Columns c;
  const int e = table.column("energy"), wd = table.column("dissipated_work"),
            wa = table.column("applied_work"), b = table.column("energy_balance"),
            w = table.column("support.wear_work"), i = table.column("support.impacts"),
            y = table.column("tube.mid.y");
  REQUIRE(e >= 0);
  REQUIRE(wd >= 0);
  REQUIRE(wa >= 0);
  REQUIRE(b >= 0);
  REQUIRE(w >= 0);
  REQUIRE(i >= 0);
  REQUIRE(table.column("support.fn") >= 0);
  REQUIRE(table.column("support.slip_speed") >= 0);
  for (const auto& row : table.rows) {
    c.balance.push_back(row[static_cast<std::size_t>(b)]);
    c.scale.push_back(std::abs(row[static_cast<std::size_t>(e)]) +
                      std::abs(row[static_cast<std::size_t>(wd)]) +
                      std::abs(row[static_cast<std::size_t>(wa)]));
    c.wear.push_back(row[static_cast<std::size_t>(w)]);
    c.impacts.push_back(row[static_cast<std::size_t>(i)]);
    c.mid_y.push_back(row[static_cast<std::size_t>(y)]);
  }
  return c;
}

TEST_CASE("tube_support_impact: energy balance, wear outputs and impacts in every reference") {
  scene::Scene scene = scene::read_scene(kScene);
  scene::SceneSpec spec = scene.spec;
  spec.end_time = 0.3;
  const core::Model model = scene::build_model(spec);
  REQUIRE(model.wear_channel_names() == std::vector<std::string>{"support"});
  REQUIRE(model.tracks_applied_work());
  reference::SolverOptions o;
  o.rtol = 1e-10;
  const std::vector<double> t = tube_grid(0.3, 0.005);
  using Solve = reference::ReferenceRun (*)(const core::Model&, const std::vector<double>&,
                                            const reference::SolverOptions&);
  std::vector<Columns> all;
  for (const Solve solve : {&reference::solve_cvode, &reference::solve_ida,
                            &reference::solve_arkode, &reference::solve_odeint}) {
    const reference::ReferenceRun run = solve(model, t, o);
    INFO(run.solver);
    const Columns c = columns(model, run);
    double worst = 0.0, scale = 0.0;
    for (std::size_t k = 0; k < c.balance.size(); ++k) {
      worst = std::max(worst, std::abs(c.balance[k]));
      scale = std::max(scale, c.scale[k]);
    }
    // The target: 1e-6 relative. Each integral is a solution component under rtol 1e-10
    // (the energy is evaluated from the state; atol = rtol = 1e-10 on modal coordinates of
    // ~1e-3 allows ~1e-7 relative errors per component): measured 3.2e-7 (CVODE), 1.6e-7 (IDA),
    // 6.6e-8 (ARKODE), 1e-9 (Odeint) of the ~1 J scale at 0.3 s.
    CHECK(worst <= 1e-6 * scale);
    CHECK(scale > 0.1);  // the forces do work: the balance is not vacuous
    // The tube reaches the support and rubs it.
    CHECK(c.impacts.back() >= 5.0);
    CHECK(c.wear.back() > 0.0);
    // The wear work never decreases by more than its own tolerance: its rate |F_t·v_t| ≥ 0, but
    // a BDF solution (IDA's, whose Newton matrix couples the integrals to the state) is not
    // monotone to the last digit where the rate vanishes: rtol 1e-10 of the value bounds it.
    for (std::size_t k = 1; k < c.wear.size(); ++k) {
      CHECK(c.wear[k] >= c.wear[k - 1] - 1e-10 * std::abs(c.wear[k - 1]));
    }
    all.push_back(c);
  }
  // The four references agree on the wear work and the impact count: each integrates W_wear'
  // = |F_t·v_t| as a component to rtol 1e-10; their distance is ≤ ~1e-8 of the value over
  // dozens of impacts (located to ~1e-12 s each), bounded here by 1e-6.
  for (std::size_t r = 1; r < all.size(); ++r) {
    CHECK(all[r].wear.back() == Approx(all[0].wear.back()).epsilon(1e-6));
    CHECK(all[r].impacts.back() == all[0].impacts.back());
  }
}

TEST_CASE("tube_support_impact: LTE and coupled models agree with the frame fixed") {
  scene::Scene scene = scene::read_scene(kScene);
  scene::SceneSpec spec = scene.spec;
  spec.end_time = 0.1;
  const core::Model coupled = scene::build_model(spec, core::FlexibleFormulation::kCoupled);
  const core::Model lte = scene::build_model(spec, core::FlexibleFormulation::kLte);
  reference::SolverOptions o;
  o.rtol = 1e-10;
  const std::vector<double> t = tube_grid(0.1, 0.005);
  const Columns a = columns(coupled, reference::solve_cvode(coupled, t, o));
  const Columns b = columns(lte, reference::solve_cvode(lte, t, o));
  // With ω̄ = 0 and α̅ = 0 the coupled model's modal rows are m_ff q̈ + D q̇ + K q = Q_f, the
  // LTE model's too, and node contacts see the deformed node in both (docs/decisions.md): the
  // solutions differ only by the solver's errors, ~1e-10 of the 1e-3 m motion.
  for (std::size_t k = 0; k < t.size(); ++k) CHECK(std::abs(a.mid_y[k] - b.mid_y[k]) < 1e-10);
  CHECK(b.wear.back() == Approx(a.wear.back()).epsilon(1e-6));
}

TEST_CASE("tube_support_impact spinning about its axis: coupled is spin-invariant, LTE is not") {
  // A beam without rotary inertia spinning about its own axis has world-frame transverse
  // dynamics independent of the spin (no gyroscopic term; the support is axisymmetric and the
  // forces are fixed in the world). The coupled model reproduces that through its Coriolis and
  // centrifugal terms (2Ω × q̇ and Ω²-softening in the body frame); the LTE model drops them, so
  // its body-frame response to the world-fixed forces is that of a non-rotating frame and its
  // world response turns at Ω. Undamped here: modal damping in a rotating frame is rotating
  // damping, which does depend on the spin (measured 4.9e-7 m at ζ = 1 %).
  scene::Scene scene = scene::read_scene(kScene);
  scene::SceneSpec fixed = scene.spec;
  fixed.end_time = 0.3;
  fixed.bodies[0].description.flexible->modal.damping_ratio.setZero();
  scene::SceneSpec spinning = fixed;
  spinning.bodies[0].description.prescribed.axis_W = Eigen::Vector3d::UnitX();
  spinning.bodies[0].description.prescribed.law.rate = 2.0;  // rad/s
  reference::SolverOptions o;
  o.rtol = 1e-10;
  const std::vector<double> t = tube_grid(0.3, 0.005);
  const auto solve = [&](const scene::SceneSpec& spec, core::FlexibleFormulation f) {
    const core::Model m = scene::build_model(spec, f);
    return columns(m, reference::solve_cvode(m, t, o));
  };
  const Columns base = solve(fixed, core::FlexibleFormulation::kCoupled);
  const Columns coupled = solve(spinning, core::FlexibleFormulation::kCoupled);
  const Columns lte = solve(spinning, core::FlexibleFormulation::kLte);
  double coupled_distance = 0.0, lte_distance = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    coupled_distance = std::max(coupled_distance, std::abs(coupled.mid_y[k] - base.mid_y[k]));
    lte_distance = std::max(lte_distance, std::abs(lte.mid_y[k] - base.mid_y[k]));
  }
  // Coupled: the references' error, ~rtol × 1e-3 m per component (measured 2.6e-10 m over 0.2 s
  // of CLI output, 6e-10 over 1 s); a wrong sign of the frame rotation in Φ_kᵀ Aᵀ f or in the
  // node's world position would turn the response by 2Ωt (0.6 rad at 0.3 s: ~1e-4 m).
  CHECK(coupled_distance < 1e-8);
  CHECK(coupled.wear.back() == Approx(base.wear.back()).epsilon(1e-6));
  // LTE: its response turns by Ω t relative to the true one (0.6 rad at 0.3 s): ~1e-4 m of the
  // ~1 mm whirl (measured 8.9e-5 m at 0.2 s, 2.3e-4 m over 1 s).
  CHECK(lte_distance > 1e-5);
}

TEST_CASE("tube_support_impact: the schemes' wear work converges at second order") {
  scene::Scene scene = scene::read_scene(kScene);
  scene::SceneSpec spec = scene.spec;
  spec.end_time = 0.3;
  const core::Model model = scene::build_model(spec, core::FlexibleFormulation::kLte);
  reference::SolverOptions o;
  o.rtol = 1e-11;
  const std::vector<double> t = tube_grid(0.3, 0.005);
  const Columns reference_columns = columns(model, reference::solve_cvode(model, t, o));
  const double reference_wear = reference_columns.wear.back();
  for (const std::string& name : lie::builtin_scheme_names()) {
    INFO(name);
    std::vector<double> errors;
    for (const double h : {2.5e-5, 1.25e-5, 6.25e-6}) {
      const std::unique_ptr<lie::Stepper> stepper = lie::make_stepper(name, model, {});
      const core::Trajectory run = lie::run_scheme(model, *stepper, h, t);
      const trajectory::TrajectoryTable table = trajectory::tabulate(model, run);
      const double wear =
          table.rows.back()[static_cast<std::size_t>(table.column("support.wear_work"))];
      errors.push_back(std::abs(wear - reference_wear) / reference_wear);
      // The schemes count the same impacts (their steps resolve each ~0.3 ms contact).
      CHECK(table.rows.back()[static_cast<std::size_t>(table.column("support.impacts"))] ==
            reference_columns.impacts.back());
    }
    // The reference's own error is ~1e-8 (rtol 1e-11; the four references agree to that), far
    // below the schemes' 1e-3..1e-4. Measured pairwise orders 1.84 and 1.92 on these 0.3 s (the
    // converge study of docs/contact_results.md: the rate reaches 2 below h = 2.5e-5, where the
    // steps resolve the ~0.3 ms impacts and the friction's 5 mm/s regularization); a first-order
    // or non-converging wear integration (a rectangle rule, a sampled output) gives ≤ 1.
    const double order_1 = std::log2(errors[0] / errors[1]);
    const double order_2 = std::log2(errors[1] / errors[2]);
    CHECK(order_1 > 1.6);
    CHECK(order_2 > 1.6);
    CHECK(errors[2] < 1e-3);
  }
}

}  // namespace
}  // namespace flexref
