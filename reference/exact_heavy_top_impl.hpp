#pragma once
/// \file exact_heavy_top_impl.hpp
/// The bodies of HeavyTopExactTpl<S> (exact_heavy_top.hpp), written once for any scalar type
/// S; include only where it is explicitly instantiated (exact_heavy_top.cpp: double;
/// precision/exact_solution_instances.cpp: long double, float128).
#include <algorithm>
#include <boost/math/constants/constants.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "reference/exact_heavy_top.hpp"
#include "reference/exact_rotation_tpl.hpp"
#include "reference/exact_torque_free_impl.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::reference {

namespace detail {

/// c₃x³ + c₂x² + c₁x + c₀, one of the re-expansions of f.
template <typename S>
struct Cubic {
  S c0, c1, c2, c3;
  S operator()(S x) const { return ((c3 * x + c2) * x + c1) * x + c0; }
  S derivative(S x) const { return (S(3) * c3 * x + S(2) * c2) * x + c1; }
};

/// Root of p between `exact_end`, where the sign of p is known exactly (the value there is an
/// expansion coefficient), and `other_end`. If rounding gives p(other_end) the same sign as
/// p(exact_end), the root lies within rounding of other_end and that is returned. Newton with
/// bisection safeguard (Numerical Recipes' rtsafe); converges to relative accuracy ~ε of S
/// (the stop |step| ≤ 2ε|x| is two roundings of x). 200 iterations: Newton converges
/// quadratically once bracketed; bisection alone would gain one bit per iteration, more than
/// quad's 113 bits below an O(1) bracket.
template <typename S>
S bracketed_root(const Cubic<S>& p, S exact_end, S other_end) {
  using std::abs;
  const S eps = std::numeric_limits<S>::epsilon();
  const S f_exact = p(exact_end);
  const S f_other = p(other_end);
  if (f_exact == S(0)) return exact_end;
  if (f_other == S(0) || (f_other > S(0)) == (f_exact > S(0))) return other_end;
  S negative = f_exact < S(0) ? exact_end : other_end;  // p(negative) < 0 < p(positive)
  S positive = f_exact < S(0) ? other_end : exact_end;
  S x = S(0.5) * (negative + positive);
  S step_before = abs(positive - negative);
  S step = step_before;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const S value = p(x);
    if (value == S(0)) return x;
    (value < S(0) ? negative : positive) = x;
    const S slope = p.derivative(x);
    const S newton = (slope != S(0)) ? S(x - value / slope) : x;
    const bool inside = (newton - negative) * (newton - positive) < S(0);
    if (!inside || abs(S(2) * value) > abs(S(step_before * slope))) {
      step_before = step;
      step = S(0.5) * (positive - negative);
      x = negative + step;
    } else {
      step_before = step;
      step = newton - x;
      x = newton;
    }
    if (abs(step) <= S(2) * eps * abs(x) || negative == positive) return x;
  }
  return x;
}

/// Roots of the quadratic c₂x² + c₁x + c₀ = 0 with real roots, (smaller, larger), without
/// cancellation.
template <typename S>
std::pair<S, S> quadratic_roots(S c2, S c1, S c0) {
  using std::copysign;
  using std::sqrt;
  const S discriminant = std::max(S(0), S(c1 * c1 - S(4) * c2 * c0));
  const S q = S(-0.5) * (c1 + copysign(sqrt(discriminant), c1));
  if (q == S(0)) return {S(0), S(0)};
  const S r1 = q / c2;
  const S r2 = c0 / q;
  return {std::min(r1, r2), std::max(r1, r2)};
}

}  // namespace detail

template <typename S>
HeavyTopExactTpl<S>::HeavyTopExactTpl(S mass, S com_distance, const Vector3& axis_B, S j_perp,
                                      S j_axial, const Vector3& g_W, const Quaternion& theta0,
                                      const Vector3& w0_B)
    : theta0_(detail::unit_euler_parameters<S>(theta0, "HeavyTopExact")), w0_B_(w0_B) {
  using std::abs;
  using std::atan2;
  using std::isfinite;
  using std::sqrt;
  const auto positive = [](S x) { return static_cast<bool>(isfinite(x)) && x > S(0); };
  if (!positive(mass) || !positive(com_distance) || !positive(j_perp) || !positive(j_axial)) {
    throw std::invalid_argument(
        "HeavyTopExact: mass, centre-of-mass distance and inertias must be finite and > 0");
  }
  // 1e-6: scenes.md's rule for unit data, not a rounding threshold.
  if (!axis_B.allFinite() || abs(axis_B.norm() - S(1)) > S(1e-6)) {
    throw std::invalid_argument("HeavyTopExact: symmetry axis must be a unit vector");
  }
  const S gravity = g_W.norm();
  if (!g_W.allFinite() || !(gravity > S(0))) {
    throw std::invalid_argument("HeavyTopExact: gravity must be finite and non-zero");
  }
  if (!w0_B.allFinite()) {
    throw std::invalid_argument("HeavyTopExact: initial angular velocity must be finite");
  }
  axis_B_ = axis_B.normalized();
  // E frame: x ⊥ e from the body axis least aligned with e, y = e × x.
  Eigen::Index least = 0;
  axis_B_.cwiseAbs().minCoeff(&least);
  x_B_ = axis_B_.cross(Vector3::Unit(least)).normalized();
  y_B_ = axis_B_.cross(x_B_);
  detail::Matrix3<S> frame;  // rows: x, y, e → maps body coordinates to E coordinates
  frame.row(0) = x_B_.transpose();
  frame.row(1) = y_B_.transpose();
  frame.row(2) = axis_B_.transpose();
  q_frame_ = detail::euler_parameters_from_matrix<S>(frame).normalized();

  const Vector3 up_B = rotation::rotation_matrix<S>(theta0_).transpose() * (-g_W / gravity);
  spin_ = axis_B_.dot(w0_B);
  a_ = j_axial * spin_ / j_perp;
  const Vector3 w_perp_B = w0_B - spin_ * axis_B_;
  p_ = up_B.dot(w_perp_B);                          // b − a u₀
  const S u_rate0 = up_B.dot(w0_B.cross(axis_B_));  // u̇₀
  const S q0 = w_perp_B.squaredNorm();              // α − β u₀ = |ω⊥|²
  const S beta = S(2) * mass * gravity * com_distance / j_perp;
  u0_ = up_B.dot(axis_B_);
  const S s0_squared = up_B.cross(axis_B_).squaredNorm();  // sin²ϑ₀ without cancellation
  const S one_plus_u0 = u0_ >= S(0) ? S(S(1) + u0_) : S(s0_squared / (S(1) - u0_));
  const S one_minus_u0 = u0_ <= S(0) ? S(S(1) - u0_) : S(s0_squared / (S(1) + u0_));
  delta_minus_ = p_ + a_ * one_plus_u0;  // b + a
  delta_plus_ = p_ - a_ * one_minus_u0;  // b − a
  const Vector3 up_E(x_B_.dot(up_B), y_B_.dot(up_B), u0_);
  psi0_ = atan2(up_E.x(), up_E.y());

  if (s0_squared == S(0)) {
    if (w_perp_B.isZero(S(0))) {
      motion_ = Motion::kPermanentRotation;  // spinning exactly about the vertical
      return;
    }
    throw std::invalid_argument(
        "HeavyTopExact: initial symmetry axis exactly vertical with transverse angular "
        "velocity; the Euler-angle chart is singular at t = 0");
  }

  // f re-expanded about u₀ (v = u − u₀), −1 (y = 1 + u) and +1 (z = 1 − u); Q(u) = α − βu.
  const S q_south = q0 + beta * one_plus_u0;   // Q(−1)
  const S q_north = q0 - beta * one_minus_u0;  // Q(1)
  const detail::Cubic<S> around_u0{u_rate0 * u_rate0,
                                   -beta * s0_squared - S(2) * u0_ * q0 + S(2) * a_ * p_,
                                   S(2) * u0_ * beta - q0 - a_ * a_, beta};
  const detail::Cubic<S> around_south{-delta_minus_ * delta_minus_,
                                      S(2) * q_south + S(2) * a_ * delta_minus_,
                                      -q_south - S(2) * beta - a_ * a_, beta};
  const detail::Cubic<S> around_north{-delta_plus_ * delta_plus_,
                                      -(S(-2) * q_north + S(2) * a_ * delta_plus_),
                                      -q_north + S(2) * beta - a_ * a_, S(-beta)};

  // Turning points relative to u₀: f(u₀) = u̇₀² ≥ 0, f(±1) = −(b ± a)² ≤ 0.
  if (around_u0.c0 > S(0)) {
    v1_ = detail::bracketed_root<S>(around_u0, S(0), S(-one_plus_u0));
    v2_ = detail::bracketed_root<S>(around_u0, S(0), one_minus_u0);
  } else if (around_u0.c1 < S(0)) {  // u₀ = u₂: deflate the root v = 0
    v1_ = detail::quadratic_roots<S>(around_u0.c3, around_u0.c2, around_u0.c1).first;
    v2_ = S(0);
  } else if (around_u0.c1 > S(0)) {  // u₀ = u₁
    v1_ = S(0);
    v2_ = detail::quadratic_roots<S>(around_u0.c3, around_u0.c2, around_u0.c1).first;
  }  // else: double root at u₀, steady precession
  const S v3 = -around_u0.c2 / around_u0.c3 - v1_ - v2_;
  const S amplitude = v2_ - v1_;  // u₂ − u₁
  // Pole distances from the expansions about the poles (relative accuracy ~ε even when the
  // axis comes within 1e-7 rad of a vertical), bracketed by the midpoint of [u₁, u₂].
  y1_ = (v1_ == S(0) && around_u0.c0 == S(0))
            ? one_plus_u0
            : detail::bracketed_root<S>(around_south, S(0),
                                        S(one_plus_u0 + v1_ + S(0.5) * amplitude));
  z2_ = (v2_ == S(0) && around_u0.c0 == S(0))
            ? one_minus_u0
            : detail::bracketed_root<S>(around_north, S(0),
                                        S(one_minus_u0 - v2_ + S(0.5) * amplitude));
  y1_ = std::min(y1_, one_plus_u0);
  z2_ = std::min(z2_, one_minus_u0);
  lambda_ = S(0.5) * sqrt(beta * (v3 - v1_));

  if (amplitude == S(0)) {
    motion_ = Motion::kSteadyPrecession;
  } else {
    using std::copysign;
    motion_ = Motion::kNutation;
    const S k2 = amplitude / (v3 - v1_);
    const S k_prime2 = (v3 - v2_) / (v3 - v1_);
    if (!(k_prime2 > S(0))) {
      throw std::invalid_argument(
          "HeavyTopExact: motion asymptotic to the upright position (u₂ = u₃ = 1) is not "
          "supported");
    }
    k_ = sqrt(k2);
    k_prime_ = sqrt(k_prime2);
    quarter_period_ = elliptic::complete_k<S>(k_prime_);
    // sn²τ₀ = (u₀ − u₁)/(u₂ − u₁), cn²τ₀ = (u₂ − u₀)/(u₂ − u₁), sign(sn cn) = sign(u̇₀).
    const S sn0 = copysign(sqrt(S(-v1_ / amplitude)), u_rate0);
    const S cn0 = sqrt(v2_ / amplitude);
    tau0_ = elliptic::incomplete_f<S>(sn0, cn0, k_prime_);
    one_minus_u1_ = one_minus_u0 - v1_;
    // A pole distance that is exactly zero (b ∓ a = 0, or its square underflowed) takes the
    // staircase limit in pole_integrals.
    if (delta_plus_ != S(0) && z2_ > S(0)) {
      north_.emplace(amplitude / one_minus_u1_, z2_ / one_minus_u1_, k_, k_prime_);
      north_coeff_ = delta_plus_ / (S(2) * lambda_ * one_minus_u1_);
    }
    if (delta_minus_ != S(0) && y1_ > S(0)) {
      south_.emplace(amplitude / y1_, k_, k_prime_);
      south_coeff_ = delta_minus_ / (S(2) * lambda_ * y1_);
    }
    const elliptic::JacobiValuesTpl<S> f0 = elliptic::jacobi<S>(tau0_, k_, k_prime_);
    const PoleIntegrals at_tau0 = pole_integrals(tau0_, f0, z2_ + amplitude * f0.cn * f0.cn);
    north0_ = at_tau0.north;
    south0_ = at_tau0.south;
  }

  // R_up = A(θ₀) Pᵀ R'(0)ᵀ with R'(0) from the same evaluation as at(0).
  Vector3 w_B;
  const Quaternion q_euler0 = euler_part(S(0), w_B);
  q_up_ = detail::quaternion_multiply<S>(
              detail::quaternion_multiply<S>(theta0_, detail::quaternion_conjugate<S>(q_frame_)),
              detail::quaternion_conjugate<S>(q_euler0))
              .normalized();
}

template <typename S>
S HeavyTopExactTpl<S>::nutation_period() const {
  if (motion_ != Motion::kNutation) return std::numeric_limits<S>::infinity();
  return S(2) * quarter_period_ / lambda_;
}

template <typename S>
typename HeavyTopExactTpl<S>::PoleIntegrals HeavyTopExactTpl<S>::pole_integrals(
    S tau, const elliptic::JacobiValuesTpl<S>& f, S one_minus_u) const {
  using std::nearbyint;
  const S pi = boost::math::constants::pi<S>();
  PoleIntegrals result{S(0), S(0)};
  const S half_period = S(2) * quarter_period_;
  // Φ₊: ∫dτ/(1 − u) = Π_{n₊}(τ)/(1 − u₁), p = 1 − n₊ sn²τ = (1 − u)/(1 − u₁). With b − a = 0
  // (u₂ = 1) the limit is a staircase: a step π per passage τ = K + 2Kj.
  if (north_) {
    result.north = north_coeff_ * (*north_)(tau, f, one_minus_u / one_minus_u1_);
  } else {
    result.north = pi * nearbyint(S(tau / half_period));
  }
  // Φ₋: ∫dτ/(1 + u) = H_{ν₋}(τ)/(1 + u₁); with b + a = 0 (u₁ = −1) steps at τ = 2Kj.
  if (south_) {
    result.south = south_coeff_ * (*south_)(tau, f);
  } else {
    result.south = pi * nearbyint(S((tau - quarter_period_) / half_period));
  }
  return result;
}

template <typename S>
RigidAttitudeTpl<S> HeavyTopExactTpl<S>::at(S t) const {
  if (motion_ == Motion::kPermanentRotation) {
    return {detail::quaternion_multiply<S>(theta0_, detail::exp_quaternion<S>(w0_B_ * t)), w0_B_};
  }
  RigidAttitudeTpl<S> result;
  const Quaternion q_euler = euler_part(t, result.w_B);
  result.theta =
      detail::quaternion_multiply<S>(detail::quaternion_multiply<S>(q_up_, q_euler), q_frame_);
  return result;
}

template <typename S>
typename HeavyTopExactTpl<S>::Quaternion HeavyTopExactTpl<S>::euler_part(S t, Vector3& w_B) const {
  using std::abs;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const S amplitude = v2_ - v1_;
  S one_plus_u = y1_;
  S one_minus_u = z2_;
  S u_minus_u0 = v1_;
  S u_rate(0);
  S phi_plus(0);
  S phi_minus(0);
  if (motion_ == Motion::kSteadyPrecession) {
    // Constant u: Φ± = (b ∓ a) t / (2(1 ∓ u₀)).
    phi_plus = delta_plus_ * t / (S(2) * one_minus_u);
    phi_minus = delta_minus_ * t / (S(2) * one_plus_u);
  } else {
    const S tau = lambda_ * t + tau0_;
    const elliptic::JacobiValuesTpl<S> f = elliptic::jacobi<S>(tau, k_, k_prime_);
    const S sn2 = f.sn * f.sn;
    one_plus_u = y1_ + amplitude * sn2;           // 1 + u = (1 + u₁) + (u₂ − u₁) sn²
    one_minus_u = z2_ + amplitude * f.cn * f.cn;  // 1 − u = (1 − u₂) + (u₂ − u₁) cn²
    u_minus_u0 = v1_ + amplitude * sn2;
    u_rate = S(2) * amplitude * lambda_ * f.sn * f.cn * f.dn;  // u̇
    const PoleIntegrals integrals = pole_integrals(tau, f, one_minus_u);
    phi_plus = integrals.north - north0_;
    phi_minus = integrals.south - south0_;
  }
  const S phi = phi_plus + phi_minus;
  const S psi = psi0_ + (spin_ - a_) * t - phi_plus + phi_minus;

  // b − a u from the anchor (u₀, −1 or +1) with the smallest rounding error.
  const S error_u0 = abs(p_) + abs(S(a_ * u_minus_u0));
  const S error_south = abs(delta_minus_) + abs(a_) * one_plus_u;
  const S error_north = abs(delta_plus_) + abs(a_) * one_minus_u;
  S b_minus_au = p_ - a_ * u_minus_u0;
  if (error_south < std::min(error_u0, error_north)) {
    b_minus_au = delta_minus_ - a_ * one_plus_u;
  } else if (error_north < error_u0) {
    b_minus_au = delta_plus_ + a_ * one_minus_u;
  }
  // Body rate in E: (φ̇ sinϑ sinψ + ϑ̇ cosψ, φ̇ sinϑ cosψ − ϑ̇ sinψ, ω₃) with
  // φ̇ sinϑ = (b − au)/sinϑ and ϑ̇ = −u̇/sinϑ.
  const S sin_theta = sqrt(one_plus_u * one_minus_u);
  const S transverse_phi = b_minus_au / sin_theta;
  const S theta_rate = -u_rate / sin_theta;
  const S sin_psi = sin(psi);
  const S cos_psi = cos(psi);
  w_B = (transverse_phi * sin_psi + theta_rate * cos_psi) * x_B_ +
        (transverse_phi * cos_psi - theta_rate * sin_psi) * y_B_ + spin_ * axis_B_;
  return zxz_euler_parameters<S>(phi, sqrt(S(S(0.5) * one_plus_u)), sqrt(S(S(0.5) * one_minus_u)),
                                 psi);
}

}  // namespace flexref::reference
