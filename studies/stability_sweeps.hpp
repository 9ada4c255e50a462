#pragma once

/// \file stability_sweeps.hpp
/// Stability sweeps whose limits are linear: the modal frequency of a flexible body and the
/// stiffness of a penalty contact (docs/design/studies.md, "swept parameter ... modal frequency,
/// contact stiffness ... with the theoretical limits drawn"). Both parts are advanced by
/// central differences in every hybrid scheme, whose limit on an undamped linear oscillator
/// of frequency ω is h ω < 2 exactly; the sweep measures where each scheme's run actually
/// becomes unstable and compares with 2/ω.
///
/// - modal_frequency: the flexible spinner's beam (LTE) spinning torque-free with the modes
///   deflected; the beam's bending stiffness is scaled so that the highest modal frequency is
///   the swept ω_max. Unstable when max |q_f| over the run exceeds `growth_factor` × max |q0|,
///   or a state is non-finite, or a step fails. Started from rest, the central-difference
///   oscillator is x_n = x0 cos(nφ) with cos φ = 1 − (hω)²/2 for hω < 2 (never above x0), and
///   grows like ρⁿ, ρ > 1, beyond: the measured limit is 2/ω to the bisection tolerance.
/// - contact_stiffness: a ball (m = 1 kg, r = 0.1 m) resting on a linear undamped penalty
///   floor under gravity, started at rest with a penetration 5 % above the static one δ_s, so
///   it oscillates about δ_s: a linear oscillator of ω = √(k/m). Unstable when the amplitude
///   |δ − δ_s| exceeds growth_factor × its initial 0.05 δ_s (with the default 10, the ball
///   still never leaves the floor, so the oscillator stays linear), or a state is non-finite.
///   (An energy criterion would mislead here: the energy of central differences with the
///   trapezoidal velocity oscillates by a factor 1/(1 − (hω/2)²) even when stable.)
/// Every run takes `steps` steps; the bisection is bisect_largest_stable (stability.hpp).

#include <string>
#include <vector>

#include "core/model.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"
#include "studies/stability_parameter.hpp"

namespace flexref::studies {

struct LinearSweepOptions {
  StabilityParameter parameter = StabilityParameter::kModalFrequency;  ///< or kContactStiffness
  /// ω_max (rad/s) for modal_frequency, k (N/m) for contact_stiffness.
  std::vector<double> values;
  std::vector<std::string> schemes = lie::default_scheme_names();
  /// The options every scheme's stepper is built with (genalpha's ρ∞ and perturbed start, a
  /// user method's named values; lie/method_options.hpp).
  lie::MethodOptions method_options;
  long steps = 2000;
  double growth_factor = 10.0;
  double relative_tolerance = 1e-3;
  int jobs = 1;
  bool progress = false;  ///< "stability: k/N bisections" on stderr (studies/progress.hpp)
};

struct LinearSweepPoint {
  std::string scheme;
  double value = 0.0;          ///< the swept parameter
  double omega = 0.0;          ///< the oscillator frequency it gives, rad/s
  double h_max = 0.0;          ///< largest stable step found, s
  double h_theory = 0.0;       ///< 2/ω, s
  std::string classification;  ///< why the first unstable step is unstable
};

/// The model of one sweep value (see the file comment) and its frequency ω (rad/s); throws
/// std::invalid_argument for a parameter that is not a linear sweep's or a value that is not
/// positive and finite.
core::Model make_linear_sweep_model(StabilityParameter parameter, double value, double& omega);
/// "stable", or why not (see the file comment).
std::string classify_linear_run(const core::Model& model, StabilityParameter parameter,
                                const std::string& scheme, double h,
                                const LinearSweepOptions& options);
/// The sweep, parallel over (value, scheme); the numbers do not depend on jobs.
std::vector<LinearSweepPoint> run_linear_sweep(const LinearSweepOptions& options);
/// CSV: scheme,parameter,value,omega,h_max,h_theory,h_max_times_omega,classification.
std::string linear_sweep_csv(StabilityParameter parameter,
                             const std::vector<LinearSweepPoint>& points);
std::string format_linear_sweep_table(StabilityParameter parameter,
                                      const std::vector<LinearSweepPoint>& points);

}  // namespace flexref::studies
