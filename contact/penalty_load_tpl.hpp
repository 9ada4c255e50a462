#pragma once
/// \file penalty_load_tpl.hpp
/// The penalty load at one contact point (docs/contact.md), written once, generic in the scalar
/// type S: the contacts (contact.hpp) and gap supports (gap_support.hpp) call it in every
/// precision (double, long double, float128). With the gap
/// g < 0, the unit normal n along which the load pushes body b, and the relative velocity
/// v_rel of b's material point at the contact point minus the other side's:
///   δ = −g,  δ̇ = −n·v_rel,  F_n = NormalLaw(δ, δ̇),  v_t = v_rel − (n·v_rel) n,
///   F_t = −μ F_n s(|v_t|) v_t   (FrictionLaw's regularized slip factor s),
/// the load on b is F_n n + F_t, and it dissipates F_nc δ̇ − F_t·v_t ≥ 0.
#include <Eigen/Core>
#include <cmath>

#include "contact/contact_laws.hpp"

namespace flexref::contact {

/// What a contact point applies at a state; all zero while g ≥ 0.
template <typename S>
struct PenaltyLoadTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  S delta_dot = S(0);                      ///< −n·v_rel
  Vector3 v_t_W = Vector3::Zero();         ///< tangential slip velocity
  NormalForceTpl<S> normal;                ///< F_n and its elastic and damping parts
  Vector3 f_friction_W = Vector3::Zero();  ///< F_t on b
  /// F_nc δ̇ − F_t·v_t ≥ 0. The normal part: F_nc = c δ̇ or α k δⁿ δ̇ has the sign of δ̇; while
  /// the clamp F_n ≥ 0 acts, F_nc = −F_e < 0 with δ̇ < 0, and the spring's energy F_e δ̇ that
  /// still changes is dissipated. The friction part: μ F_n s(|v_t|) |v_t|².
  S dissipated_power() const { return normal.dissipative() * delta_dot - f_friction_W.dot(v_t_W); }
};

/// The load at a point with gap `gap`, normal n_W and relative velocity v_rel_W (zero when
/// gap ≥ 0: no force, nothing dissipated).
template <typename S>
PenaltyLoadTpl<S> penalty_load_tpl(const NormalLaw& normal, const FrictionLaw& friction,
                                   const S& gap, const Eigen::Matrix<S, 3, 1>& n_W,
                                   const Eigen::Matrix<S, 3, 1>& v_rel_W) {
  PenaltyLoadTpl<S> e;
  if (gap >= S(0)) return e;
  const S v_n = n_W.dot(v_rel_W);
  e.delta_dot = -v_n;
  e.v_t_W = v_rel_W - v_n * n_W;
  e.normal = normal.force_in(S(-gap), e.delta_dot);
  if (friction.mu > 0.0 && e.normal.total > S(0)) {
    using std::sqrt;
    e.f_friction_W =
        -(friction.mu * e.normal.total * friction.slip_factor_in(S(sqrt(e.v_t_W.squaredNorm())))) *
        e.v_t_W;
  }
  return e;
}

}  // namespace flexref::contact
