#pragma once
/// \file ideal_joints_impl.hpp
/// IdealJointsTpl<S>'s definitions (ideal_joints.hpp), included by the units that
/// instantiate it: constraint/ideal_joints.cpp (double) and precision/ (long double, float128).
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "constraint/ideal_joints.hpp"
#include "core/element_text.hpp"

namespace flexref::constraint {
namespace detail {

/// An end's pose and motion at the evaluation, all in the world frame: the joint point p, its
/// arm r from the body's Br, its velocity v = v_Br + ω × r + A Φ q̇_f, the part of its
/// acceleration that does not involve v̇ (c = ω × (ω × r) + 2 ω × A Φ q̇_f; γ's alone, zero
/// where end_motion is asked for no γ), the body's ω and A. A ground end has p = its world
/// point and everything else zero (A = I).
template <typename S>
struct EndMotion {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Matrix3 = Eigen::Matrix<S, 3, 3>;
  const typename IdealJointsTpl<S>::End* end = nullptr;
  const core::BodyKinematicsTpl<S>* body = nullptr;  ///< nullptr: ground
  Vector3 p = Vector3::Zero(), r = Vector3::Zero(), v = Vector3::Zero(), c = Vector3::Zero();
  Vector3 w = Vector3::Zero();
  Matrix3 R = Matrix3::Identity();
  /// World axis k of the end's joint frame, A R_BJ e_k.
  Vector3 axis(int k) const { return R * end->R_BJ.col(k); }
};

template <typename S>
EndMotion<S> end_motion(const typename IdealJointsTpl<S>::End& e,
                        std::span<const core::BodyKinematicsTpl<S>> bodies,
                        bool with_gamma = true) {
  EndMotion<S> m;
  m.end = &e;
  if (e.body == kGround) {
    m.p = e.x_P;
    return m;
  }
  const core::BodyKinematicsTpl<S>& k = bodies[static_cast<std::size_t>(e.body)];
  const core::BodyStateTpl<S>& s = *k.state;
  m.body = &k;
  m.R = k.R_WB;
  m.w = m.R * s.w_WB_B;
  Eigen::Matrix<S, 3, 1> x = e.x_P - k.p_BoBr_B;  // ū_P = x_P − p_BoBr + Φ_P q_f (eq. 10)
  if (e.phi.cols() > 0) x.noalias() += e.phi * s.q_f;
  m.r = m.R * x;
  m.p = s.p_WBr + m.r;
  m.v = s.v_WBr + m.w.cross(m.r);
  if (with_gamma) m.c = m.w.cross(m.w.cross(m.r));  // γ's alone
  if (e.phi.cols() > 0) {
    const Eigen::Matrix<S, 3, 1> u_dot = m.R * (e.phi * s.qd_f);  // A Φ_P q̇_f
    m.v += u_dot;
    if (with_gamma) m.c += S(2) * m.w.cross(u_dot);
  }
  return m;
}

/// J(row, ·) += sign ∂(u · v_P)/∂v_b = sign (uᵀ, (Aᵀ (r × u))ᵀ, uᵀ A Φ_P) on the end's body.
template <typename S>
void add_point_row(const EndMotion<S>& m, const Eigen::Matrix<S, 3, 1>& u, const S& sign, int row,
                   core::ConstraintRowsTpl<S>& rows) {
  if (m.body == nullptr) return;
  auto J_b = rows.jacobian.block(row, m.end->body);
  J_b.template head<3>() += sign * u;
  J_b.template segment<3>(3) += sign * (m.R.transpose() * m.r.cross(u));
  const Eigen::Index n = m.end->phi.cols();
  if (n > 0) J_b.segment(6, n) += sign * (m.end->phi.transpose() * (m.R.transpose() * u));
}

/// J(row, ·) += sign ∂(c · ω)/∂ω̄ = sign (Aᵀ c)ᵀ on the end's body.
template <typename S>
void add_rotation_row(const EndMotion<S>& m, const Eigen::Matrix<S, 3, 1>& c, const S& sign,
                      int row, core::ConstraintRowsTpl<S>& rows) {
  if (m.body == nullptr) return;
  rows.jacobian.block(row, m.end->body).template segment<3>(3) += sign * (m.R.transpose() * c);
}

/// Rotation row Φ = p · q for a vector p of end P (p = A_P p̄(t), with p' = A_P p̄', p'' = A_P p̄''
/// its rates relative to the body; zero unless driven) and a vector q fixed in end Q:
///   Φ̇ = (p × q)·(ω_P − ω_Q) + q·p'                          (Φ_t = q·p')
///   Φ̈ = (p × q)·(ω̇_P − ω̇_Q) + d(p × q)/dt·(ω_P − ω_Q) + (ω_Q × q)·p' + q·(ω_P × p') + q·p'',
///   d(p × q)/dt = (ω_P × p + p') × q + p × (ω_Q × q),   ω̇ = A α̅.
template <typename S>
void rotation_dot_row(const EndMotion<S>& P, const Eigen::Matrix<S, 3, 1>& p,
                      const Eigen::Matrix<S, 3, 1>& p1, const Eigen::Matrix<S, 3, 1>& p2,
                      const EndMotion<S>& Q, const Eigen::Matrix<S, 3, 1>& q, int row,
                      core::ConstraintRowsTpl<S>& rows, bool with_gamma = true) {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  const Vector3 pxq = p.cross(q);
  rows.phi(row) = p.dot(q);
  add_rotation_row(P, pxq, S(1), row, rows);
  add_rotation_row(Q, pxq, S(-1), row, rows);
  rows.phi_t(row) = q.dot(p1);
  if (!with_gamma) return;
  const Vector3 w_rel = P.w - Q.w;
  const Vector3 q_dot = Q.w.cross(q);
  const Vector3 pxq_dot = (P.w.cross(p) + p1).cross(q) + p.cross(q_dot);
  rows.gamma(row) = -(pxq_dot.dot(w_rel) + q_dot.dot(p1) + q.dot(P.w.cross(p1)) + q.dot(p2));
}

/// Slide row Φ = u · d − s, u fixed in end b, d = p_a − p_b (s(t) a drive, with its rates):
///   Φ̇ = (u × d)·ω_b + u·ḋ − ṡ                                  (Φ_t = −ṡ)
///   Φ̈ = (u × d)·ω̇_b + ((ω_b × u) × d + u × ḋ)·ω_b + (ω_b × u)·ḋ + u·d̈ − s̈,
///   d̈ = a_a − a_b = (terms in v̇) + c_a − c_b.
template <typename S>
void slide_row(const EndMotion<S>& a, const EndMotion<S>& b, const Eigen::Matrix<S, 3, 1>& u,
               const S& s, const S& s1, const S& s2, int row, core::ConstraintRowsTpl<S>& rows,
               bool with_gamma = true) {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  const Vector3 d = a.p - b.p;
  const Vector3 d_dot = a.v - b.v;
  rows.phi(row) = u.dot(d) - s;
  add_rotation_row(b, u.cross(d), S(1), row, rows);
  add_point_row(a, u, S(1), row, rows);
  add_point_row(b, u, S(-1), row, rows);
  rows.phi_t(row) = -s1;
  if (!with_gamma) return;
  const Vector3 u_dot = b.w.cross(u);
  rows.gamma(row) =
      -((u_dot.cross(d) + u.cross(d_dot)).dot(b.w) + u_dot.dot(d_dot) + u.dot(a.c - b.c)) + s2;
}

/// The three point rows Φ = p_a − p_b from `row` on: J = ∂(v_a − v_b)/∂v, γ = −(c_a − c_b);
/// those `wanted` of their row.
template <typename S, typename Wanted>
void point_rows(const EndMotion<S>& a, const EndMotion<S>& b, int row,
                core::ConstraintRowsTpl<S>& rows, const Wanted& wanted, bool with_gamma) {
  for (int k = 0; k < 3; ++k) {
    if (!wanted(row + k)) continue;
    const Eigen::Matrix<S, 3, 1> u = Eigen::Matrix<S, 3, 1>::Unit(k);
    rows.phi(row + k) = a.p(k) - b.p(k);
    add_point_row(a, u, S(1), row + k, rows);
    add_point_row(b, u, S(-1), row + k, rows);
    rows.phi_t(row + k) = S(0);
    if (with_gamma) rows.gamma(row + k) = -(a.c(k) - b.c(k));
  }
}

/// Z_b·X_a and Z_b·Y_a: the axes stay parallel (those `wanted` of their row).
template <typename S, typename Wanted>
void parallel_axis_rows(const EndMotion<S>& a, const EndMotion<S>& b, int row,
                        core::ConstraintRowsTpl<S>& rows, const Wanted& wanted, bool with_gamma) {
  const Eigen::Matrix<S, 3, 1> zero = Eigen::Matrix<S, 3, 1>::Zero();
  const Eigen::Matrix<S, 3, 1> z_b = b.axis(2);
  if (wanted(row)) rotation_dot_row(b, z_b, zero, zero, a, a.axis(0), row, rows, with_gamma);
  if (wanted(row + 1)) {
    rotation_dot_row(b, z_b, zero, zero, a, a.axis(1), row + 1, rows, with_gamma);
  }
}

}  // namespace detail

template <typename S>
IdealJointsTpl<S>::IdealJointsTpl(std::vector<IdealJointSpec> joints, int body_count)
    : specs_(std::move(joints)) {
  const auto end_in_S = [](const JointEnd& e) {
    End out;
    out.body = e.body;
    out.x_P = e.p_BoP_B.template cast<S>();
    if (e.node >= 0) out.phi = e.phi_B.template cast<S>();
    out.R_BJ = e.R_BJ.template cast<S>();
    return out;
  };
  first_row_.push_back(0);
  for (std::size_t j = 0; j < specs_.size(); ++j) {
    const IdealJointSpec& spec = specs_[j];
    const std::string who = "joint '" + spec.name + "': ";
    if (spec.a.body < 0 || spec.a.body >= body_count) {
      throw std::invalid_argument(who + "its first end must be a body of the model");
    }
    if (spec.b.body != kGround && (spec.b.body < 0 || spec.b.body >= body_count)) {
      throw std::invalid_argument(who + "its second end is neither a body nor the ground");
    }
    if (spec.b.body == spec.a.body) {
      throw std::invalid_argument(who + "both ends are on the same body");
    }
    for (const JointEnd* e : {&spec.a, &spec.b}) {
      if (e->node >= 0 && e->phi_B.cols() == 0) {
        throw std::invalid_argument(who + "a node end needs the node's mode shapes");
      }
    }
    if (spec.drive.active && spec.type != JointType::kRevolute &&
        spec.type != JointType::kPrismatic) {
      throw std::invalid_argument(who + "only revolute and prismatic joints can be driven");
    }
    if (spec.type == JointType::kDistance && !(spec.length > 0.0 && std::isfinite(spec.length))) {
      throw std::invalid_argument(who + "a distance joint needs a positive finite length");
    }
    a_.push_back(end_in_S(spec.a));
    b_.push_back(end_in_S(spec.b));
    length_.push_back(S(spec.length));
    const int count = constraint::row_count(spec.type, spec.drive.active);
    first_row_.push_back(first_row_.back() + count);
    for (int k = 0; k < count; ++k) {
      row_joint_.push_back(static_cast<int>(j));
      // Length rows: the point rows, slide rows and distance rows (see evaluate's layout).
      bool length = false;
      switch (spec.type) {
        case JointType::kSpherical:
        case JointType::kDistance:
          length = true;
          break;
        case JointType::kRevolute:
        case JointType::kUniversal:
        case JointType::kFixed:
          length = k < 3;
          break;
        case JointType::kCylindrical:
          length = k < 2;
          break;
        case JointType::kPrismatic:
          length = k < 2 || k == 5;  // the drive's slide row is the sixth
          break;
      }
      length_row_.push_back(length);
      // The point rows evaluate lays out first: all of a spherical joint's, the first three of
      // a revolute, universal and fixed joint's.
      const bool points = spec.type == JointType::kSpherical ||
                          ((spec.type == JointType::kRevolute ||
                            spec.type == JointType::kUniversal || spec.type == JointType::kFixed) &&
                           k < 3);
      point_row_.push_back(points);
    }
  }
}

template <typename S>
std::array<int, 2> IdealJointsTpl<S>::row_bodies(int row) const {
  const auto j = static_cast<std::size_t>(row_joint_[static_cast<std::size_t>(row)]);
  return {a_[j].body, b_[j].body};
}

template <typename S>
void IdealJointsTpl<S>::evaluate(const S& t, std::span<const Kinematics> bodies,
                                 const core::VelocityLayout& layout,
                                 core::ConstraintRowsTpl<S>& rows) const {
  evaluate_where<true>(t, bodies, layout, rows, [](int) { return true; });
}

template <typename S>
void IdealJointsTpl<S>::evaluate_rates(const S& t, std::span<const Kinematics> bodies,
                                       const core::VelocityLayout& layout,
                                       core::ConstraintRowsTpl<S>& rows) const {
  evaluate_where<false>(t, bodies, layout, rows, [](int) { return true; });
}

template <typename S>
void IdealJointsTpl<S>::evaluate_rows(const S& t, std::span<const Kinematics> bodies,
                                      const core::VelocityLayout& layout,
                                      std::span<const char> wanted,
                                      core::ConstraintRowsTpl<S>& rows) const {
  evaluate_where<true>(t, bodies, layout, rows,
                       [wanted](int row) { return wanted[static_cast<std::size_t>(row)] != 0; });
}

template <typename S>
template <bool kGamma, typename Wanted>
void IdealJointsTpl<S>::evaluate_where(const S& t, std::span<const Kinematics> bodies,
                                       const core::VelocityLayout& layout,
                                       core::ConstraintRowsTpl<S>& rows,
                                       const Wanted& wanted) const {
  using detail::EndMotion;
  const Vector3 zero = Vector3::Zero();
  // Every row belongs to one joint, which writes only its bodies' blocks of J: those are zeroed
  // here, contiguously (the rest of J is not stored).
  this->prepare_rows(layout, rows);
  rows.jacobian.set_zero();
  rows.phi_t.setZero();
  for (std::size_t j = 0; j < specs_.size(); ++j) {
    const IdealJointSpec& spec = specs_[j];
    const int row = first_row_[j];
    bool any = false;
    for (int r = row; r < first_row_[j + 1] && !any; ++r) any = wanted(r);
    if (!any) continue;  // a joint none of whose rows is wanted: not even its ends' motion
    const EndMotion<S> a = detail::end_motion<S>(a_[j], bodies, kGamma);
    const EndMotion<S> b = detail::end_motion<S>(b_[j], bodies, kGamma);
    // The drive's relative coordinate and its rates (zero when not driven).
    S q = S(0), q1 = S(0), q2 = S(0);
    if (spec.drive.active) {
      q = spec.drive.law.template angle<S>(t);
      q1 = spec.drive.law.template angular_rate<S>(t);
      if (kGamma) q2 = spec.drive.law.template angular_acceleration<S>(t);
    }
    switch (spec.type) {
      case JointType::kSpherical:
        detail::point_rows(a, b, row, rows, wanted, kGamma);
        break;
      case JointType::kRevolute:
        detail::point_rows(a, b, row, rows, wanted, kGamma);
        detail::parallel_axis_rows(a, b, row + 3, rows, wanted, kGamma);
        if (spec.drive.active && wanted(row + 5)) {
          // p(t) = A_b (cos φ Ȳ − sin φ X̄): Φ = X_a·p = sin(ψ − φ); p̄' = −φ̇ m̄,
          // p̄'' = −φ̈ m̄ − φ̇² p̄ with m̄ = cos φ X̄ + sin φ Ȳ (joint axes of end b).
          using std::cos;
          using std::sin;
          const Vector3 x_b = b.axis(0);
          const Vector3 y_b = b.axis(1);
          const Vector3 p = cos(q) * y_b - sin(q) * x_b;
          const Vector3 m = cos(q) * x_b + sin(q) * y_b;
          const Vector3 p1 = -q1 * m;
          const Vector3 p2 = -q2 * m - q1 * q1 * p;
          detail::rotation_dot_row(b, p, p1, p2, a, a.axis(0), row + 5, rows, kGamma);
        }
        break;
      case JointType::kUniversal:
        detail::point_rows(a, b, row, rows, wanted, kGamma);
        if (wanted(row + 3)) {
          detail::rotation_dot_row(b, b.axis(2), zero, zero, a, a.axis(2), row + 3, rows, kGamma);
        }
        break;
      case JointType::kFixed:
        detail::point_rows(a, b, row, rows, wanted, kGamma);
        detail::parallel_axis_rows(a, b, row + 3, rows, wanted, kGamma);
        if (wanted(row + 5)) {
          detail::rotation_dot_row(b, b.axis(0), zero, zero, a, a.axis(1), row + 5, rows, kGamma);
        }
        break;
      case JointType::kCylindrical:
        if (wanted(row)) detail::slide_row(a, b, b.axis(0), S(0), S(0), S(0), row, rows, kGamma);
        if (wanted(row + 1))
          detail::slide_row(a, b, b.axis(1), S(0), S(0), S(0), row + 1, rows, kGamma);
        detail::parallel_axis_rows(a, b, row + 2, rows, wanted, kGamma);
        break;
      case JointType::kPrismatic:
        if (wanted(row)) detail::slide_row(a, b, b.axis(0), S(0), S(0), S(0), row, rows, kGamma);
        if (wanted(row + 1))
          detail::slide_row(a, b, b.axis(1), S(0), S(0), S(0), row + 1, rows, kGamma);
        detail::parallel_axis_rows(a, b, row + 2, rows, wanted, kGamma);
        if (wanted(row + 4)) {
          detail::rotation_dot_row(b, b.axis(0), zero, zero, a, a.axis(1), row + 4, rows, kGamma);
        }
        if (spec.drive.active && wanted(row + 5)) {
          // Z_b·d − s(t), s = the initial Z_b·d (the drive's offset) + the law's displacement.
          detail::slide_row(a, b, b.axis(2), S(S(spec.drive.offset) + q), q1, q2, row + 5, rows,
                            kGamma);
        }
        break;
      case JointType::kDistance: {
        // Φ = (|d|² − L²)/(2L): Φ̇ = d·ḋ/L, Φ̈ = (d·d̈ + ḋ·ḋ)/L.
        const S L = length_[j];
        const Vector3 d = a.p - b.p;
        const Vector3 d_dot = a.v - b.v;
        rows.phi(row) = (d.squaredNorm() - L * L) / (S(2) * L);
        const Vector3 u = d / L;
        detail::add_point_row(a, u, S(1), row, rows);
        detail::add_point_row(b, u, S(-1), row, rows);
        if (kGamma) rows.gamma(row) = -(d_dot.squaredNorm() + d.dot(a.c - b.c)) / L;
        break;
      }
    }
  }
  if (rows.J.size() > 0) {
    rows.J.setZero();
    rows.jacobian.scatter(rows.J);
  }
}

template <typename S>
core::JointReactionTpl<S> IdealJointsTpl<S>::reaction(
    int joint, std::span<const Kinematics> bodies, const core::VelocityLayout& layout,
    const Eigen::Ref<const Eigen::Matrix<S, Eigen::Dynamic, 1>>& generalized_force) const {
  const auto j = static_cast<std::size_t>(joint);
  const detail::EndMotion<S> a = detail::end_motion<S>(a_[j], bodies);
  const int o = layout.offset(a_[j].body);
  // The joint's generalized force on its first body: f (world) on the translation rows, the
  // torque about Br (body frame) on the rotation rows; about the joint point P: τ_P = A τ_B − r ×
  // f.
  core::JointReactionTpl<S> out;
  out.f_W = generalized_force.template segment<3>(o);
  out.tau_W = a.R * generalized_force.template segment<3>(o + 3) - a.r.cross(out.f_W);
  return out;
}

template <typename S>
std::string IdealJointsTpl<S>::describe(int joint, std::span<const core::Body> bodies) const {
  const IdealJointSpec& s = specs_[static_cast<std::size_t>(joint)];
  std::ostringstream out;
  const auto end = [&](const JointEnd& e) {
    return core::body_text(e.body, bodies) + " " +
           (e.node >= 0 ? core::node_text(e.body, e.node, bodies)
                        : "point " + core::vector_text(e.p_BoP_B));
  };
  out << "ideal " << to_string(s.type) << " joint '" << s.name << "': " << end(s.a) << " to "
      << end(s.b);
  if (s.type == JointType::kDistance) {
    out << ", length " << s.length << " m";
  } else if (s.type != JointType::kSpherical) {
    const Eigen::Vector3d z = s.a.R_BJ.col(2);
    out << ", axis " << core::vector_text(z) << " in the frame of "
        << core::body_text(s.a.body, bodies);
  }
  // The drive's coordinate is the relative angle of a revolute joint (rad) and the relative
  // displacement of a prismatic one (m).
  if (s.drive.active) {
    out << ", driven: " << s.drive.law.describe(s.type == JointType::kPrismatic ? "m/s" : "rad/s");
  }
  out << " (" << constraint::row_count(s.type, s.drive.active) << " rows)";
  return out.str();
}

template <typename S>
void IdealJointsTpl<S>::append_discontinuities(std::vector<double>& times) const {
  for (const IdealJointSpec& s : specs_) {
    if (s.drive.active && s.drive.law.kind == core::AngleLaw::Kind::kSpinUp) {
      times.push_back(s.drive.law.spin_up_time);  // φ⁗ jumps at the end of the spin-up
    }
  }
}

}  // namespace flexref::constraint
