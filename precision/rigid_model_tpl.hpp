#pragma once
/// \file rigid_model_tpl.hpp
/// The rigid-body model of docs/design/model.md written once for any scalar type S (double,
/// long double, boost::multiprecision::float128): free and pivot bodies with Euler parameters,
/// uniform gravity, the applied forces and torques of a scene with their time profiles,
/// point-charge potentials, spherical and revolute bushings (joints), and sphere–plane and
/// sphere–sphere penalty contacts with friction
/// (contact/contact.hpp; the laws are contact/contact_laws.hpp's, evaluated in S). Internal to
/// precision/: the templates are instantiated in rigid_model_tpl.cpp for the three precisions
/// (compile time stays bounded; no other file sees float128).
///
/// State per body (13 values, docs/design/model.md "State"): p_WBr (3), θ_WB = (e0, e) (4),
/// v_WBr (3), ω̄ = w_WB_B (3). Br is Bcm for a free body and the pivot for a pivot body.
/// Equations (model.md eqs. (3)–(6) for a rigid body about Br):
///   ṗ = v;  θ̇ = ½ θ ⊗ (0, ω̄);  m a_Bcm = F_W;  J_Br ω̄̇ + ω̄ × J_Br ω̄ = Γ_Br,B,
/// with a pivot body's p and v fixed (v = 0) and J_Br its inertia about the pivot. A prescribed
/// body (core/prescribed_motion.hpp) keeps its 13 slots, which do not move (ẏ = 0): wherever
/// the model reads them at a time t they are its angle law's pose (Br = Bo fixed on the axis,
/// θ(t) = q(φ(t) a_W) ⊗ θ0, v = 0, ω̄ = φ̇ Aᵀ a_W), and its drive torque is
/// a_W · A (J_Br α̅ + ω̄ × J_Br ω̄ − Γ_Br,B) with the law's α̅ = φ̈ Aᵀ a_W (core::Model::
/// driving_torque).
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "contact/bushing.hpp"
#include "contact/contact_laws.hpp"
#include "core/point_charge_potential.hpp"
#include "core/prescribed_motion.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::precision {

template <typename S>
using Vec3 = std::array<S, 3>;
template <typename S>
using Mat3 = std::array<std::array<S, 3>, 3>;
template <typename S>
using Quat = std::array<S, 4>;  ///< Euler parameters (e0, e1, e2, e3), scalar first

/// Values per body in the state vector.
inline constexpr int kBodyStateSize = 13;

template <typename S>
struct RigidBodyTpl {
  std::string name;
  bool pivot = false;
  bool prescribed = false;
  core::PrescribedRotation law;  ///< a prescribed body's axis and angle law (the double data)
  Vec3<S> axis_W{};              ///< its unit axis in S
  Quat<S> theta0{};              ///< its initial attitude, normalized in S
  S mass = 0;
  Vec3<S> p_BoBr_B{};  ///< Br from the frame origin
  Vec3<S> c_B{};       ///< Bcm relative to Br (zero for a free body)
  Mat3<S> J_Br_B{};    ///< inertia about Br, body frame
  Mat3<S> J_Br_B_inv{};
  std::vector<std::string> point_names;
  std::vector<Vec3<S>> p_BrP_B;             ///< tracked points relative to Br
  std::array<S, kBodyStateSize> initial{};  ///< the initial state (θ normalized in S)
};

template <typename S>
struct AppliedLoadTpl {
  bool torque = false;
  int body = 0;
  Vec3<S> value{};
  bool world_frame = true;
  Vec3<S> p_BrP_B{};  ///< point of application relative to Br (forces)
  core::TimeProfile profile = core::TimeProfile::constant();
  bool tracks_work = false;  ///< a force: its power enters W_a when the model tracks W_a
};

/// A sphere–plane or sphere–sphere pair of contact/contact.hpp on rigid parts, the sphere
/// centres relative to Br, with its element's laws (the double model's parameters).
template <typename S>
struct ContactPairTpl {
  bool sphere_sphere = false;
  int body_a = -1;  ///< sphere a's body; −1 for the ground plane
  Vec3<S> p_BrCa_B{};
  S radius_a = S(0);
  int body_b = 0;  ///< the sphere pushed along +n
  Vec3<S> p_BrCb_B{};
  S radius_b = S(0);
  Vec3<S> p_WQ{};  ///< a point of the plane
  Vec3<S> n_W{};   ///< unit plane normal (normalized in double by ContactPair, as there)
  contact::NormalLaw normal;
  contact::FrictionLaw friction;
};

/// The model in precision S, built from a scene (the scene's double values are the data: the
/// model solved is exactly the one the double references solve).
template <typename S>
class RigidModelTpl {
 public:
  /// Throws std::invalid_argument naming the first part of the scene this model does not
  /// carry (flexible or prescribed bodies, gap supports).
  explicit RigidModelTpl(const scene::SceneSpec& spec);

  int num_bodies() const { return static_cast<int>(bodies_.size()); }
  /// 13 per body, then the integrals of the double model (core::Model::extra_integral_count)
  /// when it dissipates: W_d, W_a of harmonic forces (when tracked), each wear channel's work.
  int state_size() const { return kBodyStateSize * num_bodies() + integral_count_; }
  /// The double model's studies::trajectory_columns ("t" first): output_row fills the rest.
  const std::vector<std::string>& columns() const { return columns_; }
  int wear_channel_count() const { return static_cast<int>(wear_channels_.size()); }
  /// The wear channel of a contact pair, −1 for a pair of an unnamed contact.
  int wear_channel_of_pair(int pair) const { return pair_channel_[static_cast<std::size_t>(pair)]; }
  const std::vector<RigidBodyTpl<S>>& bodies() const { return bodies_; }
  /// Times in (t0, t_end] where a load profile switches, and the end of a spin-up law (φ⁗
  /// jumps there: φ̈ = (Ω/T)(1 − cos 2πt/T) before, 0 after): integrators stop on them.
  std::vector<double> discontinuities() const;

  std::vector<S> initial_state() const;
  /// ẏ = f(t, y) on the load branch active at t_segment (core/time_profile.hpp). With
  /// `switching`, also switching_functions(t, y) from the same evaluation's contact geometry.
  /// Uses the model's scratch when it has prescribed bodies: one evaluation at a time.
  void derivative(const std::vector<S>& y, std::vector<S>& dydt, S t, double t_segment,
                  std::vector<S>* switching = nullptr) const;
  /// Kinetic + gravitational + potentials' + contact potential energy (the `energy` column) at
  /// a state whose prescribed bodies' slots hold their pose (with_prescribed).
  S energy(const std::vector<S>& y) const;
  /// Two per contact pair, in order: the gap g (the pair pushes while g < 0; its sign change is
  /// an onset or a release) and the unclamped law's value (NormalLaw::clamp_function; its sign
  /// change inside the contact is where the clamp F ≥ 0 starts or stops acting).
  int switching_function_count() const { return 2 * static_cast<int>(contacts_.size()); }
  void switching_functions(S t, const std::vector<S>& y, std::vector<S>& values) const;
  /// The trajectory_columns row at (t, y) after `t`: per body p_WBo, θ, v_WBo, ω̄, tracked
  /// points (and a prescribed body's drive torque); the energy; when the model dissipates W_d,
  /// (W_a), E − E(0) + W_d − W_a; per wear channel Σ F_n, the slip speed of its most loaded
  /// pair, its wear work and `impacts` (the caller's onset counts, one per channel; empty: none
  /// yet).
  std::vector<S> output_row(S t, const std::vector<S>& y,
                            const std::vector<double>& impacts = {}) const;
  /// y with every prescribed body's slots set to its law's pose at t (y itself when there is
  /// none; else the model's scratch, valid until the next call).
  const std::vector<S>& with_prescribed(S t, const std::vector<S>& y) const;

 private:
  std::vector<RigidBodyTpl<S>> bodies_;
  std::vector<AppliedLoadTpl<S>> loads_;
  std::vector<ContactPairTpl<S>> contacts_;
  /// Point-charge potentials (core/point_charge_potential.hpp), whose field the double
  /// class's unit_field evaluates in S; each charge's point relative to its body's Br.
  std::vector<core::PointChargePotential> potentials_;
  std::vector<std::vector<Vec3<S>>> charge_points_;
  /// A bushing end in S: the element's point from Bo (body) or in world (ground), and its axis
  /// as a unit vector of S (core/unit_vector_tpl.hpp: the damping's projection
  /// ω − ½(a (a·ω) + b (b·ω)) assumes |a| = |b| = 1), converted once.
  struct JointEndTpl {
    int body = contact::kGround;
    Vec3<S> point{};
    Vec3<S> axis{};
  };
  /// Spherical and revolute bushings (contact/bushing.hpp; their equations are
  /// contact/bushing_tpl.hpp's, evaluated in S).
  struct JointTpl {
    bool revolute = false;
    JointEndTpl a;
    JointEndTpl b;
    contact::BushingParameters parameters;
  };
  std::vector<JointTpl> joints_;
  Vec3<S> g_W_{};
  std::vector<std::string> columns_;
  bool dissipates_ = false;
  bool applied_work_ = false;  ///< a harmonic force's work W_a is tracked (AppliedForce's rule)
  int integral_count_ = 0;
  std::vector<std::string> wear_channels_;
  std::vector<int> pair_channel_;
  std::vector<double> discontinuities_;
  bool has_prescribed_ = false;
  mutable std::vector<S> y_prescribed_;  ///< with_prescribed's scratch
  mutable std::vector<S> drive_torque_;  ///< per body, of the last derivative (prescribed only)
  S energy0_ = S(0);
  void switching_values(const std::vector<S>& y, std::vector<S>& values) const;
  /// Writes a prescribed body's 13 slots at t: p_WBr (its initial one), θ, v = 0, ω̄.
  static void prescribed_pose(const RigidBodyTpl<S>& b, S t, S* slots);

  /// Geometry (contact/contact_point_tpl.hpp) and relative motion of a pair.
  struct PairState {
    S gap;
    Vec3<S> n_W;
    Vec3<S> p_WP;
    Vec3<S> v_rel_W;  ///< b's material point at P minus a's
  };
  PairState pair_state(const ContactPairTpl<S>& c, const std::vector<S>& y, const Mat3<S>* A) const;
  /// What a pair does at a state: its force on b at P and the powers it dissipates.
  struct PairLoad {
    S normal = S(0);  ///< F_n
    S slip_speed = S(0);
    Vec3<S> f_W{};              ///< F_n n + F_t on b
    S dissipated_power = S(0);  ///< F_nc δ̇ − F_t·v_t ≥ 0
    S wear_power = S(0);        ///< |F_t·v_t|
  };
  PairLoad pair_load(const ContactPairTpl<S>& c, const PairState& s) const;
};

// Small generic vector algebra (Eigen's fixed-size types are not needed for 3-vectors).
template <typename S>
Vec3<S> cross(const Vec3<S>& a, const Vec3<S>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <typename S>
S dot(const Vec3<S>& a, const Vec3<S>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <typename S>
Vec3<S> multiply(const Mat3<S>& m, const Vec3<S>& v) {
  return {dot(m[0], v), dot(m[1], v), dot(m[2], v)};
}
template <typename S>
Vec3<S> multiply_transposed(const Mat3<S>& m, const Vec3<S>& v) {
  return {m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
          m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
          m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2]};
}
/// A(θ) for Euler parameters of any norm: A(θ/|θ|) (model.md eq. (1)).
template <typename S>
Mat3<S> rotation_matrix(const Quat<S>& q) {
  const S n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  const S s = S(2) / n2;
  const S e0 = q[0], e1 = q[1], e2 = q[2], e3 = q[3];
  return {{{S(1) - s * (e2 * e2 + e3 * e3), s * (e1 * e2 - e0 * e3), s * (e1 * e3 + e0 * e2)},
           {s * (e1 * e2 + e0 * e3), S(1) - s * (e1 * e1 + e3 * e3), s * (e2 * e3 - e0 * e1)},
           {s * (e1 * e3 - e0 * e2), s * (e2 * e3 + e0 * e1), S(1) - s * (e1 * e1 + e2 * e2)}}};
}
template <typename S>
Quat<S> quaternion_multiply(const Quat<S>& a, const Quat<S>& b) {
  return {a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
          a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
          a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
          a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]};
}
/// The geodesic angle between two attitudes, 2 atan2(|vec(a* ⊗ b)|, |scal(a* ⊗ b)|): accurate
/// to the precision's ε also for tiny angles (no acos).
template <typename S>
S geodesic_angle(const Quat<S>& a, const Quat<S>& b) {
  using std::abs;
  using std::atan2;
  using std::sqrt;
  const Quat<S> d = quaternion_multiply(Quat<S>{a[0], -a[1], -a[2], -a[3]}, b);
  return S(2) * atan2(sqrt(d[1] * d[1] + d[2] * d[2] + d[3] * d[3]), abs(d[0]));
}

}  // namespace flexref::precision
