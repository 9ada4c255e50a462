#pragma once
/// \file constraint_projection_tpl.hpp
/// Measures of a configuration's distance from the joints and the Newton projection onto them,
/// in any scalar type S (docs/joints.md, "Initial state"): the joints' length scale, the
/// relative position violation, each joint's violations, and the projection of the positions
/// onto Φ(q, t) = 0 in the mass metric.
#include <Eigen/Core>
#include <array>
#include <cmath>
#include <vector>

#include "core/constrained_solve_tpl.hpp"

namespace flexref::core {

/// The joints' length scale ℓ: the largest arm from a body's Br to a joint point, |∂(u·v_P)/∂ω̄|
/// over the length rows of J (1 when every joint sits at its bodies' reference points). Relative
/// violations divide a length row's Φ by it.
template <typename S>
S joint_length_scale(const ConstraintEquationsTpl<S>& equations, const VelocityLayout&,
                     const ConstraintJacobianTpl<S>& J) {
  S scale = S(0);
  for (int r = 0; r < J.rows(); ++r) {
    if (!equations.is_length_row(r)) continue;
    for (int k = 0; k < 2; ++k) {
      if (J.slot(r, k).body < 0) continue;
      const S arm = J.values(r, k).template segment<3>(3).norm();
      if (arm > scale) scale = arm;
    }
  }
  return scale > S(0) ? scale : S(1);
}

/// The largest relative position violation of the rows: |Φ_r| / ℓ for a length row, |Φ_r| for a
/// rotation row (the sine of an angle).
template <typename S>
S relative_position_violation(const ConstraintEquationsTpl<S>& equations,
                              const Eigen::Matrix<S, Eigen::Dynamic, 1>& phi,
                              const S& length_scale) {
  using std::abs;
  S worst = S(0);
  for (Eigen::Index r = 0; r < phi.size(); ++r) {
    const S v = abs(phi(r)) / (equations.is_length_row(static_cast<int>(r)) ? length_scale : S(1));
    if (v > worst) worst = v;
  }
  return worst;
}

/// Newton projection of the positions onto Φ(q, t) = 0 in the mass metric (Hairer, Lubich &
/// Wanner IV.4, Newton with the Jacobian of each iterate). On entry s is factored at the
/// positions; factor_at() evaluates the rows at the current positions into s.rows and factors
/// them (factor_constraints), violation() is the relative position violation of s.rows,
/// apply_increment(δ) adds δ = s.x, the stacked (δp_Br, δφ_B, δq_f), to the positions. Stops
/// when the violation is at most `converged` (a few ε of S: the round-off of Φ itself) or after
/// 20 iterations (far more than quadratic convergence needs from an accepted violation; a far
/// start may first grow before it converges, so a growing iterate does not stop it). s is left
/// factored at the final positions.
template <typename S, typename FactorAt, typename Violation, typename ApplyIncrement>
void project_positions(FactorAt&& factor_at, Violation&& violation,
                       ApplyIncrement&& apply_increment, const S& converged,
                       ConstraintSolveTpl<S>& s) {
  S current = violation();
  for (int iteration = 0; iteration < 20 && current > converged; ++iteration) {
    constraint_correction<S>(s.rows.phi, s);
    apply_increment(s.x);
    factor_at();
    current = violation();
  }
}

/// Per joint, the largest |Φ| of its rows and the largest |J v + Φ_t| of its velocity rows, from
/// the rows and the stacked velocities at a state.
template <typename S>
std::vector<std::array<S, 2>> joint_violations(const ConstraintEquationsTpl<S>& equations,
                                               const ConstraintRowsTpl<S>& rows,
                                               const Eigen::Matrix<S, Eigen::Dynamic, 1>& v) {
  using std::abs;
  Eigen::Matrix<S, Eigen::Dynamic, 1> rate(rows.phi.size());
  rows.jacobian.multiply(v, rate);
  rate += rows.phi_t;
  std::vector<std::array<S, 2>> out(static_cast<std::size_t>(equations.joint_count()),
                                    {S(0), S(0)});
  for (Eigen::Index r = 0; r < rows.phi.size(); ++r) {
    auto& j = out[static_cast<std::size_t>(equations.joint_of_row(static_cast<int>(r)))];
    if (abs(rows.phi(r)) > j[0]) j[0] = abs(rows.phi(r));
    if (abs(rate(r)) > j[1]) j[1] = abs(rate(r));
  }
  return out;
}

}  // namespace flexref::core
