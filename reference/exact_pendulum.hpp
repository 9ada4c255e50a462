#pragma once
/// \file exact_pendulum.hpp
/// Exact motion of a compound (physical) pendulum released from rest.
///
/// Sources: L. D. Landau, E. M. Lifshitz, Mechanics, §11 problem 1 (finite-amplitude period);
/// Abramowitz & Stegun §16.4 and DLMF §22.19(i) (pendulum in Jacobi functions).
#include <Eigen/Core>

#include "reference/exact_torque_free.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::reference {

/// Rigid body of mass m on a fixed pivot, centre of mass at c_B (body frame, pivot → centre of
/// mass), inertia J_pivot_B about the pivot, uniform gravity g_W, released at rest from θ₀.
/// It rotates about the fixed global axis \f$n = (A(\theta_0)c_B \times g_W)/|\cdot|\f$, which
/// must be a principal axis of J_pivot (otherwise the motion is not planar). With θ the angle
/// of c from the downward vertical, \f$J_n = n_B^T J n_B\f$, \f$l = |c|\f$:
/// \f[ J_n\ddot\theta = -m g l \sin\theta,\qquad \omega_0^2 = \frac{m g l}{J_n},\qquad
///     \theta(t) = 2\arcsin\bigl(k\,\mathrm{sn}(K - \omega_0 t, k)\bigr),\quad
///     k = \sin\tfrac{\theta_0}{2}, \f]
/// period 4K(k)/ω₀. The half-angles are evaluated as sin(θ/2) = k sn and cos(θ/2) = dn (no
/// arcsin, no cancellation near the inverted position), with k = |ĉ − ĝ|/2 and
/// k' = |ĉ + ĝ|/2 accurate even for a release within 1e-8 of upside down. The attitude is
/// \f$A(t) = \mathrm{Rot}(n, \theta_0 - \theta(t))\,A(\theta_0)\f$ and
/// \f$\omega_B = 2 k \omega_0\,\mathrm{cn}(K - \omega_0 t)\, n_B\f$. A body released exactly
/// above or below the pivot (c ∥ g), or with c = 0, stays at rest.
///
/// Accuracy, against RKF78 in float128 over the bundled scene (t ≤ 10): ω to 8e-15·ω₀, θ to
/// 1e-14 rad. Note that above the horizontal the planar motion is unstable to out-of-plane
/// perturbations, so a numerical solution drifts away from it (see the test); this is the
/// exact planar solution. at() allocates nothing and costs one AGM (≈ 0.7 µs).
///
/// Written once for any scalar type S (docs/precision.md): the bodies are in
/// exact_pendulum_impl.hpp, instantiated for double in exact_pendulum.cpp and for long double and
/// float128 in precision/exact_solution_instances.cpp. PendulumExact is the double one.
template <typename S>
class PendulumExactTpl {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  using Quaternion = Eigen::Matrix<S, 4, 1>;

  /// \throws std::invalid_argument for non-positive mass, non-finite input, a J_pivot that is
  /// not symmetric to 1e-12 relative, an axis n that is not principal to 1e-12·‖J‖ (a larger
  /// coupling would tilt the plane of motion by more than the accuracy claimed here), or
  /// n_Bᵀ J n_B ≤ 0.
  PendulumExactTpl(S mass, const Vector3& c_B, const Matrix3& j_pivot_B, const Vector3& g_W,
                   const Quaternion& theta0);

  RigidAttitudeTpl<S> at(S t) const;
  /// 4K(k)/ω₀; +∞ when the body stays at rest.
  S period() const;
  /// ω₀ = √(m g l/J_n), the small-amplitude angular frequency; 0 when the body stays at rest.
  S natural_frequency() const { return omega0_; }
  /// θ₀, the release angle from the downward vertical, in [0, π].
  S amplitude() const { return amplitude_; }
  /// The rotation axis n (global frame); zero when the body stays at rest.
  const Vector3& axis_W() const { return axis_W_; }

 private:
  Quaternion theta0_;
  bool at_rest_ = true;
  Vector3 axis_W_ = Vector3::Zero();
  Vector3 axis_B_ = Vector3::Zero();
  S amplitude_ = S(0);
  S omega0_ = S(0);
  S k_ = S(0), k_prime_ = S(1), quarter_period_ = S(0);
};
using PendulumExact = PendulumExactTpl<double>;

extern template class PendulumExactTpl<double>;

}  // namespace flexref::reference
