#include "precision/rigid_model_tpl.hpp"

#include <algorithm>
#include <boost/math/constants/constants.hpp>
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/float128.hpp>
#include <stdexcept>

#include "contact/bushing_tpl.hpp"
#include "contact/contact.hpp"
#include "contact/contact_point_tpl.hpp"
#include "contact/penalty_load_tpl.hpp"
#include "core/unit_vector_tpl.hpp"
#include "precision/refusal.hpp"
#include "scene/build_model.hpp"
#include "studies/trajectory_table.hpp"

namespace flexref::precision {
namespace {

template <typename S>
Vec3<S> to_s(const Eigen::Vector3d& v) {
  return {S(v.x()), S(v.y()), S(v.z())};
}

template <typename S>
Mat3<S> inverse(const Mat3<S>& m) {
  // Cofactors over the determinant (the inertia is symmetric positive definite: Body checks it
  // in double, and the scene's values are the same here).
  const S c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const S c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  const S c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const S det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  const S r = S(1) / det;
  return {{{c00 * r, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * r,
            (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * r},
           {c01 * r, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * r,
            (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * r},
           {c02 * r, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * r,
            (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * r}}};
}

template <typename S>
Quat<S> quat_at(const std::vector<S>& y, std::size_t o) {
  return {y[o + 3], y[o + 4], y[o + 5], y[o + 6]};
}

template <typename S>
using EigenVector3 = Eigen::Matrix<S, 3, 1>;

template <typename S>
EigenVector3<S> eigen(const Vec3<S>& v) {
  return EigenVector3<S>(v[0], v[1], v[2]);
}

/// A bushing end's pose and velocity in S (contact/bushing_tpl.hpp): a body's attachment point
/// p_Br + A (P − Bo − p_BoBr), its Br, v_Br, ω = A ω̄ and axis A ā; the ground's as given.
template <typename S, typename End>
contact::bushing::EndMotion<S> end_motion(const End& end, const RigidBodyTpl<S>* body,
                                          const std::vector<S>& y, const Mat3<S>& A,
                                          std::size_t o) {
  contact::bushing::EndMotion<S> m;
  const Vec3<S>& point = end.point;
  const Vec3<S>& axis = end.axis;
  if (body == nullptr) {
    m.p_WP = eigen(point);
    m.axis_W = eigen(axis);
    return m;
  }
  m.ground = false;
  const Vec3<S> r = multiply(A, Vec3<S>{point[0] - body->p_BoBr_B[0], point[1] - body->p_BoBr_B[1],
                                        point[2] - body->p_BoBr_B[2]});
  m.p_WBr = EigenVector3<S>(y[o], y[o + 1], y[o + 2]);
  m.p_WP = m.p_WBr + eigen(r);
  m.v_WBr = EigenVector3<S>(y[o + 7], y[o + 8], y[o + 9]);
  m.w_WB_W = eigen(multiply(A, Vec3<S>{y[o + 10], y[o + 11], y[o + 12]}));
  m.axis_W = eigen(multiply(A, axis));
  return m;
}

}  // namespace

template <typename S>
RigidModelTpl<S>::RigidModelTpl(const scene::SceneSpec& spec) : g_W_(to_s<S>(spec.g_W)) {
  const auto refuse = [&](const scene::SpecSource& source, const std::string& what) {
    refuse_part(spec, source, what,
                "yet (docs/precision.md: rigid free, pivot and prescribed bodies, gravity, applied "
                "forces and torques, point-charge potentials, bushings, sphere contacts)");
  };
  for (const scene::ContactSpec& c : spec.contacts) {
    if (c.gap) refuse(c.source, "a gap support");
  }
  for (const scene::BodySpec& b : spec.bodies) {
    const core::RigidBodyDescription& d = b.description;
    if (d.flexible) refuse(b.source, "a flexible body");
    RigidBodyTpl<S> body;
    body.name = d.name;
    body.pivot = d.motion == core::MotionKind::kPivot;
    body.prescribed = d.motion == core::MotionKind::kPrescribed;
    body.law = d.prescribed;
    const EigenVector3<S> axis = core::unit_vector_in<S>(d.prescribed.axis_W);
    body.axis_W = {axis(0), axis(1), axis(2)};
    body.mass = S(d.mass);
    const Vec3<S> p_BoBcm_B = to_s<S>(d.p_BoBcm_B);
    // Br: Bcm (free), the pivot, or Bo, fixed on the axis (prescribed; core/body.cpp).
    body.p_BoBr_B = body.pivot ? to_s<S>(d.p_BoPivot_B) : body.prescribed ? Vec3<S>{} : p_BoBcm_B;
    for (std::size_t i = 0; i < 3; ++i) body.c_B[i] = p_BoBcm_B[i] - body.p_BoBr_B[i];
    for (std::size_t i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < 3; ++j)
        body.J_Br_B[i][j] =
            S(d.I_Bcm_B(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
    }
    if (body.pivot || body.prescribed) {  // parallel axes: J_Br = J_Bcm + m (|c|² I − c cᵀ)
      const S c2 = dot(body.c_B, body.c_B);
      for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
          body.J_Br_B[i][j] += body.mass * ((i == j ? c2 : S(0)) - body.c_B[i] * body.c_B[j]);
        }
      }
    }
    // A prescribed body's J_Br is never inverted (its α̅ is the law's).
    if (!body.prescribed) body.J_Br_B_inv = inverse(body.J_Br_B);
    {
      using std::sqrt;
      const core::BodyInitialState& init = d.initial;
      Quat<S> q{S(init.theta_WB(0)), S(init.theta_WB(1)), S(init.theta_WB(2)), S(init.theta_WB(3))};
      const S norm = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      for (S& x : q) x /= norm;
      body.theta0 = q;
      const Mat3<S> A = rotation_matrix(q);
      const Vec3<S> w = to_s<S>(init.w_WB_B);
      const Vec3<S> r_W = multiply(A, body.p_BoBr_B);
      const Vec3<S> u_W = multiply(A, cross(w, body.p_BoBr_B));
      const Vec3<S> p0 = to_s<S>(init.p_WBo);
      const Vec3<S> v0 = to_s<S>(init.v_WBo);
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t uk = k;
        body.initial[uk] = p0[k] + r_W[k];  // p_WBr = p_WBo + A p_BoBr
        body.initial[7 + uk] = body.pivot || body.prescribed
                                   ? S(0)
                                   : v0[k] + u_W[k];  // v_WBr = v_WBo + A (ω̄ × p_BoBr)
        body.initial[10 + uk] = w[k];
      }
      for (std::size_t k = 0; k < 4; ++k) body.initial[3 + k] = q[k];
    }
    for (const core::TrackedPoint& p : d.points) {
      body.point_names.push_back(p.name);
      const Vec3<S> r = to_s<S>(p.p_BoP_B);
      body.p_BrP_B.push_back(
          {r[0] - body.p_BoBr_B[0], r[1] - body.p_BoBr_B[1], r[2] - body.p_BoBr_B[2]});
    }
    bodies_.push_back(std::move(body));
  }
  for (const scene::LoadSpec& l : spec.loads) {
    if (l.node >= 0) refuse(l.source, "a load at a node");
    AppliedLoadTpl<S> load;
    load.torque = l.torque;
    load.body = l.body;
    load.value = to_s<S>(l.value);
    load.world_frame = l.frame == core::LoadFrame::kWorld;
    const Vec3<S> r = to_s<S>(l.p_BoP_B);
    const Vec3<S>& o = bodies_.at(static_cast<std::size_t>(l.body)).p_BoBr_B;
    load.p_BrP_B = {r[0] - o[0], r[1] - o[1], r[2] - o[2]};
    load.profile = l.profile;
    // W_a, once a harmonic force makes the model track it, is the work of every applied force
    // (core::Model::integral_rates sums AppliedForce::applied_power over all of them).
    load.tracks_work = !l.torque;
    loads_.push_back(load);
  }
  for (const scene::PotentialSpec& p : spec.potentials) {
    potentials_.emplace_back(p.alpha, p.beta, p.p_WM, p.charges);
    std::vector<Vec3<S>> points;
    for (const core::PointChargePotential::Charge& c : p.charges) {
      const Vec3<S> r = to_s<S>(c.p_BoP_B);
      const Vec3<S>& o = bodies_.at(static_cast<std::size_t>(c.body)).p_BoBr_B;
      points.push_back({r[0] - o[0], r[1] - o[1], r[2] - o[2]});
    }
    charge_points_.push_back(std::move(points));
  }
  // The double model of the same spec gives the outputs (columns, integrals) and the contact
  // laws as it builds them (the default effective mass, the Hunt–Crossley α from the
  // restitution): the same parameters, so every precision solves one model.
  const core::Model built = scene::build_model(spec);
  columns_ = studies::trajectory_columns(built);
  dissipates_ = built.dissipates();
  applied_work_ = dissipates_ && built.tracks_applied_work();
  wear_channels_ = built.wear_channel_names();
  integral_count_ = dissipates_ ? 1 + built.extra_integral_count() : 0;
  const auto end_in_s = [](const contact::BushingEnd& end) {
    const EigenVector3<S> axis = core::unit_vector_in<S>(end.axis);
    return JointEndTpl{end.body, to_s<S>(end.point), {axis(0), axis(1), axis(2)}};
  };
  for (const auto& element : built.elements()) {
    if (const auto* j = dynamic_cast<const contact::SphericalBushing*>(element.get())) {
      joints_.push_back({false, end_in_s(j->end_a()), end_in_s(j->end_b()), j->parameters()});
    } else if (const auto* r = dynamic_cast<const contact::RevoluteBushing*>(element.get())) {
      joints_.push_back({true, end_in_s(r->end_a()), end_in_s(r->end_b()), r->parameters()});
    }
  }
  {
    for (const auto& element : built.elements()) {
      const auto* e = dynamic_cast<const contact::ContactElement*>(element.get());
      if (e == nullptr) continue;
      int channel = -1;
      if (e->wear_channel_count() > 0) {
        channel = static_cast<int>(
            std::find(wear_channels_.begin(), wear_channels_.end(), e->wear_channel_name()) -
            wear_channels_.begin());
      }
      for (const contact::ContactPair& p : e->pairs()) {
        pair_channel_.push_back(channel);
        ContactPairTpl<S> c;
        c.sphere_sphere = p.kind == contact::ContactPair::Kind::kSphereSphere;
        c.body_a = p.body_a;
        c.body_b = p.body_b;
        c.radius_a = S(p.radius_a);
        c.radius_b = S(p.radius_b);
        const Vec3<S>& ob = bodies_.at(static_cast<std::size_t>(p.body_b)).p_BoBr_B;
        const Vec3<S> cb = to_s<S>(p.p_BoCb_B);
        c.p_BrCb_B = {cb[0] - ob[0], cb[1] - ob[1], cb[2] - ob[2]};
        if (p.body_a >= 0) {
          const Vec3<S>& oa = bodies_.at(static_cast<std::size_t>(p.body_a)).p_BoBr_B;
          const Vec3<S> ca = to_s<S>(p.p_BoCa_B);
          c.p_BrCa_B = {ca[0] - oa[0], ca[1] - oa[1], ca[2] - oa[2]};
        }
        c.p_WQ = to_s<S>(p.p_WQ);
        const EigenVector3<S> n = core::unit_vector_in<S>(p.n_W);
        c.n_W = {n(0), n(1), n(2)};
        c.normal = e->normal_law();
        c.friction = e->friction_law();
        contacts_.push_back(c);
      }
    }
  }
  for (const AppliedLoadTpl<S>& l : loads_) l.profile.append_discontinuities(discontinuities_);
  for (RigidBodyTpl<S>& b : bodies_) {
    if (!b.prescribed) continue;
    has_prescribed_ = true;
    prescribed_pose(b, S(0), b.initial.data());  // the law's pose and rate at t = 0
    if (b.law.law.kind == core::AngleLaw::Kind::kSpinUp) {
      discontinuities_.push_back(b.law.law.spin_up_time);
    }
  }
  std::sort(discontinuities_.begin(), discontinuities_.end());
  discontinuities_.erase(std::unique(discontinuities_.begin(), discontinuities_.end()),
                         discontinuities_.end());
  drive_torque_.assign(bodies_.size(), S(0));
  energy0_ = energy(initial_state());
}

template <typename S>
void RigidModelTpl<S>::prescribed_pose(const RigidBodyTpl<S>& b, S t, S* slots) {
  // core::Model::apply_prescribed_motion in S: p_WBr = p_WBo (Br = Bo), v = 0,
  // θ = q(φ a_W) ⊗ θ0, ω̄ = φ̇ Aᵀ a_W (core/prescribed_motion.hpp).
  using std::cos;
  using std::sin;
  const S phi = b.law.law.template angle_in<S>(t);
  const S half_sin = sin(S(0.5) * phi);
  const Quat<S> q_axis{cos(S(0.5) * phi), half_sin * b.axis_W[0], half_sin * b.axis_W[1],
                       half_sin * b.axis_W[2]};
  const Quat<S> theta = quaternion_multiply(q_axis, b.theta0);
  const Vec3<S> axis_B = multiply_transposed(rotation_matrix(theta), b.axis_W);
  const S rate = b.law.law.template angular_rate_in<S>(t);
  for (std::size_t k = 0; k < 4; ++k) slots[3 + k] = theta[k];
  for (std::size_t k = 0; k < 3; ++k) {
    slots[k] = b.initial[k];  // p_WBr = p_WBo, fixed
    slots[7 + k] = S(0);
    slots[10 + k] = rate * axis_B[k];
  }
}

template <typename S>
const std::vector<S>& RigidModelTpl<S>::with_prescribed(S t, const std::vector<S>& y) const {
  if (!has_prescribed_) return y;
  if (&y != &y_prescribed_) y_prescribed_.assign(y.begin(), y.end());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (bodies_[i].prescribed) prescribed_pose(bodies_[i], t, &y_prescribed_[kBodyStateSize * i]);
  }
  return y_prescribed_;
}

template <typename S>
typename RigidModelTpl<S>::PairLoad RigidModelTpl<S>::pair_load(const ContactPairTpl<S>& c,
                                                                const PairState& s) const {
  // contact/penalty_load_tpl.hpp in S (ContactElement::evaluate's), and the wear channel's power.
  using std::abs;
  using std::sqrt;
  PairLoad load;
  const contact::PenaltyLoadTpl<S> e =
      contact::penalty_load_tpl<S>(c.normal, c.friction, s.gap, eigen(s.n_W), eigen(s.v_rel_W));
  load.dissipated_power = e.dissipated_power();
  if (!(e.normal.total > S(0))) return load;
  load.normal = e.normal.total;
  load.slip_speed = sqrt(e.v_t_W.squaredNorm());
  const EigenVector3<S> f_W = e.normal.total * eigen(s.n_W) + e.f_friction_W;
  load.f_W = {f_W(0), f_W(1), f_W(2)};
  load.wear_power = abs(e.f_friction_W.dot(e.v_t_W));
  return load;
}

template <typename S>
typename RigidModelTpl<S>::PairState RigidModelTpl<S>::pair_state(const ContactPairTpl<S>& c,
                                                                  const std::vector<S>& y,
                                                                  const Mat3<S>* A) const {
  // Centre, and velocity of the material point at P: v_Br + (A ω̄) × (P − p_WBr).
  const auto centre = [&](int body, const Vec3<S>& p_BrC_B) {
    const std::size_t o = kBodyStateSize * static_cast<std::size_t>(body);
    const Vec3<S> r = multiply(A[body], p_BrC_B);
    return EigenVector3<S>(y[o] + r[0], y[o + 1] + r[1], y[o + 2] + r[2]);
  };
  const auto velocity = [&](int body, const EigenVector3<S>& p_WP) {
    const std::size_t o = kBodyStateSize * static_cast<std::size_t>(body);
    const Vec3<S> w_W = multiply(A[body], Vec3<S>{y[o + 10], y[o + 11], y[o + 12]});
    const Vec3<S> u = cross(w_W, Vec3<S>{p_WP[0] - y[o], p_WP[1] - y[o + 1], p_WP[2] - y[o + 2]});
    return EigenVector3<S>(y[o + 7] + u[0], y[o + 8] + u[1], y[o + 9] + u[2]);
  };
  // The geometry of contact/contact_point_tpl.hpp in S (ContactElement's contact_point).
  const EigenVector3<S> cb = centre(c.body_b, c.p_BrCb_B);
  const contact::ContactPointTpl<S> point =
      c.sphere_sphere
          ? contact::sphere_sphere_point_tpl<S>(centre(c.body_a, c.p_BrCa_B), c.radius_a, cb,
                                                c.radius_b)
          : contact::sphere_plane_point_tpl<S>(cb, c.radius_b, eigen(c.p_WQ), eigen(c.n_W));
  EigenVector3<S> v_rel = velocity(c.body_b, point.p_WP);
  if (c.sphere_sphere) v_rel -= velocity(c.body_a, point.p_WP);
  PairState s;
  s.gap = point.gap;
  s.n_W = {point.n_W(0), point.n_W(1), point.n_W(2)};
  s.p_WP = {point.p_WP(0), point.p_WP(1), point.p_WP(2)};
  s.v_rel_W = {v_rel(0), v_rel(1), v_rel(2)};
  return s;
}

template <typename S>
void RigidModelTpl<S>::switching_functions(S t, const std::vector<S>& y,
                                           std::vector<S>& values) const {
  switching_values(with_prescribed(t, y), values);
}

template <typename S>
void RigidModelTpl<S>::switching_values(const std::vector<S>& y, std::vector<S>& values) const {
  std::array<Mat3<S>, 8> small_A{};
  std::vector<Mat3<S>> big_A;
  Mat3<S>* A = small_A.data();
  if (bodies_.size() > small_A.size()) {
    big_A.assign(bodies_.size(), Mat3<S>{});
    A = big_A.data();
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    A[i] = rotation_matrix(quat_at(y, kBodyStateSize * i));
  }
  for (std::size_t p = 0; p < contacts_.size(); ++p) {
    const PairState s = pair_state(contacts_[p], y, A);
    values[2 * p] = s.gap;
    values[2 * p + 1] = contacts_[p].normal.clamp_function(-s.gap, -dot(s.n_W, s.v_rel_W));
  }
}

template <typename S>
std::vector<double> RigidModelTpl<S>::discontinuities() const {
  return discontinuities_;
}

template <typename S>
std::vector<S> RigidModelTpl<S>::initial_state() const {
  std::vector<S> y;
  y.reserve(static_cast<std::size_t>(state_size()));
  for (const RigidBodyTpl<S>& b : bodies_) y.insert(y.end(), b.initial.begin(), b.initial.end());
  y.insert(y.end(), static_cast<std::size_t>(integral_count_), S(0));  // the integrals start at 0
  return y;
}

template <typename S>
void RigidModelTpl<S>::derivative(const std::vector<S>& y_in, std::vector<S>& dydt, S t,
                                  double t_segment, std::vector<S>* switching) const {
  const std::vector<S>& y = with_prescribed(t, y_in);
  const std::size_t n = bodies_.size();
  // Loads on each body: world force through Bcm-independent points, body-frame torque about Br.
  std::array<Vec3<S>, 8> small_force{};
  std::array<Vec3<S>, 8> small_torque{};
  std::vector<Vec3<S>> big_force, big_torque;
  Vec3<S>* force_W = small_force.data();
  Vec3<S>* torque_B = small_torque.data();
  if (n > small_force.size()) {
    big_force.assign(n, Vec3<S>{});
    big_torque.assign(n, Vec3<S>{});
    force_W = big_force.data();
    torque_B = big_torque.data();
  }
  std::array<Mat3<S>, 8> small_A{};
  std::vector<Mat3<S>> big_A;
  Mat3<S>* A = small_A.data();
  if (n > small_A.size()) {
    big_A.assign(n, Mat3<S>{});
    A = big_A.data();
  }
  for (std::size_t i = 0; i < n; ++i) {
    const RigidBodyTpl<S>& b = bodies_[i];
    A[i] = rotation_matrix(quat_at(y, kBodyStateSize * i));
    // Gravity: m g at Bcm; its moment about Br is c × m Aᵀ g.
    const Vec3<S> mg_W{b.mass * g_W_[0], b.mass * g_W_[1], b.mass * g_W_[2]};
    force_W[i] = mg_W;
    torque_B[i] = cross(b.c_B, multiply_transposed(A[i], mg_W));
  }
  for (const AppliedLoadTpl<S>& l : loads_) {
    const auto i = static_cast<std::size_t>(l.body);
    const S f = l.profile.value_in(t, t_segment);
    const Vec3<S> v{f * l.value[0], f * l.value[1], f * l.value[2]};
    if (l.torque) {
      const Vec3<S> g_B = l.world_frame ? multiply_transposed(A[i], v) : v;
      for (std::size_t k = 0; k < 3; ++k) torque_B[i][k] += g_B[k];
    } else {
      const Vec3<S> f_B = l.world_frame ? multiply_transposed(A[i], v) : v;
      const Vec3<S> f_W = l.world_frame ? v : multiply(A[i], v);
      const Vec3<S> m_B = cross(l.p_BrP_B, f_B);
      for (std::size_t k = 0; k < 3; ++k) {
        force_W[i][k] += f_W[k];
        torque_B[i][k] += m_B[k];
      }
    }
  }
  for (std::size_t p = 0; p < potentials_.size(); ++p) {
    // f_i = c_i (unit field at P_i), at P_i (core/point_charge_potential.hpp).
    const auto& charges = potentials_[p].charges();
    for (std::size_t k = 0; k < charges.size(); ++k) {
      const auto i = static_cast<std::size_t>(charges[k].body);
      const std::size_t o = kBodyStateSize * i;
      const Vec3<S> r = multiply(A[i], charge_points_[p][k]);
      const S p_WP[3] = {y[o] + r[0], y[o + 1] + r[1], y[o + 2] + r[2]};
      S field[3];
      S v;
      potentials_[p].unit_field(p_WP, field, v);
      const Vec3<S> f{charges[k].weight * field[0], charges[k].weight * field[1],
                      charges[k].weight * field[2]};
      const Vec3<S> m_B = multiply_transposed(A[i], cross(r, f));
      for (std::size_t j = 0; j < 3; ++j) {
        force_W[i][j] += f[j];
        torque_B[i][j] += m_B[j];
      }
    }
  }
  // The integrals' rates: W_d, (W_a), wear work per channel.
  const std::size_t integrals = kBodyStateSize * n;
  for (int k = 0; k < integral_count_; ++k) dydt[integrals + static_cast<std::size_t>(k)] = S(0);
  for (const JointTpl& j : joints_) {
    // f = k d + c u on A at M, −f on B; τ_A, −τ_B for a revolute bushing (bushing.hpp).
    namespace bushing = contact::bushing;
    const auto end = [&](const JointEndTpl& side) {
      if (side.body == contact::kGround) return end_motion<S>(side, nullptr, y, Mat3<S>{}, 0);
      const auto i = static_cast<std::size_t>(side.body);
      return end_motion<S>(side, &bodies_[i], y, A[i], kBodyStateSize * i);
    };
    const bushing::EndMotion<S> a = end(j.a);
    const bushing::EndMotion<S> b = end(j.b);
    const bushing::Separation<S> sep = bushing::separation(a, b);
    const EigenVector3<S> f = bushing::spherical_force(sep, j.parameters);
    EigenVector3<S> tau = EigenVector3<S>::Zero();
    if (j.revolute) tau = bushing::revolute_torque(a, b, j.parameters);
    const auto apply = [&](const JointEndTpl& side, const bushing::EndMotion<S>& m, S sign) {
      if (side.body == contact::kGround) return;
      const auto i = static_cast<std::size_t>(side.body);
      const EigenVector3<S> moment = (sep.p_WM - m.p_WBr).cross(f) + tau;
      const Vec3<S> m_B =
          multiply_transposed(A[i], Vec3<S>{sign * moment[0], sign * moment[1], sign * moment[2]});
      for (std::size_t k = 0; k < 3; ++k) {
        force_W[i][k] += sign * f[static_cast<Eigen::Index>(k)];
        torque_B[i][k] += m_B[k];
      }
    };
    apply(j.a, a, S(1));
    apply(j.b, b, S(-1));
    if (dissipates_) {
      dydt[integrals] += bushing::dissipated_power(a, b, j.parameters, j.revolute);
    }
  }
  const std::size_t first_wear = integrals + (applied_work_ ? 2 : 1);
  for (std::size_t p = 0; p < contacts_.size(); ++p) {
    const ContactPairTpl<S>& c = contacts_[p];
    const PairState s = pair_state(c, y, A);
    if (switching != nullptr) {
      (*switching)[2 * p] = s.gap;
      (*switching)[2 * p + 1] = c.normal.clamp_function(-s.gap, -dot(s.n_W, s.v_rel_W));
    }
    const PairLoad load = pair_load(c, s);
    if (dissipates_) dydt[integrals] += load.dissipated_power;
    if (!(load.normal > S(0))) continue;
    const auto apply = [&](int body, S sign) {
      const auto i = static_cast<std::size_t>(body);
      const std::size_t o = kBodyStateSize * i;
      const Vec3<S> f{sign * load.f_W[0], sign * load.f_W[1], sign * load.f_W[2]};
      const Vec3<S> r{s.p_WP[0] - y[o], s.p_WP[1] - y[o + 1], s.p_WP[2] - y[o + 2]};
      const Vec3<S> m_B = multiply_transposed(A[i], cross(r, f));
      for (std::size_t k = 0; k < 3; ++k) {
        force_W[i][k] += f[k];
        torque_B[i][k] += m_B[k];
      }
    };
    apply(c.body_b, S(1));
    if (c.body_a >= 0) apply(c.body_a, S(-1));
    if (pair_channel_[p] >= 0) {
      dydt[first_wear + static_cast<std::size_t>(pair_channel_[p])] += load.wear_power;
    }
  }
  if (applied_work_) {
    // W_a: f·v_P of every applied force (core::AppliedForce::applied_power).
    for (const AppliedLoadTpl<S>& l : loads_) {
      if (!l.tracks_work) continue;
      const auto i = static_cast<std::size_t>(l.body);
      const std::size_t o = kBodyStateSize * i;
      const S f = l.profile.value_in(t, t_segment);
      const Vec3<S> v{f * l.value[0], f * l.value[1], f * l.value[2]};
      const Vec3<S> f_W = l.world_frame ? v : multiply(A[i], v);
      const Vec3<S> w_W = multiply(A[i], Vec3<S>{y[o + 10], y[o + 11], y[o + 12]});
      const Vec3<S> u = cross(w_W, multiply(A[i], l.p_BrP_B));
      const Vec3<S> v_P{y[o + 7] + u[0], y[o + 8] + u[1], y[o + 9] + u[2]};
      dydt[integrals + 1] += dot(f_W, v_P);
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const RigidBodyTpl<S>& b = bodies_[i];
    const std::size_t o = kBodyStateSize * i;
    const Vec3<S> w{y[o + 10], y[o + 11], y[o + 12]};
    if (b.prescribed) {
      // Its slots do not move; the drive supplies τ_d,B = J_Br α̅ + ω̄ × J_Br ω̄ − Γ_Br,B
      // (core::Model::driving_torque), α̅ = φ̈ Aᵀ a_W the law's, along a_W in the world.
      for (std::size_t k = 0; k < kBodyStateSize; ++k) dydt[o + k] = S(0);
      const Vec3<S> axis_B = multiply_transposed(A[i], b.axis_W);
      const S phi_dd = b.law.law.template angular_acceleration_in<S>(t);
      const Vec3<S> J_alpha =
          multiply(b.J_Br_B, Vec3<S>{phi_dd * axis_B[0], phi_dd * axis_B[1], phi_dd * axis_B[2]});
      const Vec3<S> gyro = cross(w, multiply(b.J_Br_B, w));
      const Vec3<S> tau_B{J_alpha[0] + gyro[0] - torque_B[i][0],
                          J_alpha[1] + gyro[1] - torque_B[i][1],
                          J_alpha[2] + gyro[2] - torque_B[i][2]};
      drive_torque_[i] = dot(axis_B, tau_B);  // a_W · A τ = (Aᵀ a_W) · τ
      continue;
    }
    // θ̇ = ½ θ ⊗ (0, ω̄) (model.md eq. (2)).
    const S e0 = y[o + 3], e1 = y[o + 4], e2 = y[o + 5], e3 = y[o + 6];
    const S h(0.5);
    dydt[o + 3] = -h * (e1 * w[0] + e2 * w[1] + e3 * w[2]);
    dydt[o + 4] = h * (e0 * w[0] + e2 * w[2] - e3 * w[1]);
    dydt[o + 5] = h * (e0 * w[1] + e3 * w[0] - e1 * w[2]);
    dydt[o + 6] = h * (e0 * w[2] + e1 * w[1] - e2 * w[0]);
    // J ω̄̇ = Γ − ω̄ × J ω̄ about Br (Euler's equations; a free body's Br is Bcm).
    const Vec3<S> Jw = multiply(b.J_Br_B, w);
    const Vec3<S> gyro = cross(w, Jw);
    const Vec3<S> rhs{torque_B[i][0] - gyro[0], torque_B[i][1] - gyro[1], torque_B[i][2] - gyro[2]};
    const Vec3<S> alpha = multiply(b.J_Br_B_inv, rhs);
    for (std::size_t k = 0; k < 3; ++k) {
      dydt[o + 10 + k] = alpha[k];
      if (b.pivot) {
        dydt[o + k] = S(0);
        dydt[o + 7 + k] = S(0);
      } else {
        dydt[o + k] = y[o + 7 + k];
        dydt[o + 7 + k] = force_W[i][k] / b.mass;
      }
    }
  }
}

template <typename S>
S RigidModelTpl<S>::energy(const std::vector<S>& y) const {
  S e(0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const RigidBodyTpl<S>& b = bodies_[i];
    const std::size_t o = kBodyStateSize * i;
    const Vec3<S> p{y[o], y[o + 1], y[o + 2]};
    const Vec3<S> v{y[o + 7], y[o + 8], y[o + 9]};
    const Vec3<S> w{y[o + 10], y[o + 11], y[o + 12]};
    const Mat3<S> A = rotation_matrix(quat_at(y, o));
    e += S(0.5) * dot(w, multiply(b.J_Br_B, w));
    if (!b.pivot) e += S(0.5) * b.mass * dot(v, v);
    const Vec3<S> c_W = multiply(A, b.c_B);
    const Vec3<S> p_cm{p[0] + c_W[0], p[1] + c_W[1], p[2] + c_W[2]};
    e -= b.mass * dot(g_W_, p_cm);
  }
  for (std::size_t p = 0; p < potentials_.size(); ++p) {
    const auto& charges = potentials_[p].charges();
    for (std::size_t k = 0; k < charges.size(); ++k) {
      const std::size_t o = kBodyStateSize * static_cast<std::size_t>(charges[k].body);
      const Vec3<S> r = multiply(rotation_matrix(quat_at(y, o)), charge_points_[p][k]);
      const S p_WP[3] = {y[o] + r[0], y[o + 1] + r[1], y[o + 2] + r[2]};
      S field[3];
      S v;
      potentials_[p].unit_field(p_WP, field, v);
      e += charges[k].weight * v;
    }
  }
  if (!contacts_.empty() || !joints_.empty()) {
    std::vector<Mat3<S>> A(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      A[i] = rotation_matrix(quat_at(y, kBodyStateSize * i));
    }
    for (const JointTpl& j : joints_) {
      const auto end = [&](const JointEndTpl& side) {
        if (side.body == contact::kGround) return end_motion<S>(side, nullptr, y, Mat3<S>{}, 0);
        const auto i = static_cast<std::size_t>(side.body);
        return end_motion<S>(side, &bodies_[i], y, A[i], kBodyStateSize * i);
      };
      e += contact::bushing::potential(end(j.a), end(j.b), j.parameters, j.revolute);
    }
    for (const ContactPairTpl<S>& c : contacts_) {
      e += c.normal.potential_in(S(-pair_state(c, y, A.data()).gap));
    }
  }
  return e;
}

template <typename S>
std::vector<S> RigidModelTpl<S>::output_row(S t, const std::vector<S>& y_in,
                                            const std::vector<double>& impacts) const {
  if (has_prescribed_) {
    // The drive torques at (t, y) on the right-limit branch at t (core::Model::driving_torque).
    std::vector<S> rates(y_in.size());
    derivative(y_in, rates, t, static_cast<double>(t));
  }
  const std::vector<S>& y = with_prescribed(t, y_in);
  std::vector<S> row;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const RigidBodyTpl<S>& b = bodies_[i];
    const std::size_t o = kBodyStateSize * i;
    const Mat3<S> A = rotation_matrix(quat_at(y, o));
    const Vec3<S> w{y[o + 10], y[o + 11], y[o + 12]};
    const Vec3<S> r_BrBo{-b.p_BoBr_B[0], -b.p_BoBr_B[1], -b.p_BoBr_B[2]};
    const Vec3<S> r_W = multiply(A, r_BrBo);
    const Vec3<S> u_W = multiply(A, cross(w, r_BrBo));
    for (std::size_t k = 0; k < 3; ++k) row.push_back(y[o + k] + r_W[k]);
    for (std::size_t k = 0; k < 4; ++k) row.push_back(y[o + 3 + k]);
    for (std::size_t k = 0; k < 3; ++k) {
      const S v = b.pivot ? S(0) : y[o + 7 + k];
      row.push_back(v + u_W[k]);
    }
    for (std::size_t k = 0; k < 3; ++k) row.push_back(w[k]);
    for (const Vec3<S>& p : b.p_BrP_B) {
      const Vec3<S> q = multiply(A, p);
      for (std::size_t k = 0; k < 3; ++k) row.push_back(y[o + k] + q[k]);
    }
    if (b.prescribed) row.push_back(drive_torque_[i]);
  }
  const S e = energy(y);
  row.push_back(e);
  const std::size_t integrals = kBodyStateSize * bodies_.size();
  if (dissipates_) {
    const S work = y[integrals];
    const S applied = applied_work_ ? y[integrals + 1] : S(0);
    row.push_back(work);
    if (applied_work_) row.push_back(applied);
    row.push_back(e - energy0_ + work - applied);  // E(t) − E(0) + W_d(t) − W_a(t)
  }
  if (!wear_channels_.empty()) {
    std::vector<Mat3<S>> A(bodies_.size());
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      A[i] = rotation_matrix(quat_at(y, kBodyStateSize * i));
    }
    std::vector<S> normal(wear_channels_.size()), largest(wear_channels_.size()),
        slip(wear_channels_.size());
    for (std::size_t p = 0; p < contacts_.size(); ++p) {
      if (pair_channel_[p] < 0) continue;
      const auto c = static_cast<std::size_t>(pair_channel_[p]);
      const PairLoad load = pair_load(contacts_[p], pair_state(contacts_[p], y, A.data()));
      if (!(load.normal > S(0))) continue;
      normal[c] += load.normal;
      if (load.normal > largest[c]) {  // ContactElement::wear_samples' rule
        largest[c] = load.normal;
        slip[c] = load.slip_speed;
      }
    }
    const std::size_t first_wear = integrals + (applied_work_ ? 2 : 1);
    for (std::size_t c = 0; c < wear_channels_.size(); ++c) {
      row.push_back(normal[c]);
      row.push_back(slip[c]);
      row.push_back(y[first_wear + c]);
      row.push_back(c < impacts.size() ? S(impacts[c]) : S(0));
    }
  }
  return row;
}

template class RigidModelTpl<double>;
template class RigidModelTpl<long double>;
template class RigidModelTpl<boost::multiprecision::float128>;

}  // namespace flexref::precision
