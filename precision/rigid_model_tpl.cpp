#include "precision/rigid_model_tpl.hpp"

#include <algorithm>
#include <boost/math/constants/constants.hpp>
#include <boost/multiprecision/float128.hpp>
#include <stdexcept>

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

/// core::TimeProfile::value in precision S (the same laws; the branch is chosen in double by
/// t_segment, as there).
template <typename S>
S profile_value(const core::TimeProfile& p, S t, double t_segment) {
  using std::sin;
  const bool active = t_segment >= p.start() && t_segment < p.start() + p.duration();
  const S pi = boost::math::constants::pi<S>();
  switch (p.shape()) {
    case core::TimeProfile::Shape::kConstant:
      return S(1);
    case core::TimeProfile::Shape::kSin2Pulse: {
      if (!active) return S(0);
      const S s = sin(pi * (t - S(p.start())) / S(p.duration()));
      return s * s;
    }
    case core::TimeProfile::Shape::kRectangularPulse:
      return active ? S(1) : S(0);
    case core::TimeProfile::Shape::kHarmonic:
      return sin(S(2) * pi * S(p.frequency()) * t + S(p.phase()));
  }
  return S(0);
}

template <typename S>
Quat<S> quat_at(const std::vector<S>& y, std::size_t o) {
  return {y[o + 3], y[o + 4], y[o + 5], y[o + 6]};
}

}  // namespace

template <typename S>
RigidModelTpl<S>::RigidModelTpl(const scene::SceneSpec& spec) : g_W_(to_s<S>(spec.g_W)) {
  const auto refuse = [&](const scene::SpecSource& source, const std::string& what) {
    throw std::invalid_argument(
        (source.path.empty() ? spec.name : source.path) + ": " + what +
        " is not in the extended/quad model yet (docs/precision.md: rigid free and pivot "
        "bodies, gravity, applied forces and torques); use --precision double");
  };
  if (!spec.potentials.empty()) refuse(spec.potentials.front().source, "a potential");
  if (!spec.contacts.empty()) refuse(spec.contacts.front().source, "a contact");
  if (!spec.joints.empty()) refuse(spec.joints.front().source, "a joint");
  for (const scene::BodySpec& b : spec.bodies) {
    const core::RigidBodyDescription& d = b.description;
    if (d.flexible) refuse(b.source, "a flexible body");
    if (d.motion == core::MotionKind::kPrescribed) refuse(b.source, "prescribed motion");
    RigidBodyTpl<S> body;
    body.name = d.name;
    body.pivot = d.motion == core::MotionKind::kPivot;
    body.mass = S(d.mass);
    const Vec3<S> p_BoBcm_B = to_s<S>(d.p_BoBcm_B);
    body.p_BoBr_B = body.pivot ? to_s<S>(d.p_BoPivot_B) : p_BoBcm_B;
    for (std::size_t i = 0; i < 3; ++i) body.c_B[i] = p_BoBcm_B[i] - body.p_BoBr_B[i];
    for (std::size_t i = 0; i < 3; ++i) {
      for (std::size_t j = 0; j < 3; ++j)
        body.J_Br_B[i][j] =
            S(d.I_Bcm_B(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
    }
    if (body.pivot) {  // parallel axes: J_Br = J_Bcm + m (|c|² I − c cᵀ)
      const S c2 = dot(body.c_B, body.c_B);
      for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
          body.J_Br_B[i][j] += body.mass * ((i == j ? c2 : S(0)) - body.c_B[i] * body.c_B[j]);
        }
      }
    }
    body.J_Br_B_inv = inverse(body.J_Br_B);
    {
      using std::sqrt;
      const core::BodyInitialState& init = d.initial;
      Quat<S> q{S(init.theta_WB(0)), S(init.theta_WB(1)), S(init.theta_WB(2)), S(init.theta_WB(3))};
      const S norm = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      for (S& x : q) x /= norm;
      const Mat3<S> A = rotation_matrix(q);
      const Vec3<S> w = to_s<S>(init.w_WB_B);
      const Vec3<S> r_W = multiply(A, body.p_BoBr_B);
      const Vec3<S> u_W = multiply(A, cross(w, body.p_BoBr_B));
      const Vec3<S> p0 = to_s<S>(init.p_WBo);
      const Vec3<S> v0 = to_s<S>(init.v_WBo);
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t uk = k;
        body.initial[uk] = p0[k] + r_W[k];  // p_WBr = p_WBo + A p_BoBr
        body.initial[7 + uk] =
            body.pivot ? S(0) : v0[k] + u_W[k];  // v_WBr = v_WBo + A (ω̄ × p_BoBr)
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
    loads_.push_back(load);
  }
}

template <typename S>
std::vector<double> RigidModelTpl<S>::discontinuities() const {
  std::vector<double> times;
  for (const AppliedLoadTpl<S>& l : loads_) l.profile.append_discontinuities(times);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  return times;
}

template <typename S>
std::vector<S> RigidModelTpl<S>::initial_state() const {
  std::vector<S> y;
  y.reserve(static_cast<std::size_t>(state_size()));
  for (const RigidBodyTpl<S>& b : bodies_) y.insert(y.end(), b.initial.begin(), b.initial.end());
  return y;
}

template <typename S>
void RigidModelTpl<S>::derivative(const std::vector<S>& y, std::vector<S>& dydt, S t,
                                  double t_segment) const {
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
    const S f = profile_value(l.profile, t, t_segment);
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
  for (std::size_t i = 0; i < n; ++i) {
    const RigidBodyTpl<S>& b = bodies_[i];
    const std::size_t o = kBodyStateSize * i;
    const Vec3<S> w{y[o + 10], y[o + 11], y[o + 12]};
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
  return e;
}

template <typename S>
std::vector<S> RigidModelTpl<S>::output_row(const std::vector<S>& y) const {
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
  }
  row.push_back(energy(y));
  return row;
}

template class RigidModelTpl<double>;
template class RigidModelTpl<long double>;
template class RigidModelTpl<boost::multiprecision::float128>;

}  // namespace flexref::precision
