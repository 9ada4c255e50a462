/// Physics of geometric stiffening (docs/geometric_stiffening.md), from simulated responses
/// (CVODE, tight tolerance) against closed-form and classical results:
///   - rotating uniform cantilever, zero hub radius, flapwise: the nondimensional frequencies at
///     λ = Ω √(ρA L⁴/EI) = 12 of the classical table (13.1702, 37.6031, 79.6145);
///   - the Southwell coefficient of mode 1 (ω² = ω0² + α Ω², α → 1.193 at small λ);
///   - in-plane: ω² = ω_flap² − Ω² (stiffening and centrifugal softening together);
///   - the Kane–Ryan–Banerjee spin-up beam: bounded for Ω_s = 2, 4, 6, 10 with stiffening, the
///     largest lag while spinning up; divergent for Ω_s = 4 and 6 without.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/output_times.hpp"
#include "reference/reference_solver.hpp"
#include "tests/support/flexible_models.hpp"

namespace flexref {
namespace {

using core::FlexibleFormulation;

/// Uniform cantilever L = 1, EI = 1, ρA = 1 (so λ = Ω and ω̄ = ω) clamped at the spin axis,
/// turning at constant Ω about z; one bending family (bending-xz: flapwise, out of the plane of
/// rotation; bending-xy: in-plane), 20 elements, `modes` modes, geometric stiffening on.
core::Model rotating_unit_cantilever(double omega, bool flapwise, int modes,
                                     const Eigen::VectorXd& q0) {
  flexible::BeamParameters p;
  p.length = 1.0;
  p.elements = 20;
  p.EA = 1e4;
  p.EI_y = 1.0;
  p.EI_z = 1.0;
  p.rho_A = 1.0;
  flexible::BeamModeFilter filter{false, !flapwise, flapwise};
  return testing::constant_rate_model(
      testing::flexible_body(
          "beam", flexible::make_beam_modal_data(
                      p, modes, filter, flexible::BeamModeNormalization::kUnitModalMass, true)),
      FlexibleFormulation::kCoupled, omega, q0);
}

/// The r-th mode of the linearized rotating beam (the initial condition that excites it alone)
/// and its predicted frequency: generalized eigenpair of K + Ω² F_xx (+ −Ω² m_ff in-plane)
/// against m_ff.
struct RotatingMode {
  Eigen::VectorXd shape;
  double omega = 0.0;  ///< rad/s, predicted (sets the run's time scale only)
};

RotatingMode rotating_mode(const core::Model& model, double omega, bool flapwise, int r) {
  const core::Body& b = model.body(0);
  const auto& inv = b.invariants();
  Eigen::MatrixXd K =
      Eigen::MatrixXd(b.modal_stiffness().asDiagonal()) + omega * omega * inv.geometric->F[0];
  if (!flapwise) K -= omega * omega * inv.m_ff;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(K, inv.m_ff);
  return {solver.eigenvectors().col(r), std::sqrt(solver.eigenvalues()(r))};
}

/// Angular frequency of the response projected on mode v (v·m_ff q(t)) from its zero crossings
/// (linear interpolation between outputs): π (half periods) / (time between first and last).
double measured_frequency(const core::Model& model, const Eigen::VectorXd& v, double end,
                          double dt) {
  const auto times = core::output_times(end, dt);
  reference::SolverOptions o;
  o.rtol = 1e-11;
  const auto run = reference::solve_cvode(model, times, o);
  const Eigen::VectorXd mv = model.body(0).invariants().m_ff * v;
  std::vector<double> c;
  const auto& s = run.trajectory.states;
  for (std::size_t k = 1; k < times.size(); ++k) {
    const double a = mv.dot(s[k - 1][0].q_f);
    const double b = mv.dot(s[k][0].q_f);
    if ((a < 0.0) != (b < 0.0)) c.push_back(times[k - 1] + (times[k] - times[k - 1]) * a / (a - b));
  }
  REQUIRE(c.size() >= 20);
  return std::numbers::pi * static_cast<double>(c.size() - 1) / (c.back() - c.front());
}

/// Frequency of mode r at spin λ, simulated over ~25 periods with ~60 outputs per period.
double rotating_frequency(double lambda, bool flapwise, int modes, int r) {
  const core::Model probe = rotating_unit_cantilever(lambda, flapwise, modes, {});
  const RotatingMode mode = rotating_mode(probe, lambda, flapwise, r);
  const core::Model model = rotating_unit_cantilever(lambda, flapwise, modes, 1e-3 * mode.shape);
  // The predicted frequency fixes the time scale of the run (the measurement is the simulation's).
  const double period = 2.0 * std::numbers::pi / mode.omega;
  return measured_frequency(model, mode.shape, 25.0 * period, period / 60.0);
}

TEST_CASE("rotating cantilever, flapwise: the classical frequencies at λ = 12",
          "[reference][flexible][geometric]") {
  // Uniform cantilever, zero hub radius, λ = 12: ω̄ = 13.1702, 37.6031, 79.6145 (the classical
  // table: Wright et al. 1982, Hodges & Rutkowski 1981). The finite-element modes (20 Hermite
  // elements) are converged to ~1e-6; six modes carry the stiffening's coupling (the third
  // frequency moves by < 1e-4 from 6 to 8 modes); the zero-crossing measurement over 25 periods
  // at 60 outputs per period is accurate to ~1e-6. The acceptance bound is the 0.5 %.
  const double expected[3] = {13.1702, 37.6031, 79.6145};
  for (int r = 0; r < 3; ++r) {
    const double w = rotating_frequency(12.0, true, 6, r);
    INFO("mode " << r + 1 << ": ω̄ = " << w << " (table " << expected[r] << ")");
    CHECK(w == Approx(expected[r]).epsilon(5e-3));
  }
}

TEST_CASE("rotating cantilever: Southwell coefficient of mode 1 and in-plane ω² = ω_flap² − Ω²",
          "[reference][flexible][geometric]") {
  // Southwell: ω1² = ω0² + α Ω² with α = 1.193 for mode 1 of a uniform cantilever at zero hub
  // radius; at λ = 0.5 the O(λ⁴) remainder is below 1e-3 of α; the measurement (1e-6 of ω)
  // contributes 2 ω̄0² 1e-6 / λ² ≈ 1e-4. Bound 0.3 %.
  const core::Model still = rotating_unit_cantilever(0.0, true, 6, {});
  const double w0 = still.body(0).natural_frequencies()(0);
  REQUIRE(w0 == Approx(3.5160).epsilon(1e-4));
  const double lambda = 0.5;
  const double w1 = rotating_frequency(lambda, true, 6, 0);
  const double alpha = (w1 * w1 - w0 * w0) / (lambda * lambda);
  INFO("ω̄0 = " << w0 << ", ω̄1(λ = 0.5) = " << w1 << ", Southwell α = " << alpha);
  CHECK(alpha == Approx(1.193).epsilon(3e-3));

  // In-plane at λ = 6: the in-plane modes have the flapwise shapes, stiffening Ω² F_xx and the
  // classical softening −Ω² m_ff: ω_in² = ω_flap² − Ω² exactly in the model; both measured to
  // ~1e-6, bound 1e-4 relative on ω².
  for (int r = 0; r < 2; ++r) {
    const double flap = rotating_frequency(6.0, true, 6, r);
    const double in_plane = rotating_frequency(6.0, false, 6, r);
    INFO("mode " << r + 1 << ": flapwise " << flap << ", in-plane " << in_plane
                 << ", √(flap² − 36) = " << std::sqrt(flap * flap - 36.0));
    CHECK(in_plane * in_plane == Approx(flap * flap - 36.0).epsilon(1e-4));
  }
}

struct SpinUpPeak {
  double lag = 0.0;   ///< the tip's most negative deflection along the rotating y axis, m
  double time = 0.0;  ///< when, s
  double late = 0.0;  ///< max |deflection| over [25, 30] s, m
  bool finite = true;
};

SpinUpPeak spin_up_peak(double omega_s, bool stiffening) {
  const core::Model model =
      testing::spin_up_beam_model(FlexibleFormulation::kCoupled, omega_s, 4, 10, stiffening);
  const auto times = core::output_times(30.0, 0.05);
  reference::SolverOptions o;
  o.rtol = 1e-8;
  const auto run = reference::solve_cvode(model, times, o);
  const core::Body& b = model.body(0);
  const core::TrackedPoint& tip = b.description().points[0];
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(b.mode_count());
  SpinUpPeak peak;
  for (std::size_t k = 0; k < times.size(); ++k) {
    const double y = (b.p_BrP_B(tip, run.trajectory.states[k][0].q_f) - b.p_BrP_B(tip, zero)).y();
    peak.finite = peak.finite && std::isfinite(y);
    if (y < peak.lag) {
      peak.lag = y;
      peak.time = times[k];
    }
    if (times[k] >= 25.0) peak.late = std::max(peak.late, std::abs(y));
  }
  return peak;
}

TEST_CASE("spin-up beam: stiffened it stays bounded for Ω_s = 2, 4, 6, 10, classical diverges",
          "[reference][flexible][geometric]") {
  // Kane, Ryan and Banerjee (1987): L = 10 m, EI = 1.4e4 N m², ρA = 1.2 kg/m, T_s = 15 s;
  // in-plane ω1 = 3.80 rad/s. With stiffening the in-plane stiffness is ω_flap(Ω)² − Ω² ≥ ω1² > 0
  // at every spin: the beam lags while the hub accelerates (largest lag during spin-up, t < T_s),
  // returns, and vibrates about zero; the lag grows with the spin-up acceleration 2Ω_s/T_s yet
  // stays far below the beam length (bound 1.5 m = 0.15 L; published lags are below 1 m).
  double previous = 0.0;
  for (const double omega_s : {2.0, 4.0, 6.0, 10.0}) {
    const SpinUpPeak p = spin_up_peak(omega_s, true);
    INFO("Ω_s = " << omega_s << ": peak tip lag " << p.lag << " m at " << p.time
                  << " s; late amplitude " << p.late << " m");
    CHECK(p.finite);
    CHECK(p.lag < -0.05);
    CHECK(p.lag > -1.5);
    CHECK(p.time < 15.0);
    CHECK(p.late < std::abs(p.lag));
    CHECK(std::abs(p.lag) > std::abs(previous));
    previous = p.lag;
  }
  // Without stiffening, Ω(t) passes ω1 = 3.80 rad/s for Ω_s = 4 and 6 and the in-plane stiffness
  // ω1² − Ω² turns negative: the deflection grows exponentially (to > 10 m, i.e. the model is
  // meaningless; docs/design/model.md, "Geometric stiffening").
  for (const double omega_s : {4.0, 6.0}) {
    const SpinUpPeak p = spin_up_peak(omega_s, false);
    INFO("classical Ω_s = " << omega_s << ": late amplitude " << p.late << " m");
    CHECK((!p.finite || p.late > 10.0));
  }
}

}  // namespace
}  // namespace flexref
