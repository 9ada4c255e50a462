#pragma once
/// \file exact_heavy_top.hpp
/// Exact motion of the symmetric heavy top on a fixed pivot (Lagrange top).
///
/// Sources: H. Goldstein, C. Poole, J. Safko, Classical Mechanics, 3rd ed., §5.7; L. D. Landau,
/// E. M. Lifshitz, Mechanics, §35 problem 1; DLMF §19.7 (change of parameter of Π) and
/// B. C. Carlson, Numer. Algorithms 10 (1995) for the elliptic integrals.
#include <Eigen/Core>
#include <optional>

#include "reference/exact_torque_free.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::reference {

/// Symmetric heavy top: mass m, centre of mass at distance l from the fixed pivot along the
/// body symmetry axis e (unit, pivot → centre of mass, body frame), inertia about the pivot
/// J = J⊥(I − e eᵀ) + J_a e eᵀ, uniform gravity g_W.
///
/// With the z-x-z Euler angles of Goldstein §5.7 (inertial z = up = −g/|g|, body z = e,
/// R = R_up R_z(φ) R_x(ϑ) R_z(ψ) P, P a fixed body rotation taking e to e_z), u = cos ϑ and
/// the constants a = J_a ω₃/J⊥, b = p_φ/J⊥ (p_φ: angular momentum about the vertical),
/// α = 2E'/J⊥, β = 2 m g l/J⊥:
/// \f[ \dot u^2 = f(u) = (1 - u^2)(\alpha - \beta u) - (b - a u)^2
///     = \beta (u - u_1)(u - u_2)(u - u_3),\qquad -1 \le u_1 \le u_0 \le u_2 \le 1 \le u_3, \f]
/// \f[ u = u_1 + (u_2 - u_1)\,\mathrm{sn}^2(\lambda t + \tau_0, k),\quad
///     k^2 = \frac{u_2 - u_1}{u_3 - u_1},\quad \lambda = \tfrac12\sqrt{\beta(u_3 - u_1)}, \f]
/// \f[ \dot\varphi = \frac{b - a u}{1 - u^2} = \frac{b - a}{2(1 - u)} + \frac{b + a}{2(1 + u)},
///     \qquad \dot\psi = \frac{J_\perp a}{J_a} - u\dot\varphi
///     = \frac{J_\perp a}{J_a} - a - \frac{b - a}{2(1 - u)} + \frac{b + a}{2(1 + u)}, \f]
/// so φ = Φ₊ + Φ₋ and ψ = ψ₀ + (J⊥a/J_a − a) t − Φ₊ + Φ₋ with the pole integrals
/// \f[ \Phi_+ = \frac{b - a}{2\lambda(1 - u_1)}\,\Pi_{n_+}(\tau)\Big|_{\tau_0}^{\tau},\;
///     n_+ = \frac{u_2 - u_1}{1 - u_1};\qquad
///     \Phi_- = \frac{b + a}{2\lambda(1 + u_1)}\,H_{\nu_-}(\tau)\Big|_{\tau_0}^{\tau},\;
///     \nu_- = \frac{u_2 - u_1}{1 + u_1}, \f]
/// evaluated in closed form (elliptic::CircularPi, elliptic::ShiftedHyperbolicPi) instead of by
/// quadrature: when the symmetry axis passes close to a vertical (the bundled heavy_top scene
/// has b + a = 4.6e-6 and passes within 7e-7 rad of straight down, where φ̇ reaches 9e6 rad/s
/// for 1e-7 s) a quadrature in t would need ~1e7 nodes per period, whereas the closed forms
/// are a sum of non-negative Carlson integrals. For that to hold, every small difference is
/// formed from the initial data without cancellation: the cubic is re-expanded about u₀ (where
/// f = u̇₀²), about −1 (f = −(b + a)²) and about +1 (f = −(b − a)²), and each root is taken
/// from the expansion about the nearest anchor; b ± a and b − a u₀ = ω⊥·up come straight from
/// ω₀. If b ± a = 0 exactly the axis passes through that pole and Φ∓ becomes a staircase of
/// steps π at the passages (the jump in (φ ± ψ)/2 is multiplied by cos or sin of ϑ/2 = 0, so
/// θ(t) stays continuous); at() is then undefined (0/0) only at the passage instants.
///
/// Accuracy (S = double), measured against RKF78 in float128 at tolerance 1e-24 over the bundled
/// scene (t ≤ 2): ω to 4e-15 relative, θ to 9e-14 rad (also with b + a = 0 exactly). at() allocates
/// nothing: one AGM plus two R_F and two R_J evaluations (≈ 2.5 µs).
///
/// Written once for any scalar type S (as exact_torque_free.hpp): bodies in
/// exact_heavy_top_impl.hpp, instantiated for double in exact_heavy_top.cpp and for long double
/// and float128 in precision/exact_solution_instances.cpp; HeavyTopExact is the double one.
template <typename S>
class HeavyTopExactTpl {
 public:
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Quaternion = Eigen::Matrix<S, 4, 1>;  ///< Euler parameters (e0, e1, e2, e3)

  /// \throws std::invalid_argument for non-positive mass, distance or inertias, a symmetry
  /// axis or θ₀ not unit to 1e-6, zero or non-finite gravity, non-finite ω₀, or an initial
  /// symmetry axis exactly along the vertical with non-zero transverse ω (the Euler-angle
  /// chart is singular there; tilt it by any amount). A top spinning exactly upright or
  /// hanging exactly down about its axis is a permanent rotation and is accepted.
  HeavyTopExactTpl(S mass, S com_distance, const Vector3& axis_B, S j_perp, S j_axial,
                   const Vector3& g_W, const Quaternion& theta0, const Vector3& w0_B);

  RigidAttitudeTpl<S> at(S t) const;

  /// Period of u(t) = cos ϑ (2K/λ); +∞ for permanent rotation and steady precession.
  S nutation_period() const;
  /// Turning points u₁ ≤ u₂ of u = up · (symmetry axis).
  S u_min() const { return S(-1) + y1_; }
  S u_max() const { return S(1) - z2_; }

 private:
  enum class Motion { kPermanentRotation, kSteadyPrecession, kNutation };
  Motion motion_ = Motion::kNutation;
  Quaternion theta0_;
  Vector3 w0_B_;
  Vector3 x_B_, y_B_, axis_B_;  ///< body frame E = (x, y, e) of the Euler angles
  S a_ = S(0);                  ///< J_a ω₃ / J⊥
  S spin_ = S(0);               ///< ω₃ = J⊥ a / J_a
  S p_ = S(0);                  ///< b − a u₀ = ω⊥ · up
  S delta_minus_ = S(0);        ///< b + a
  S delta_plus_ = S(0);         ///< b − a
  S u0_ = S(0);
  S v1_ = S(0), v2_ = S(0);  ///< u₁ − u₀, u₂ − u₀
  S y1_ = S(0), z2_ = S(0);  ///< 1 + u₁, 1 − u₂
  S one_minus_u1_ = S(2);
  S k_ = S(0), k_prime_ = S(1), lambda_ = S(0), tau0_ = S(0), quarter_period_ = S(0);
  S psi0_ = S(0);
  S north_coeff_ = S(0), south_coeff_ = S(0);  ///< (b ∓ a)/(2λ(1 ∓ u₁))
  S north0_ = S(0), south0_ = S(0);            ///< the pole integrals at τ₀
  std::optional<elliptic::CircularPiTpl<S>> north_;
  std::optional<elliptic::ShiftedHyperbolicPiTpl<S>> south_;
  Quaternion q_up_;     ///< R_up
  Quaternion q_frame_;  ///< P: body → E

  struct PoleIntegrals {
    S north;  ///< Φ₊ up to the constant
    S south;  ///< Φ₋ up to the constant
  };
  PoleIntegrals pole_integrals(S tau, const elliptic::JacobiValuesTpl<S>& f, S one_minus_u) const;
  Quaternion euler_part(S t, Vector3& w_B) const;
};
using HeavyTopExact = HeavyTopExactTpl<double>;

extern template class HeavyTopExactTpl<double>;

}  // namespace flexref::reference
