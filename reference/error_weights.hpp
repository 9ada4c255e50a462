#pragma once
/// \file error_weights.hpp
/// The error weights of the multistep references, CVODE and IDA (docs/references.md, "Error
/// weights"): w_i = 1/tol_i in their weighted RMS norms, so that the attitude error a run
/// accumulates is rtol × the angle each body turns, whatever the formulation.
///
/// Why. A linear multistep method keeps every step's local error below the tolerance, and on a
/// rotation those errors are systematic (Adams leads, BDF lags and damps): after N steps the
/// attitude is off by ~N × tol. With SUNDIALS' per-component weights rtol|y_i| + atol, the
/// heavy top (150 rad/s) took 13 CVODE steps and 57 IDA steps per radian turned at rtol 1e-11,
/// and its transverse angular velocity (4.6 rad/s, turning at 145 rad/s in the body frame),
/// held to 5.6 rtol per step, drifted the energy linearly and the attitude quadratically:
/// 1.8e-7 and 2.4e-7 rad after 2 s against rtol × 300 rad = 3e-9.
///
/// What. Per body with an attitude (θ, ω̄ in y), with s = |ω̄| + 1/T (T the run's span) and
/// f = min(1, s h̄), h̄ the run's mean step so far (StepClock::mean_step; f = 1 before the first
/// step), the tolerances are the natural sizes of what one step may add to the attitude error:
///   θ (unit quaternion, all four components):  tol = f (rtol + atol)
///                       — rtol of the angle the body turns in a step, and h̄/T rad at rest;
///   ω̄ (all three components):                  tol = f (rtol + atol) / T
///                       — a rate error δω turns into the attitude error δω (T − t) ≤ δω T;
/// so that the errors of all the steps add up to (rtol + atol)(∫|ω̄| dt + 1) at most: error per
/// unit step, on the rotation only. h̄ is the mean over the run, not the current step: with the
/// current step CVODE's order selection stalled at order 6 on heavy_top (12 493 steps at rtol
/// 1e-11 instead of 3 561 with the mean). Both are floored at kRoundoff ε times the
/// component's size (1 for θ; |ω_i| + 1/T for ω_i): below that the solver would be asked for
/// less than its own rounding. Every other component (positions, velocities, modal
/// coordinates, the integrals) keeps SUNDIALS' 1/(rtol |y_i| + atol), and algebraic components
/// (IDA's multipliers) their own absolute tolerance (set_algebraic). IDA leaves those out of its
/// error test, but its weighted RMS norm still divides by all N components (N_VWrmsNormMask), so
/// the N_d tested components' weights are multiplied by √(N/N_d): the test is then the RMS over
/// the tested components, as CVODE's over the same state (Andrews' squeezer: N = 173, N_d = 91).
///
/// Where. Only on a smooth, non-stiff model (rotation_weights_per_step, method_choice.hpp: no
/// contact, no stiff or stiff oscillatory mode); elsewhere the solvers get no RotationBlock and
/// so SUNDIALS' weights throughout. The share presumes that the rotation's accuracy sets the
/// steps. Where stiffness or contacts set them, smaller steps made the share smaller and the
/// tolerance tighter, and the steps smaller again (rtol 1e-10, steps before → with the share:
/// flexible_spinner_64 CVODE BDF2 32 743 → 391 113, IDA 42 343 → 410 346;
/// double_pendulum_impacts CVODE 43 084 → 649 799, IDA 46 436 → 1 994 672;
/// pendulum_on_sliding_support CVODE 1.7 million steps — docs/references.md).
///
/// IDA on ideal joints (index-2 GGL form, dae_form.hpp) floors the tolerances at
/// kIndex2Roundoff ε instead of kRoundoff ε: the Newton corrections of its Euler parameters
/// jitter by 1–4 ulp whatever the step (measured on Andrews' squeezer: the constraint rows'
/// rounding, ε |p|, turned into attitude through the joints' levers), and IDA accepts a
/// corrector after a fresh Jacobian only if 20 ‖δ‖ ≤ 0.33 in its weighted RMS norm: 3 ulp on the
/// 14 of its 173 components that jitter is ‖δ‖ = 3 ε √(14/173)/tol ≤ 0.0165 for tol ≥ 52 ε, 72 ε
/// with the √(N/N_d) above. At 8 ε the iteration stalled, the step fell and the index-2 matrix
/// (condition ~ h⁻²) made it worse: IDA_CONV_FAIL at h = 1e-19 on Andrews, 1.1 million steps on
/// heavy_top_spherical at rtol 1e-11; at 100 ε neither (docs/references.md). Near a singular
/// configuration the iteration's rounding grows beyond any fixed floor; IDA then drops the
/// share (drop_rotation_share, ida_solver.cpp).
///
/// On ideal joints the floors also grow with the bodies' distance from the origin
/// (set_joint_rounding): a length row compares world coordinates, so it is rounded at ε |p|
/// (m), and the joint's arm ℓ turns that into ε |p| / ℓ rad of the body's attitude; a velocity
/// row likewise into ε |v| / ℓ rad/s of its angular velocity. So the floors are
///   θ:  R ε max(1, |p| / ℓ),        ω̄_i:  R ε max(|ω̄_i| + 1/T, |v| / ℓ),
/// with R the multiple above and ℓ the joints' length scale (core::Model::joint_length_scale).
/// Why: on issue 52's chain of N rods of 0.2 m (|p| up to 0.2 N m) the fixed floors lay below
/// that rounding from N ≈ 64 on; the error estimates of the attitudes were then rounding, the
/// steps fell, the mean step h̄ and with it the share fell, and the steps fell again. IDA at
/// rtol 1e-8 took 28 939 steps over 0.45 s at N = 96 (20 s; 1 756 without the share) and did
/// not end at N = 128; CVODE at rtol 1e-11 took 38 185 steps at N = 128. With the floors above:
/// 4 861 steps (N = 96), 7 016 steps (IDA, N = 128), 12 379 (CVODE, rtol 1e-11, N = 128).
#include <vector>

namespace flexref::reference {

/// The offsets in y of a body's Euler parameters θ (4) and angular velocity ω̄ (3), and of its
/// position p (3) and velocity v (3) for the joints' rounding (−1: none). A joint angle and its
/// rate (the reduced form's coordinates, reference/reduced_cvode.hpp) are a block of one
/// attitude and one rate component: the same budget per unit step, its speed |u|.
struct RotationBlock {
  int theta = -1;
  int w = -1;
  int p = -1;
  int v = -1;
  int attitudes = 4;  ///< components at theta
  int rates = 3;      ///< components at w
};

class ErrorWeights {
 public:
  /// Multiples of ε (machine epsilon) times a component's size below which no rotation
  /// tolerance goes: the solvers' own rounding, and IDA's index-2 Newton iteration's (above).
  static constexpr double kRoundoff = 8.0;
  static constexpr double kIndex2Roundoff = 100.0;

  /// `span`: the run's time span T (s); T ≤ 0 (a run of one output time) keeps SUNDIALS'
  /// weights on the rotation too, as does an empty `rotations`. `roundoff`: the floor's multiple
  /// of ε.
  ErrorWeights(int size, double rtol, double atol, double span,
               std::vector<RotationBlock> rotations, double roundoff = kRoundoff);
  /// Components [first, size) are algebraic, with absolute tolerance `atol` (IDA's multipliers:
  /// out of its error test, in its Newton test, in both norms' count); the weights of the others
  /// are multiplied by √(size/first).
  void set_algebraic(int first, double atol);
  /// On ideal joints: the floors grow with |p| / ℓ and |v| / ℓ (above); `length_scale` ℓ > 0 (m),
  /// the joints' length scale. Blocks without p and v offsets keep the fixed floors.
  void set_joint_rounding(double length_scale);

  /// The weights at y given the run's mean step so far (≤ 0: none yet); ewt has size() entries.
  /// Allocates nothing.
  void evaluate(const double* y, double mean_step, double* ewt) const;

  /// Whether the rotation is weighted per unit step (rotation blocks and a span T > 0).
  bool weighs_rotation() const { return span_ > 0.0 && !rotations_.empty(); }
  /// SUNDIALS' weights on the rotation from now on (IDA's fallback, ida_solver.cpp).
  void drop_rotation_share() { rotations_.clear(); }

  int size() const { return size_; }

 private:
  int size_;
  double rtol_, atol_, span_;
  std::vector<RotationBlock> rotations_;
  double roundoff_;
  double joint_length_scale_ = 0.0;  ///< ℓ with ideal joints (set_joint_rounding), else 0
  int algebraic_first_ = -1;
  double algebraic_atol_ = 0.0;
  double differential_scale_ = 1.0;  ///< √(size/first) with algebraic components, else 1
};

}  // namespace flexref::reference
