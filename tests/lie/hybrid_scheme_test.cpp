/// The paper's hybrid scheme on flexible bodies (docs/design/schemes.md, "The hybrid step"): C1, C2
/// or NMB for the rotation, central differences for the translation and the modal coordinates,
/// integrating the LTE model. The error is measured against the LTE model integrated by
/// Boost.Odeint RKF7(8) at 1e-12 (CVODE agrees with it, tests/reference). Metric: L∞ over the
/// outputs of |q_f − q_f,ref|∞ plus the geodesic attitude angle plus the tip position error.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "reference/reference_solver.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/order_checks.hpp"

namespace flexref::lie {
namespace {

using core::FlexibleFormulation;

double modal_trajectory_error(const core::Model& model, const core::Trajectory& a,
                              const core::Trajectory& b) {
  REQUIRE(a.states.size() == b.states.size());
  double e = 0.0;
  const core::TrackedPoint& tip = model.body(0).description().points.front();
  for (std::size_t k = 0; k < a.states.size(); ++k) {
    const core::BodyState& s = a.states[k][0];
    const core::BodyState& r = b.states[k][0];
    const double modal = (s.q_f - r.q_f).cwiseAbs().maxCoeff();
    const double angle = rotation::geodesic_angle(s.theta_WB, r.theta_WB);
    const double tip_error = (model.p_WP(0, s, tip) - model.p_WP(0, r, tip)).norm();
    e = std::max(e, modal + angle + tip_error);
  }
  return e;
}

core::Trajectory reference(const core::Model& model, const std::vector<double>& times,
                           double rtol) {
  reference::SolverOptions options;
  options.rtol = rtol;
  return reference::solve_odeint(model, times, options).trajectory;
}

std::vector<double> errors_for(const core::Model& model, const std::string& scheme,
                               const std::vector<double>& times, const core::Trajectory& ref,
                               double h0) {
  std::vector<double> errors;
  for (double h : {h0, h0 / 2.0, h0 / 4.0}) {
    const auto stepper = make_stepper(scheme, model, {});
    errors.push_back(modal_trajectory_error(model, run_scheme(model, *stepper, h, times), ref));
  }
  return errors;
}

// Order 2 of every scheme over [0, 2] with steps 0.01, 0.005, 0.0025 (below 2/ω_max = 0.05),
// against the LTE reference at 1e-12 whose error is bounded by its distance to a run 100×
// looser.
void check_hybrid_orders(const core::Model& model) {
  const std::vector<double> times = core::output_times(2.0, 0.05);
  const core::Trajectory ref = reference(model, times, 1e-12);
  const double ref_error = modal_trajectory_error(model, reference(model, times, 1e-10), ref);
  for (const std::string& name : builtin_scheme_names()) {
    DYNAMIC_SECTION("scheme " << name) {
      testing::check_two_sided_order(errors_for(model, name, times, ref, 0.01), 2.0, ref_error);
    }
  }
}

TEST_CASE("the hybrid schemes refuse the coupled model", "[lie][flexible]") {
  const core::Model coupled = testing::flexible_spinner_model(FlexibleFormulation::kCoupled);
  for (const std::string& name : builtin_scheme_names()) {
    CHECK_THROWS_AS(make_stepper(name, coupled, {}), std::invalid_argument);
  }
}

TEST_CASE("hybrid scheme: observed order 2 on flexible_spinner against the LTE reference",
          "[lie][flexible][order]") {
  // Span [0, 2]: the torque pulse [0, 0.5) and 1.5 s of free spinning with vibrating modes
  // (ω = 6.3 and 39.4 rad/s). Steps 0.01 → 0.0025 are below 2/ω_max = 0.05 (stability) and
  // h ω_max ≤ 0.4 (the asymptotic range of central differences on the fastest mode).
  check_hybrid_orders(testing::flexible_spinner_model(FlexibleFormulation::kLte));
}

TEST_CASE("hybrid scheme: observed order 2 on a tumbling flexible spinner (non-commuting)",
          "[lie][flexible][order]") {
  // The bundled spinner turns about a principal axis, so its rotations commute. Here the spin
  // is tilted, ω̄0 = (0.3, 0.2, 1), and the modes start deflected: the attitude tumbles and
  // the rigid and modal errors interact.
  const core::Model base = testing::flexible_spinner_model(FlexibleFormulation::kLte);
  core::RigidBodyDescription d = base.body(0).description();
  d.initial.w_WB_B = Eigen::Vector3d(0.3, 0.2, 1.0);
  d.flexible->q0 = Eigen::Vector4d(0.02, 0.01, 0.005, 0.0);
  std::vector<core::Body> bodies;
  bodies.emplace_back(d);
  testing::FlexibleElements elements;
  elements.push_back(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d(1.0, 0.0, 5.0), core::LoadFrame::kWorld,
      core::TimeProfile::sin2_pulse(0.0, 0.5)));
  const core::Model model(std::move(bodies), std::move(elements), FlexibleFormulation::kLte);
  check_hybrid_orders(model);
}

TEST_CASE("hybrid scheme: observed order 2 on a rotating cantilever (prescribed hub)",
          "[lie][flexible][order]") {
  Eigen::VectorXd q0(2);
  q0 << 0.02, 0.01;
  const core::Model model =
      testing::rotating_cantilever_model(FlexibleFormulation::kLte, 3.0, 2, 10, q0);
  check_hybrid_orders(model);
}

TEST_CASE("hybrid scheme: central differences on the modes are stable below 2/omega_max only",
          "[lie][flexible][stability]") {
  // A vibrating prescribed beam with no spin: the modal part is the undamped oscillators
  // q̈ = −ω² q, whose central-difference limit is h ω_max < 2. Just below, the modal energy
  // stays within a bounded ratio; just above, the fastest mode grows like ρ^n with
  // ρ = |λ| > 1 and passes 1e6 × its initial size within 200 steps at h = 1.02·2/ω.
  Eigen::VectorXd q0(4);
  q0 << 0.02, 0.02, 0.01, 0.01;
  const core::Model model =
      testing::rotating_cantilever_model(FlexibleFormulation::kLte, 0.0, 4, 10, q0);
  const double omega_max = model.body(0).natural_frequencies().maxCoeff();
  const double h_limit = 2.0 / omega_max;
  auto max_modal = [&](double h, int steps) {
    const auto stepper = make_stepper("c2", model, {});
    stepper->initialize(0.0, model.initial_state());
    double m = 0.0;
    for (int k = 0; k < steps; ++k) {
      if (!stepper->step(h).ok) return std::numeric_limits<double>::infinity();
      m = std::max(m, stepper->state()[0].q_f.cwiseAbs().maxCoeff());
    }
    return m;
  };
  // Energy of the discrete oscillator below the limit: the amplitude of q_n is bounded by
  // q0/√(1 − (hω/2)²) ≈ 5 q0 at hω = 0.98·2.
  CHECK(max_modal(0.98 * h_limit, 2000) < 10.0 * q0.maxCoeff());
  CHECK(max_modal(1.02 * h_limit, 400) > 1e6 * q0.maxCoeff());
}

}  // namespace
}  // namespace flexref::lie
