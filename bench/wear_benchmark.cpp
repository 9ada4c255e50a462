/// Cost of contact at a deforming node on the tube of scenes/tube_support_impact.toml,
/// built in code with the same parameters (clamped-clamped beam EI = 534, ρA = 0.743, 10
/// elements, 6 bending modes, ζ = 1 %; harmonic forces at node4; gap support at node5, 1 mm
/// clearance, Hunt–Crossley, μ = 0.3; fixed frame):
///  - BM_TubeRhs: one ODE right-hand side with the tube in contact (loads, modal solve, the
///    dissipated, applied and wear-work rates), against BM_TubeRhsNoWear without the wear
///    channel and applied-work tracking (the price of the extra integrals);
///  - BM_TubeStep: one C2 step (LTE model; C1 and NMB take the same modal update here);
///  - BM_TubeReference: CVODE on the first 0.3 s at rtol 1e-10 (67 impacts).
#include <benchmark/benchmark.h>

#include <memory>
#include <numbers>
#include <vector>

#include "contact/gap_support.hpp"
#include "core/applied_load.hpp"
#include "core/model.hpp"
#include "core/output_times.hpp"
#include "flexible/beam_model.hpp"
#include "lie/stepper.hpp"
#include "reference/ode_form.hpp"
#include "reference/reference_solver.hpp"

namespace {

using namespace flexref;

core::Model tube(bool wear, core::FlexibleFormulation formulation) {
  flexible::BeamParameters p;
  p.length = 1.0;
  p.elements = 10;
  p.EA = 1e7;
  p.EI_y = p.EI_z = 534.0;
  p.rho_A = 0.743;
  p.boundary = flexible::BeamBoundary::kClampedClamped;
  flexible::BeamModeFilter filter;
  filter.axial = false;
  flexible::ModalData modal = flexible::make_beam_modal_data(p, 6, filter);
  modal.damping_ratio.setConstant(0.01);
  const int forced = 16, supported = 20;  // node4 (x = 0.4), node5 (x = 0.5)
  core::RigidBodyDescription d;
  d.name = "tube";
  d.mass = 0.0;
  d.I_Bcm_B.setZero();
  d.motion = core::MotionKind::kPrescribed;
  d.prescribed.law.kind = core::AngleLaw::Kind::kConstantRate;
  d.prescribed.law.rate = 0.0;
  const core::NodeAttachment at_force = core::NodeAttachment::of_node(modal, forced);
  const core::NodeAttachment at_support = core::NodeAttachment::of_node(modal, supported);
  const Eigen::Vector3d x_force = modal.p_BoNode_B.col(forced);
  const Eigen::Vector3d x_support = modal.p_BoNode_B.col(supported);
  d.flexible = core::FlexiblePart{std::move(modal), {}, {}};
  std::vector<std::unique_ptr<const core::ForceElement>> e;
  const auto profile = [&](double phase) {
    // A constant profile when the applied work is not tracked (same force at t = 0.25/80 s).
    return wear ? core::TimeProfile::harmonic(80.0, phase) : core::TimeProfile::constant();
  };
  e.push_back(std::make_unique<core::AppliedForce>(0, Eigen::Vector3d(0.0, 60.0, 0.0),
                                                   core::LoadFrame::kWorld, x_force, profile(0.0),
                                                   at_force));
  e.push_back(std::make_unique<core::AppliedForce>(0, Eigen::Vector3d(0.0, 0.0, 20.0),
                                                   core::LoadFrame::kWorld, x_force,
                                                   profile(0.5 * std::numbers::pi), at_force));
  contact::GapSupportGeometry g;
  g.clearance = 1e-3;
  contact::FrictionLaw friction;
  friction.mu = 0.3;
  friction.v_reg = 5e-3;
  e.push_back(std::make_unique<contact::GapSupport>(
      0, x_support, at_support, g, contact::NormalLaw::hunt_crossley(5e8, 1.5, 0.7, 0.1), friction,
      0.3, wear ? "support" : ""));
  std::vector<core::Body> bodies;
  bodies.emplace_back(d);
  return core::Model(std::move(bodies), std::move(e), formulation);
}

/// A state in contact: the support node ≈ 1.1 mm off the axis (first y mode, φ_mid ≈ 1.84 m
/// per unit modal coordinate at unit modal mass), moving.
core::State in_contact(const core::Model& m) {
  core::State s = m.initial_state();
  s[0].q_f.setZero();
  s[0].q_f(0) = 6e-4;
  s[0].qd_f.setConstant(0.05);
  return s;
}

void rhs(benchmark::State& state, bool wear) {
  const core::Model m = tube(wear, core::FlexibleFormulation::kCoupled);
  const reference::OdeForm form(m);
  reference::OdeForm::Scratch scratch = form.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(form.size())), f(y.size());
  form.pack(in_contact(m), y.data());
  for (auto _ : state) {
    form.rhs(core::LoadContext{0.01, 0.01}, y.data(), f.data(), scratch);
    benchmark::DoNotOptimize(f.data());
  }
  state.counters["size"] = form.size();
}
void BM_TubeRhs(benchmark::State& state) { rhs(state, true); }
void BM_TubeRhsNoWear(benchmark::State& state) { rhs(state, false); }

void BM_TubeStep(benchmark::State& state) {
  const core::Model m = tube(true, core::FlexibleFormulation::kLte);
  const std::unique_ptr<lie::Stepper> stepper = lie::make_stepper("c2", m, {});
  const core::State s0 = in_contact(m);
  stepper->initialize(0.0, s0);
  long steps = 0;
  for (auto _ : state) {
    if (++steps % 1000 == 0) stepper->initialize(0.0, s0);  // stay near the support
    benchmark::DoNotOptimize(stepper->step(2.5e-5).ok);
  }
}

void BM_TubeReference(benchmark::State& state) {
  const core::Model m = tube(true, core::FlexibleFormulation::kCoupled);
  const std::vector<double> times = core::output_times(0.3, 0.005);
  reference::SolverOptions o;
  o.rtol = 1e-10;
  reference::ReferenceRun run;
  for (auto _ : state) {
    run = reference::solve_cvode(m, times, o);
    benchmark::DoNotOptimize(run.trajectory.states.back()[0].q_f.data());
  }
  state.counters["steps"] = static_cast<double>(run.stats.steps);
  state.counters["events"] = static_cast<double>(run.stats.events);
}

BENCHMARK(BM_TubeRhs);
BENCHMARK(BM_TubeRhsNoWear);
BENCHMARK(BM_TubeStep);
BENCHMARK(BM_TubeReference)->Unit(benchmark::kMillisecond);

}  // namespace
