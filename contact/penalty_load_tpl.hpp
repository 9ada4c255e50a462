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
#include "core/wear_law.hpp"

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

/// What a point of a wearing contact applies (docs/wear.md): the penalty load, the worn volume
/// rate V̇ of its wear law and the rate ḣ at which its worn surface recedes at the point.
template <typename S>
struct WornPenaltyLoadTpl : PenaltyLoadTpl<S> {
  S volume_rate = S(0);  ///< V̇, m³/s
  S recession = S(0);    ///< ḣ of the surface the point sees, m/s (0 on a frozen geometry)
};

/// The load at a point of a wearing contact with gap `gap`, unit normal n_W along which the load
/// pushes, approach rate u (m/s; −n·v_rel for a contact pair, ∇δ·v on a worn hole) and relative
/// velocity v_rel_W (its slip v_t = v_rel − (n·v_rel) n). The normal force is `force_scale` F_n
/// (1, or |∇δ| on a worn hole) with F_n from the law at δ = −gap and δ̇ = u − ḣ: the surface the
/// point sees recedes at ḣ = β F_n, β = (V̇ per F_n) · `depth_per_volume` (1/A for a pin, the
/// profile's share over the sector area on a hole; 0 when the geometry is frozen), so that a
/// contact that wears at a steady rate is not damped by its own wear
/// (NormalLaw::force_with_recession_in). V̇ per F_n: Archard F k s_n |v_t| / H, work rate
/// F K_w μ s_n s(|v_t|) |v_t|² (|F_t·v_t| with F_t = −μ s_n F_n s(|v_t|) v_t), s_n the
/// force_scale. Dissipation: PenaltyLoadTpl's with δ̇ = u, plus the spring energy the recession
/// releases, F_e ḣ (the callers add it).
template <typename S>
WornPenaltyLoadTpl<S> worn_penalty_load_tpl(const NormalLaw& normal, const FrictionLaw& friction,
                                            const core::WearLaw& wear, const S& gap,
                                            const Eigen::Matrix<S, 3, 1>& n_W,
                                            const S& approach_rate,
                                            const Eigen::Matrix<S, 3, 1>& v_rel_W,
                                            const S& force_scale, const S& depth_per_volume) {
  using std::sqrt;
  WornPenaltyLoadTpl<S> e;
  if (gap >= S(0)) return e;
  e.delta_dot = approach_rate;
  e.v_t_W = v_rel_W - n_W.dot(v_rel_W) * n_W;
  const S slip = sqrt(e.v_t_W.squaredNorm());
  const S slip_factor = friction.mu > 0.0 ? friction.slip_factor_in(slip) : S(0);
  const S volume_per_force =
      wear.kind == core::WearLaw::Kind::kArchard
          ? S(wear.rate_factor()) * force_scale * slip
          : S(wear.rate_factor() * friction.mu) * force_scale * slip_factor * slip * slip;
  const S beta = wear.geometry_frozen ? S(0) : volume_per_force * depth_per_volume;
  e.normal = normal.force_with_recession_in(S(-gap), approach_rate, beta);
  if (friction.mu > 0.0 && e.normal.total > S(0)) {
    e.f_friction_W = -(friction.mu * force_scale * e.normal.total * slip_factor) * e.v_t_W;
  }
  e.volume_rate = volume_per_force * e.normal.total;
  e.recession = beta * e.normal.total;
  return e;
}

}  // namespace flexref::contact
