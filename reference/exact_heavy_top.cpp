#include "reference/exact_heavy_top.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace flexref::reference {

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kPi = std::numbers::pi;

/// c₃x³ + c₂x² + c₁x + c₀, one of the re-expansions of f.
struct Cubic {
  double c0, c1, c2, c3;
  double operator()(double x) const { return ((c3 * x + c2) * x + c1) * x + c0; }
  double derivative(double x) const { return (3.0 * c3 * x + 2.0 * c2) * x + c1; }
};

/// Root of p between `exact_end`, where the sign of p is known exactly (the value there is an
/// expansion coefficient), and `other_end`. If rounding gives p(other_end) the same sign as
/// p(exact_end), the root lies within rounding of other_end and that is returned. Newton with
/// bisection safeguard (Numerical Recipes' rtsafe); converges to relative accuracy ~ε.
double bracketed_root(const Cubic& p, double exact_end, double other_end) {
  const double f_exact = p(exact_end);
  const double f_other = p(other_end);
  if (f_exact == 0.0) return exact_end;
  if (f_other == 0.0 || (f_other > 0.0) == (f_exact > 0.0)) return other_end;
  double negative = f_exact < 0.0 ? exact_end : other_end;  // p(negative) < 0 < p(positive)
  double positive = f_exact < 0.0 ? other_end : exact_end;
  double x = 0.5 * (negative + positive);
  double step_before = std::abs(positive - negative);
  double step = step_before;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const double value = p(x);
    if (value == 0.0) return x;
    (value < 0.0 ? negative : positive) = x;
    const double slope = p.derivative(x);
    const double newton = (slope != 0.0) ? x - value / slope : x;
    const bool inside = (newton - negative) * (newton - positive) < 0.0;
    if (!inside || std::abs(2.0 * value) > std::abs(step_before * slope)) {
      step_before = step;
      step = 0.5 * (positive - negative);
      x = negative + step;
    } else {
      step_before = step;
      step = newton - x;
      x = newton;
    }
    if (std::abs(step) <= 2.0 * kEps * std::abs(x) || negative == positive) return x;
  }
  return x;
}

/// Roots of the quadratic c₂x² + c₁x + c₀ = 0 with real roots, (smaller, larger), without
/// cancellation.
std::pair<double, double> quadratic_roots(double c2, double c1, double c0) {
  const double discriminant = std::max(0.0, c1 * c1 - 4.0 * c2 * c0);
  const double q = -0.5 * (c1 + std::copysign(std::sqrt(discriminant), c1));
  if (q == 0.0) return {0.0, 0.0};
  const double r1 = q / c2;
  const double r2 = c0 / q;
  return {std::min(r1, r2), std::max(r1, r2)};
}

}  // namespace

HeavyTopExact::HeavyTopExact(double mass, double com_distance, const Eigen::Vector3d& axis_B,
                             double j_perp, double j_axial, const Eigen::Vector3d& g_W,
                             const rotation::EulerParameters& theta0, const Eigen::Vector3d& w0_B)
    : theta0_(detail::unit_euler_parameters(theta0, "HeavyTopExact")), w0_B_(w0_B) {
  const auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  if (!positive(mass) || !positive(com_distance) || !positive(j_perp) || !positive(j_axial)) {
    throw std::invalid_argument(
        "HeavyTopExact: mass, centre-of-mass distance and inertias must be finite and > 0");
  }
  if (!axis_B.allFinite() || std::abs(axis_B.norm() - 1.0) > 1e-6) {
    throw std::invalid_argument("HeavyTopExact: symmetry axis must be a unit vector");
  }
  const double gravity = g_W.norm();
  if (!g_W.allFinite() || !(gravity > 0.0)) {
    throw std::invalid_argument("HeavyTopExact: gravity must be finite and non-zero");
  }
  if (!w0_B.allFinite()) {
    throw std::invalid_argument("HeavyTopExact: initial angular velocity must be finite");
  }
  axis_B_ = axis_B.normalized();
  // E frame: x ⊥ e from the body axis least aligned with e, y = e × x.
  Eigen::Index least = 0;
  axis_B_.cwiseAbs().minCoeff(&least);
  x_B_ = axis_B_.cross(Eigen::Vector3d::Unit(least)).normalized();
  y_B_ = axis_B_.cross(x_B_);
  Eigen::Matrix3d frame;  // rows: x, y, e → maps body coordinates to E coordinates
  frame.row(0) = x_B_.transpose();
  frame.row(1) = y_B_.transpose();
  frame.row(2) = axis_B_.transpose();
  q_frame_ = rotation::euler_parameters_from_matrix(frame).normalized();

  const Eigen::Vector3d up_B = rotation::rotation_matrix(theta0_).transpose() * (-g_W / gravity);
  spin_ = axis_B_.dot(w0_B);
  a_ = j_axial * spin_ / j_perp;
  const Eigen::Vector3d w_perp_B = w0_B - spin_ * axis_B_;
  p_ = up_B.dot(w_perp_B);                               // b − a u₀
  const double u_rate0 = up_B.dot(w0_B.cross(axis_B_));  // u̇₀
  const double q0 = w_perp_B.squaredNorm();              // α − β u₀ = |ω⊥|²
  const double beta = 2.0 * mass * gravity * com_distance / j_perp;
  u0_ = up_B.dot(axis_B_);
  const double s0_squared = up_B.cross(axis_B_).squaredNorm();  // sin²ϑ₀ without cancellation
  const double one_plus_u0 = u0_ >= 0.0 ? 1.0 + u0_ : s0_squared / (1.0 - u0_);
  const double one_minus_u0 = u0_ <= 0.0 ? 1.0 - u0_ : s0_squared / (1.0 + u0_);
  delta_minus_ = p_ + a_ * one_plus_u0;  // b + a
  delta_plus_ = p_ - a_ * one_minus_u0;  // b − a
  const Eigen::Vector3d up_E(x_B_.dot(up_B), y_B_.dot(up_B), u0_);
  psi0_ = std::atan2(up_E.x(), up_E.y());

  if (s0_squared == 0.0) {
    if (w_perp_B.isZero(0.0)) {
      motion_ = Motion::kPermanentRotation;  // spinning exactly about the vertical
      return;
    }
    throw std::invalid_argument(
        "HeavyTopExact: initial symmetry axis exactly vertical with transverse angular "
        "velocity; the Euler-angle chart is singular at t = 0");
  }

  // f re-expanded about u₀ (v = u − u₀), −1 (y = 1 + u) and +1 (z = 1 − u); Q(u) = α − βu.
  const double q_south = q0 + beta * one_plus_u0;   // Q(−1)
  const double q_north = q0 - beta * one_minus_u0;  // Q(1)
  const Cubic around_u0{u_rate0 * u_rate0, -beta * s0_squared - 2.0 * u0_ * q0 + 2.0 * a_ * p_,
                        2.0 * u0_ * beta - q0 - a_ * a_, beta};
  const Cubic around_south{-delta_minus_ * delta_minus_, 2.0 * q_south + 2.0 * a_ * delta_minus_,
                           -q_south - 2.0 * beta - a_ * a_, beta};
  const Cubic around_north{-delta_plus_ * delta_plus_, -(-2.0 * q_north + 2.0 * a_ * delta_plus_),
                           -q_north + 2.0 * beta - a_ * a_, -beta};

  // Turning points relative to u₀: f(u₀) = u̇₀² ≥ 0, f(±1) = −(b ± a)² ≤ 0.
  if (around_u0.c0 > 0.0) {
    v1_ = bracketed_root(around_u0, 0.0, -one_plus_u0);
    v2_ = bracketed_root(around_u0, 0.0, one_minus_u0);
  } else if (around_u0.c1 < 0.0) {  // u₀ = u₂: deflate the root v = 0
    v1_ = quadratic_roots(around_u0.c3, around_u0.c2, around_u0.c1).first;
    v2_ = 0.0;
  } else if (around_u0.c1 > 0.0) {  // u₀ = u₁
    v1_ = 0.0;
    v2_ = quadratic_roots(around_u0.c3, around_u0.c2, around_u0.c1).first;
  }  // else: double root at u₀, steady precession
  const double v3 = -around_u0.c2 / around_u0.c3 - v1_ - v2_;
  const double amplitude = v2_ - v1_;  // u₂ − u₁
  // Pole distances from the expansions about the poles (relative accuracy ~ε even when the
  // axis comes within 1e-7 rad of a vertical), bracketed by the midpoint of [u₁, u₂].
  y1_ = (v1_ == 0.0 && around_u0.c0 == 0.0)
            ? one_plus_u0
            : bracketed_root(around_south, 0.0, one_plus_u0 + v1_ + 0.5 * amplitude);
  z2_ = (v2_ == 0.0 && around_u0.c0 == 0.0)
            ? one_minus_u0
            : bracketed_root(around_north, 0.0, one_minus_u0 - v2_ + 0.5 * amplitude);
  y1_ = std::min(y1_, one_plus_u0);
  z2_ = std::min(z2_, one_minus_u0);
  lambda_ = 0.5 * std::sqrt(beta * (v3 - v1_));

  if (amplitude == 0.0) {
    motion_ = Motion::kSteadyPrecession;
  } else {
    motion_ = Motion::kNutation;
    const double k2 = amplitude / (v3 - v1_);
    const double k_prime2 = (v3 - v2_) / (v3 - v1_);
    if (!(k_prime2 > 0.0)) {
      throw std::invalid_argument(
          "HeavyTopExact: motion asymptotic to the upright position (u₂ = u₃ = 1) is not "
          "supported");
    }
    k_ = std::sqrt(k2);
    k_prime_ = std::sqrt(k_prime2);
    quarter_period_ = elliptic::complete_k(k_prime_);
    // sn²τ₀ = (u₀ − u₁)/(u₂ − u₁), cn²τ₀ = (u₂ − u₀)/(u₂ − u₁), sign(sn cn) = sign(u̇₀).
    const double sn0 = std::copysign(std::sqrt(-v1_ / amplitude), u_rate0);
    const double cn0 = std::sqrt(v2_ / amplitude);
    tau0_ = elliptic::incomplete_f(sn0, cn0, k_prime_);
    one_minus_u1_ = one_minus_u0 - v1_;
    // A pole distance that is exactly zero (b ∓ a = 0, or its square underflowed) takes the
    // staircase limit in pole_integrals.
    if (delta_plus_ != 0.0 && z2_ > 0.0) {
      north_.emplace(amplitude / one_minus_u1_, z2_ / one_minus_u1_, k_, k_prime_);
      north_coeff_ = delta_plus_ / (2.0 * lambda_ * one_minus_u1_);
    }
    if (delta_minus_ != 0.0 && y1_ > 0.0) {
      south_.emplace(amplitude / y1_, k_, k_prime_);
      south_coeff_ = delta_minus_ / (2.0 * lambda_ * y1_);
    }
    const elliptic::JacobiValues f0 = elliptic::jacobi(tau0_, k_, k_prime_);
    const PoleIntegrals at_tau0 = pole_integrals(tau0_, f0, z2_ + amplitude * f0.cn * f0.cn);
    north0_ = at_tau0.north;
    south0_ = at_tau0.south;
  }

  // R_up = A(θ₀) Pᵀ R'(0)ᵀ with R'(0) from the same evaluation as at(0).
  Eigen::Vector3d w_B;
  const rotation::EulerParameters q_euler0 = euler_part(0.0, w_B);
  q_up_ = rotation::quaternion_multiply(
              rotation::quaternion_multiply(theta0_, rotation::quaternion_conjugate(q_frame_)),
              rotation::quaternion_conjugate(q_euler0))
              .normalized();
}

double HeavyTopExact::nutation_period() const {
  if (motion_ != Motion::kNutation) return std::numeric_limits<double>::infinity();
  return 2.0 * quarter_period_ / lambda_;
}

HeavyTopExact::PoleIntegrals HeavyTopExact::pole_integrals(double tau,
                                                           const elliptic::JacobiValues& f,
                                                           double one_minus_u) const {
  PoleIntegrals result{0.0, 0.0};
  const double half_period = 2.0 * quarter_period_;
  // Φ₊: ∫dτ/(1 − u) = Π_{n₊}(τ)/(1 − u₁), p = 1 − n₊ sn²τ = (1 − u)/(1 − u₁). With b − a = 0
  // (u₂ = 1) the limit is a staircase: a step π per passage τ = K + 2Kj.
  if (north_) {
    result.north = north_coeff_ * (*north_)(tau, f, one_minus_u / one_minus_u1_);
  } else {
    result.north = kPi * std::nearbyint(tau / half_period);
  }
  // Φ₋: ∫dτ/(1 + u) = H_{ν₋}(τ)/(1 + u₁); with b + a = 0 (u₁ = −1) steps at τ = 2Kj.
  if (south_) {
    result.south = south_coeff_ * (*south_)(tau, f);
  } else {
    result.south = kPi * std::nearbyint((tau - quarter_period_) / half_period);
  }
  return result;
}

RigidAttitude HeavyTopExact::at(double t) const {
  if (motion_ == Motion::kPermanentRotation) {
    return {rotation::quaternion_multiply(theta0_, rotation::exp_quaternion(w0_B_ * t)), w0_B_};
  }
  RigidAttitude result;
  const rotation::EulerParameters q_euler = euler_part(t, result.w_B);
  result.theta =
      rotation::quaternion_multiply(rotation::quaternion_multiply(q_up_, q_euler), q_frame_);
  return result;
}

rotation::EulerParameters HeavyTopExact::euler_part(double t, Eigen::Vector3d& w_B) const {
  const double amplitude = v2_ - v1_;
  double one_plus_u = y1_;
  double one_minus_u = z2_;
  double u_minus_u0 = v1_;
  double u_rate = 0.0;
  double phi_plus = 0.0;
  double phi_minus = 0.0;
  if (motion_ == Motion::kSteadyPrecession) {
    // Constant u: Φ± = (b ∓ a) t / (2(1 ∓ u₀)).
    phi_plus = delta_plus_ * t / (2.0 * one_minus_u);
    phi_minus = delta_minus_ * t / (2.0 * one_plus_u);
  } else {
    const double tau = lambda_ * t + tau0_;
    const elliptic::JacobiValues f = elliptic::jacobi(tau, k_, k_prime_);
    const double sn2 = f.sn * f.sn;
    one_plus_u = y1_ + amplitude * sn2;           // 1 + u = (1 + u₁) + (u₂ − u₁) sn²
    one_minus_u = z2_ + amplitude * f.cn * f.cn;  // 1 − u = (1 − u₂) + (u₂ − u₁) cn²
    u_minus_u0 = v1_ + amplitude * sn2;
    u_rate = 2.0 * amplitude * lambda_ * f.sn * f.cn * f.dn;  // u̇
    const PoleIntegrals integrals = pole_integrals(tau, f, one_minus_u);
    phi_plus = integrals.north - north0_;
    phi_minus = integrals.south - south0_;
  }
  const double phi = phi_plus + phi_minus;
  const double psi = psi0_ + (spin_ - a_) * t - phi_plus + phi_minus;

  // b − a u from the anchor (u₀, −1 or +1) with the smallest rounding error.
  const double error_u0 = std::abs(p_) + std::abs(a_ * u_minus_u0);
  const double error_south = std::abs(delta_minus_) + std::abs(a_) * one_plus_u;
  const double error_north = std::abs(delta_plus_) + std::abs(a_) * one_minus_u;
  double b_minus_au = p_ - a_ * u_minus_u0;
  if (error_south < std::min(error_u0, error_north)) {
    b_minus_au = delta_minus_ - a_ * one_plus_u;
  } else if (error_north < error_u0) {
    b_minus_au = delta_plus_ + a_ * one_minus_u;
  }
  // Body rate in E: (φ̇ sinϑ sinψ + ϑ̇ cosψ, φ̇ sinϑ cosψ − ϑ̇ sinψ, ω₃) with
  // φ̇ sinϑ = (b − au)/sinϑ and ϑ̇ = −u̇/sinϑ.
  const double sin_theta = std::sqrt(one_plus_u * one_minus_u);
  const double transverse_phi = b_minus_au / sin_theta;
  const double theta_rate = -u_rate / sin_theta;
  const double sin_psi = std::sin(psi);
  const double cos_psi = std::cos(psi);
  w_B = (transverse_phi * sin_psi + theta_rate * cos_psi) * x_B_ +
        (transverse_phi * cos_psi - theta_rate * sin_psi) * y_B_ + spin_ * axis_B_;
  return zxz_euler_parameters(phi, std::sqrt(0.5 * one_plus_u), std::sqrt(0.5 * one_minus_u), psi);
}

}  // namespace flexref::reference
