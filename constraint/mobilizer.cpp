#include "constraint/mobilizer.hpp"

#include <cmath>

#include "rotation/euler_parameters.hpp"

namespace flexref::constraint {
namespace {

Eigen::Matrix3d rotation_z(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix3d r;
  r << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return r;
}

/// The angle of a rotation about z (R = R_z(ψ)): ψ = atan2(R(1,0), R(0,0)).
double angle_z(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

Eigen::Vector4d euler_parameters(const double* q) {
  return Eigen::Vector4d(q[0], q[1], q[2], q[3]);
}

/// θ ⊗ exp(h ω̄) into q[0..3].
void advance_euler_parameters(const double* q, const double* w, double h, double* q_out) {
  const Eigen::Vector3d phi = h * Eigen::Vector3d(w[0], w[1], w[2]);
  const Eigen::Vector4d theta =
      rotation::quaternion_multiply(euler_parameters(q), rotation::exp_quaternion(phi));
  for (int k = 0; k < 4; ++k) q_out[k] = theta(k);
}

}  // namespace

const char* to_string(MobilizerKind kind) {
  switch (kind) {
    case MobilizerKind::kFree:
      return "free";
    case MobilizerKind::kPivot:
      return "pivot";
    case MobilizerKind::kRevolute:
      return "revolute";
    case MobilizerKind::kPrismatic:
      return "prismatic";
    case MobilizerKind::kCylindrical:
      return "cylindrical";
    case MobilizerKind::kUniversal:
      return "universal";
    case MobilizerKind::kSpherical:
      return "spherical";
    case MobilizerKind::kFixed:
      return "fixed";
  }
  return "?";
}

int position_count(MobilizerKind kind) {
  switch (kind) {
    case MobilizerKind::kFree:
      return 7;
    case MobilizerKind::kPivot:
    case MobilizerKind::kSpherical:
      return 4;
    case MobilizerKind::kRevolute:
    case MobilizerKind::kPrismatic:
      return 1;
    case MobilizerKind::kCylindrical:
    case MobilizerKind::kUniversal:
      return 2;
    case MobilizerKind::kFixed:
      return 0;
  }
  return 0;
}

int velocity_count(MobilizerKind kind) {
  switch (kind) {
    case MobilizerKind::kFree:
      return 6;
    case MobilizerKind::kPivot:
    case MobilizerKind::kSpherical:
      return 3;
    default:
      return position_count(kind);
  }
}

void relative_motion(const Mobilizer& m, const double* q, const double* u, RelativeMotion& out) {
  const int n = velocity_count(m.kind);
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  out.H_w.setZero(3, n);
  out.H_v.setZero(3, n);
  out.w_dot_bias_F.setZero();
  out.p_ddot_bias_F.setZero();
  out.p_FM_F.setZero();
  switch (m.kind) {
    case MobilizerKind::kFree:
      // q = (p_WBr, θ_WB), u = (v_WBr, ω̄): w_FM_F = A ω̄, ṗ = v; Ȧ ω̄ = A (ω̄ × ω̄) = 0.
      out.R_FM = rotation::rotation_matrix(euler_parameters(q + 3));
      out.p_FM_F = Eigen::Vector3d(q[0], q[1], q[2]);
      out.H_v.leftCols<3>().setIdentity();
      out.H_w.rightCols<3>() = out.R_FM;
      break;
    case MobilizerKind::kPivot:
    case MobilizerKind::kSpherical:
      // u = w_FM_M: w_FM_F = A u, and Ȧ u = A (u × u) = 0.
      out.R_FM = rotation::rotation_matrix(euler_parameters(q));
      out.H_w = out.R_FM;
      break;
    case MobilizerKind::kRevolute:
      out.R_FM = rotation_z(q[0]);
      out.H_w.col(0) = z;
      break;
    case MobilizerKind::kPrismatic:
      out.R_FM.setIdentity();
      out.p_FM_F = q[0] * z;
      out.H_v.col(0) = z;
      break;
    case MobilizerKind::kCylindrical:
      out.R_FM = rotation_z(q[0]);
      out.p_FM_F = q[1] * z;
      out.H_w.col(0) = z;
      out.H_v.col(1) = z;
      break;
    case MobilizerKind::kUniversal: {
      // R_FM = R_z(ψ1) C R_z(ψ2): w_FM_F = z ψ̇1 + a ψ̇2 with a = R_z(ψ1) C z (the child's axis
      // in F); ȧ = (z ψ̇1) × a, so Ḣ_w u = (z × a) ψ̇1 ψ̇2.
      const Eigen::Matrix3d R1 = rotation_z(q[0]);
      out.R_FM = R1 * m.C * rotation_z(q[1]);
      const Eigen::Vector3d a = R1 * m.C.col(2);
      out.H_w.col(0) = z;
      out.H_w.col(1) = a;
      out.w_dot_bias_F = z.cross(a) * (u[0] * u[1]);
      break;
    }
    case MobilizerKind::kFixed:
      out.R_FM.setIdentity();
      break;
  }
}

void advance_coordinates(const Mobilizer& m, const double* q, const double* u, double h,
                         double* q_out) {
  switch (m.kind) {
    case MobilizerKind::kFree:
      for (int k = 0; k < 3; ++k) q_out[k] = q[k] + h * u[k];
      advance_euler_parameters(q + 3, u + 3, h, q_out + 3);
      break;
    case MobilizerKind::kPivot:
    case MobilizerKind::kSpherical:
      advance_euler_parameters(q, u, h, q_out);
      break;
    default:
      for (int k = 0; k < position_count(m.kind); ++k) q_out[k] = q[k] + h * u[k];
      break;
  }
}

void coordinate_rates(const Mobilizer& m, const double* q, const double* u, double* q_dot) {
  const auto theta_rate = [](const double* theta, const double* w, double* out) {
    const Eigen::Vector4d t = euler_parameters(theta).normalized();
    const Eigen::Vector4d rate =
        rotation::euler_parameter_rate(t, Eigen::Vector3d(w[0], w[1], w[2]));
    for (int k = 0; k < 4; ++k) out[k] = rate(k);
  };
  switch (m.kind) {
    case MobilizerKind::kFree:
      for (int k = 0; k < 3; ++k) q_dot[k] = u[k];
      theta_rate(q + 3, u + 3, q_dot + 3);
      break;
    case MobilizerKind::kPivot:
    case MobilizerKind::kSpherical:
      theta_rate(q, u, q_dot);
      break;
    default:
      for (int k = 0; k < position_count(m.kind); ++k) q_dot[k] = u[k];
      break;
  }
}

void normalize_coordinates(const Mobilizer& m, double* q) {
  double* theta = m.kind == MobilizerKind::kFree ? q + 3
                  : (m.kind == MobilizerKind::kPivot || m.kind == MobilizerKind::kSpherical)
                      ? q
                      : nullptr;
  if (theta == nullptr) return;
  Eigen::Map<Eigen::Vector4d> t(theta);
  t.normalize();
}

void mobilizer_coordinates(const Mobilizer& m, const Eigen::Matrix3d& R_FM,
                           const Eigen::Vector3d& p_FM_F, const Eigen::Vector3d& w_FM_F,
                           const Eigen::Vector3d& p_dot_FM_F, const Eigen::Vector4d* theta,
                           double* q, double* u) {
  const auto put_theta = [&](double* out) {
    const Eigen::Vector4d t =
        theta != nullptr ? *theta : rotation::euler_parameters_from_matrix(R_FM);
    for (int k = 0; k < 4; ++k) out[k] = t(k);
  };
  const Eigen::Vector3d w_FM_M = R_FM.transpose() * w_FM_F;
  switch (m.kind) {
    case MobilizerKind::kFree:
      for (int k = 0; k < 3; ++k) {
        q[k] = p_FM_F(k);
        u[k] = p_dot_FM_F(k);
        u[3 + k] = w_FM_M(k);
      }
      put_theta(q + 3);
      break;
    case MobilizerKind::kPivot:
    case MobilizerKind::kSpherical:
      put_theta(q);
      for (int k = 0; k < 3; ++k) u[k] = w_FM_M(k);
      break;
    case MobilizerKind::kRevolute:
      q[0] = angle_z(R_FM);
      u[0] = w_FM_F(2);
      break;
    case MobilizerKind::kPrismatic:
      q[0] = p_FM_F(2);
      u[0] = p_dot_FM_F(2);
      break;
    case MobilizerKind::kCylindrical:
      q[0] = angle_z(R_FM);
      q[1] = p_FM_F(2);
      u[0] = w_FM_F(2);
      u[1] = p_dot_FM_F(2);
      break;
    case MobilizerKind::kUniversal: {
      // ψ1: the angle about z from C z to R_FM z (both ⊥ z); then R_z(ψ2) = Cᵀ R_z(−ψ1) R_FM.
      // u from w_FM_F = z ψ̇1 + a ψ̇2 with a ⊥ z unit: ψ̇1 = z·w, ψ̇2 = a·w.
      const Eigen::Vector3d c = m.C.col(2);
      const Eigen::Vector3d d = R_FM.col(2);
      q[0] = std::atan2(c.cross(d).z(), c.x() * d.x() + c.y() * d.y());
      const Eigen::Matrix3d R1 = rotation_z(q[0]);
      q[1] = angle_z(m.C.transpose() * R1.transpose() * R_FM);
      u[0] = w_FM_F(2);
      u[1] = (R1 * c).dot(w_FM_F);
      break;
    }
    case MobilizerKind::kFixed:
      break;
  }
}

}  // namespace flexref::constraint
