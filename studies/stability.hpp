#pragma once
/// \file stability.hpp
/// The `stability` study for rigid bodies (docs/design/studies.md, "Stability at the extremes"):
/// the largest stable step of each scheme by bisection against a swept parameter (spin rate
/// |W0| or inertia ratio J3/J1 of a torque-free body), a built-in set of degenerate and extreme
/// bodies, and long runs recording energy, angular-momentum and quaternion-norm drift.
///
/// **Instability criterion** (StabilityCriterion). A run of `steps` steps from the initial
/// state is unstable as soon as
///   - a state component becomes non-finite ("non-finite"),
///   - a step fails, i.e. the scheme's Newton solve does not converge ("newton failure: …"),
///   - the kinetic energy leaves |E − E₀| ≤ energy_factor·|E₀| ("energy growth"), or
///   - the world angular momentum leaves |π − π₀| ≤ momentum_factor·|π₀| ("momentum growth").
/// Both quantities are exact invariants of a torque-free body, so a bounded error of a few
/// percent (NMB, C2 at h|W| ≲ 0.25, docs/schemes.md) is "stable", while C2's energy run-away to
/// the largest energy compatible with |π| (E/E₀ → J3/J1 of the body, 1.67 on free_spin) is
/// not. The default factor 0.5 sits between the two. A fixed number of steps (not a fixed time
/// span) makes the test invariant under the similarity W → sW, h → h/s of the free rigid body,
/// so h_max·|W| is a property of the scheme and the body shape alone.
///
/// **No central-difference limit.** A free rigid body is not a linear oscillator, so there is
/// no exact h_max = 2/ω. The plot draws two guides: h|W| = 2, the central-difference limit of a
/// linear oscillator of the body's spin frequency, and h|W| = π, where the rotation per step
/// reaches π and a sampled rotation can no longer be told from the reverse one (the step's
/// rotation vector leaves the injectivity domain of exp/log on SO(3)).
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"
#include "studies/stability_parameter.hpp"

namespace flexref::studies {

/// Result of bisect_largest_stable: a stable step and an unstable one bracketing the limit.
struct StableStepBracket {
  double h_stable = 0.0;    ///< largest step found stable (0 if none down to the floor)
  double h_unstable = 0.0;  ///< smallest step found unstable (+inf if none up to the cap)
  int evaluations = 0;      ///< calls of is_stable
  bool bracketed() const;   ///< both ends found: h_unstable ≤ h_stable·(1 + tolerance)
};

/// Default scan ratio of bisect_largest_stable: 2^(1/4), four trial steps per octave.
inline constexpr double kDefaultScanRatio = 1.189207115002721;

/// The first stability limit above h_lo: scans h_lo·rᵏ (r = scan_ratio) upward to the first
/// unstable step (or h_cap), then bisects on log h between it and the last stable one until
/// h_unstable/h_stable ≤ 1 + relative_tolerance. When h_lo itself is unstable, h_lo/4,
/// h_lo/16, … are tried (at most 10 times). Stability need not be monotone in h: the scan
/// finds the first limit, not a later stable window, but may step over an unstable window
/// narrower than the ratio r.
StableStepBracket bisect_largest_stable(const std::function<bool(double h)>& is_stable, double h_lo,
                                        double h_cap, double relative_tolerance,
                                        double scan_ratio = kDefaultScanRatio);

/// When a run counts as unstable (see the file comment).
struct StabilityCriterion {
  long steps = 1000;             ///< steps per run
  double energy_factor = 0.5;    ///< unstable when |E − E₀| > energy_factor·|E₀|
  double momentum_factor = 0.5;  ///< unstable when |π − π₀| > momentum_factor·|π₀|
};

/// Classification of one run of `scheme` built with `method_options`: "stable", "energy
/// growth", "momentum growth", "non-finite", "newton failure: <the scheme's message>", or
/// "exception: <what>". Never throws for an unstable run; throws std::invalid_argument for a
/// model with force elements (the energy and momentum tests assume a torque-free model), an
/// unknown scheme or an option value its factory refuses.
std::string classify_run(const core::Model& model, const std::string& scheme,
                         const lie::MethodOptions& method_options, double h,
                         const StabilityCriterion& criterion);

/// Largest stable step of a scheme on a torque-free model (the first limit above h_lo, at
/// most h_cap), by bisect_largest_stable on classify_run(…) == "stable".
double largest_stable_step(const core::Model& model, const std::string& scheme,
                           const lie::MethodOptions& method_options,
                           const StabilityCriterion& criterion, double h_lo, double h_cap,
                           double relative_tolerance);

/// A torque-free single free body with inertia I_Bcm_B and initial angular velocity w_WB_B.
core::Model make_free_body_model(const Eigen::Matrix3d& I_Bcm_B, const Eigen::Vector3d& w_WB_B);

/// Inertia of the inertia-ratio sweep: diag(1, r − ½, r) kg·m² for r = J3/J1 ≥ 1, a slightly
/// asymmetric slender rod for large r (J1 ≪ J2 < J3, triangle inequality J1 + J2 ≥ J3 kept).
Eigen::Matrix3d rod_inertia(double ratio);

struct StabilityOptions {
  StabilityParameter parameter = StabilityParameter::kSpin;  ///< or kInertiaRatio
  std::vector<double> values;
  std::vector<std::string> schemes = lie::default_scheme_names();
  /// The options every scheme's stepper is built with (genalpha's ρ∞ and perturbed start, a
  /// user method's named values; lie/method_options.hpp).
  lie::MethodOptions method_options;
  /// The body: free_spin's J = diag(3, 4, 5) and W0 direction (0.2, 0.3, 2.0) by default.
  Eigen::Matrix3d I_Bcm_B = Eigen::Vector3d(3.0, 4.0, 5.0).asDiagonal();
  Eigen::Vector3d w_direction_B{0.2, 0.3, 2.0};
  double spin = 1.0;  ///< |W0| for the inertia-ratio sweep and the degenerate set (rad/s)
  StabilityCriterion criterion;
  double relative_tolerance = 1e-3;  ///< bisection stops at h_unstable/h_stable ≤ 1 + this
  bool degenerate = true;            ///< also run the built-in degenerate set
  long long_run_steps = 0;           ///< 0: no long run
  double long_run_h = 0.01;          ///< s, on the base body at its |W0| = |w_direction_B|
  int long_run_samples = 1000;       ///< rows per scheme in long_run.csv
  int jobs = 1;
  bool progress = false;  ///< "stability: k/N runs" on stderr (studies/progress.hpp)
};

/// One (scheme, body) bisection.
struct StabilityPoint {
  std::string scheme;
  std::string parameter;  ///< "spin", "inertia_ratio" or the degenerate body's name
  double value = 0.0;     ///< swept value (for degenerate bodies: J3/J1)
  double spin = 0.0;      ///< |W0| of the run, rad/s
  double h_max = 0.0;     ///< largest stable step found, s
  double h_unstable = 0.0;
  std::string classification;  ///< why h_unstable is unstable ("stable to cap" if none)
  std::string near_pi;         ///< classification at h|W0| = 3.1 (degenerate set only)
};

struct LongRunSample {
  std::string scheme;
  long step = 0;
  double t = 0.0;
  double energy_drift = 0.0;      ///< |E − E₀|/|E₀|
  double momentum_drift = 0.0;    ///< |π − π₀|/|π₀|, world angular momentum
  double quaternion_drift = 0.0;  ///< ||θ| − 1|
  /// "ok", "unstable" (from the first sample whose energy or momentum drift exceeds the
  /// invariant monitor's tolerance, core/invariants.hpp, on), or the classification that
  /// stopped the run.
  std::string status;
};

struct StabilityResult {
  StabilityOptions options;
  std::vector<StabilityPoint> sweep;       ///< by value, then scheme (option order)
  std::vector<StabilityPoint> degenerate;  ///< by body, then scheme
  std::vector<LongRunSample> long_run;     ///< by scheme, then step
};

/// Runs the sweep, the degenerate set and the long run; parallel over (scheme, value) with
/// options.jobs threads; the numbers do not depend on jobs.
StabilityResult run_stability(const StabilityOptions& options);

/// The degenerate and extreme bodies (name, inertia): flat disk diag(1, 1, 2) and flat plate
/// diag(1, 2, 3) (J3 = J1 + J2), slender rods rod_inertia(1e2), (1e4), (1e6).
std::vector<std::pair<std::string, Eigen::Matrix3d>> degenerate_bodies();

/// CSV: scheme,parameter,value,h_max,h_max_times_spin,classification (sweep and degenerate).
std::string stability_csv(const StabilityResult& result);
/// CSV: scheme,step,t,energy_drift,momentum_drift,quaternion_norm_drift,status.
std::string long_run_csv(const StabilityResult& result);
/// The terminal table.
std::string format_stability_table(const StabilityResult& result);

}  // namespace flexref::studies
