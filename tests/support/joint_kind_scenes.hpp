#pragma once
/// \file joint_kind_scenes.hpp
/// One scene per ideal-joint kind (docs/joints.md, "Ideal joints"), written as scene text so
/// that build_model forms the joint frames as for a user's file, each with an oracle that does
/// not use flexref's constrained solve:
///
///   prismatic          a body sliding freely down an inclined guide under gravity: uniform
///                      acceleration (g·u) u along the guide, no rotation, the reaction −m g⊥
///                      and the torque (p_C − p_P) × f that keeps it from turning (closed form).
///   driven_prismatic   the same guide driven by the Kane–Ryan–Banerjee law s(t): the position
///                      is the law, the force m (s̈ u − g) (the drive's share m s̈ − m g·u).
///   cylindrical        a body spinning at constant rate ω about a vertical guide that is not a
///                      principal axis and misses its centre of mass, while it falls along it:
///                      the spin stays constant (no moment about the axis), the centre of mass
///                      circles the axis (force −m ω² ρ), the torque about it is ω × (I_W ω).
///   universal          a Hooke joint between two shafts at β = 30°, the input driven at Ω:
///                      tan φ2 = cos β tan φ1 for yokes perpendicular at φ1 = φ2 = 0, and the
///                      driving torque from the power balance Ω τ = d/dt(½ I2 φ̇2²).
///   fixed              two bodies welded and tumbling under gravity: the merged rigid body
///                      (combined mass, centre of mass and inertia, parallel-axis theorem) in
///                      free fall, its rotation the exact torque-free motion
///                      (reference::TorqueFreeExact, Euler–Poinsot); the weld's reaction from
///                      the first body's Newton–Euler equations along that motion.
///   distance           a spherical pendulum on a massless rod: the point-mass equation
///                      r̈ = g − (r·g + |ṙ|²) r / L² (the rod's tension T = m (r·g + |ṙ|²)/L
///                      from d²|r|²/dt² = 0) integrated by RKF7(8) at 1e-13 (Boost.Odeint).
///   driven_revolute    a rod on a horizontal hinge driven by the spin-up law under gravity,
///                      with products of inertia about the hinge axis: the bearing's force
///                      m (a_C − g) and torque I_P α + ω × (I_P ω) − (p_C − p_P) × m g about
///                      the hinge (Euler's equations about a fixed point).
///
/// Each oracle gives, at the output times, every body's centre of mass, velocity, attitude and
/// angular velocity (world) and expected values of the joint's output columns (`J.fx … J.tz`).
/// Header-only; needs flexref::reference (the torque-free solution) and Boost.Odeint.
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <array>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "reference/exact_torque_free.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::testing {

/// A body's motion as an oracle knows it, world frame (C its centre of mass).
struct OracleBody {
  Eigen::Vector3d p_WC = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_WC = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity();
  Eigen::Vector3d w_W = Eigen::Vector3d::Zero();
};

/// The oracle at one output time: the scene's bodies in order, and expected values of output
/// columns by name (reaction forces `J.f?` in N, torques `J.t?` in N·m).
struct OracleSample {
  std::vector<OracleBody> bodies;
  std::vector<std::pair<std::string, double>> columns;
};

struct JointKindScene {
  std::string kind;    ///< the joint kind the scene exercises
  std::string oracle;  ///< what the oracle is
  std::string toml;    ///< the scene file's text
  double end_time = 1.0;
  double output_step = 0.01;
  /// Scales of the motion for the tolerances: lengths (m), speeds (m/s), the fastest rate of
  /// the motion (1/s: angular rates and the frequency of the drive law), forces (N), torques
  /// (N·m).
  double length = 1.0, speed = 1.0, rate = 1.0, force = 1.0, torque = 1.0;
  std::function<std::vector<OracleSample>(const std::vector<double>&)> oracle_at;
};

namespace joint_scene_detail {

inline std::string number(double x) {
  std::ostringstream o;
  o.precision(17);
  o << std::showpoint << x;
  return o.str();
}

inline std::string vector(const Eigen::Vector3d& v) {
  return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]";
}

inline Eigen::Matrix3d rotation(const Eigen::Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

/// A free rigid body's [[body]] table from its centre-of-mass motion (the file gives the frame
/// origin Bo and its velocity, and ω̄ in the body frame).
struct SceneBody {
  std::string name;
  double mass = 1.0;
  Eigen::Matrix3d I_C_B = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_BoC_B = Eigen::Vector3d::Zero();
  OracleBody initial;

  std::string toml() const {
    const Eigen::Matrix3d& R = initial.R_WB;
    const Eigen::Vector3d p_WBo = initial.p_WC - R * p_BoC_B;
    const Eigen::Vector3d v_WBo = initial.v_WC + initial.w_W.cross(p_WBo - initial.p_WC);
    const rotation::EulerParameters theta = rotation::euler_parameters_from_matrix(R);
    std::string inertia = "[";
    for (int r = 0; r < 3; ++r) {
      inertia += vector(I_C_B.row(r).transpose()) + (r < 2 ? ", " : "]");
    }
    return "[[body]]\nname = \"" + name + "\"\nmass = " + number(mass) + "\ninertia = " + inertia +
           "\ncenter_of_mass = " + vector(p_BoC_B) + "\nposition = " + vector(p_WBo) +
           "\norientation = [" + number(theta(0)) + ", " + number(theta(1)) + ", " +
           number(theta(2)) + ", " + number(theta(3)) + "]\nvelocity = " + vector(v_WBo) +
           "\nangular_velocity = " + vector(R.transpose() * initial.w_W) + "\n";
  }
  /// A point given in the world at the initial pose, in the body frame from Bo.
  Eigen::Vector3d point(const Eigen::Vector3d& p_W) const {
    return initial.R_WB.transpose() * (p_W - initial.p_WC) + p_BoC_B;
  }
  Eigen::Vector3d axis(const Eigen::Vector3d& u_W) const { return initial.R_WB.transpose() * u_W; }
};

inline std::string header(const std::string& name, double end_time, double output_step,
                          const Eigen::Vector3d& g_W) {
  return "[scene]\nname = \"" + name + "\"\nend_time = " + number(end_time) +
         "\noutput_step = " + number(output_step) + "\ngravity = " + vector(g_W) + "\n";
}

inline std::string joint(const std::string& name, const std::string& kind, const std::string& a,
                         const Eigen::Vector3d& point_a, const std::string& b,
                         const Eigen::Vector3d& point_b, const std::string& extra) {
  return "[[joint]]\nname = \"" + name + "\"\nmodel = \"ideal\"\nkind = \"" + kind +
         "\"\nbody_a = \"" + a + "\"\npoint_a = " + vector(point_a) + "\nbody_b = \"" + b +
         "\"\npoint_b = " + vector(point_b) + "\n" + extra;
}

inline std::string axes(const Eigen::Vector3d& axis_a, const Eigen::Vector3d& axis_b) {
  return "axis_a = " + vector(axis_a) + "\naxis_b = " + vector(axis_b) + "\n";
}

/// The six reaction columns of joint J: (f, τ).
inline void add_reaction(OracleSample& s, const std::string& joint, const Eigen::Vector3d& f,
                         const Eigen::Vector3d& tau) {
  const char* names[] = {".fx", ".fy", ".fz", ".tx", ".ty", ".tz"};
  for (int k = 0; k < 3; ++k) s.columns.emplace_back(joint + names[k], f(k));
  for (int k = 0; k < 3; ++k) s.columns.emplace_back(joint + names[k + 3], tau(k));
}

/// The Kane–Ryan–Banerjee spin-up law (J. Guidance 10(2), 1987; docs/design/model.md, "Rigid
/// motion modes"), written here from its formula: s = (Ω/T)[t²/2 + (T/2π)²(cos(2πt/T) − 1)]
/// for t ≤ T, Ω(t − T/2) after; its rate and acceleration by differentiation.
struct SpinUp {
  double Omega = 1.0, T = 1.0;
  std::array<double, 3> at(double t) const {
    const double w = 2.0 * std::numbers::pi / T;
    if (t >= T) return {Omega * (t - 0.5 * T), Omega, 0.0};
    return {(Omega / T) * (0.5 * t * t + (std::cos(w * t) - 1.0) / (w * w)),
            (Omega / T) * (t - std::sin(w * t) / w), (Omega / T) * (1.0 - std::cos(w * t))};
  }
};

}  // namespace joint_scene_detail

/// A slider on a prismatic guide to the ground along u = (2, 1, 2)/3, gravity −9.81 z: free
/// (driven = false: thrown up the guide at 0.5 m/s, it slides with s̈ = g·u) or driven by the
/// spin-up law to 0.8 m/s over 0.5 s. Its centre of mass is off the joint point and off its frame
/// origin, its attitude is not the world's.
inline JointKindScene prismatic_guide_scene(bool driven) {
  namespace d = joint_scene_detail;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  const Eigen::Vector3d u = Eigen::Vector3d(2.0, 1.0, 2.0) / 3.0;
  d::SceneBody slider;
  slider.name = "slider";
  slider.mass = 2.0;
  slider.I_C_B = Eigen::Vector3d(0.02, 0.03, 0.04).asDiagonal();
  slider.p_BoC_B = Eigen::Vector3d(0.05, 0.0, 0.0);
  slider.initial.R_WB = d::rotation(Eigen::Vector3d(1.0, 2.0, 3.0), 0.4);
  slider.initial.p_WC = Eigen::Vector3d(0.1, -0.2, 0.3);
  const double v0 = driven ? 0.0 : 0.5;  // the spin-up law starts at rest
  slider.initial.v_WC = v0 * u;
  const Eigen::Vector3d p_WP0 = slider.initial.p_WC + Eigen::Vector3d(0.1, -0.15, 0.2);
  const d::SpinUp law{0.8, 0.5};
  JointKindScene s;
  s.kind = driven ? "driven prismatic" : "prismatic";
  s.oracle = driven
                 ? "position = the spin-up law; force m (s'' u - g), torque (p_C - p_P) x f"
                 : "free fall along the guide: s'' = g.u; force -m g_perp, torque (p_C - p_P) x f";
  s.toml = d::header(driven ? "driven_prismatic" : "prismatic", 1.0, 0.01, g) + slider.toml() +
           d::joint("guide", "prismatic", "slider", slider.point(p_WP0), "ground", p_WP0,
                    d::axes(slider.axis(u), u) +
                        (driven ? "drive = { law = \"spin-up\", rate = 0.8, spin_up_time = 0.5 }\n"
                                : ""));
  s.length = 3.0;  // s(1) = 0.5 − 3.27 m (free), 0.6 m (driven)
  s.speed = 3.0;
  s.rate = driven ? 2.0 * std::numbers::pi / law.T : 1.0;
  s.force = slider.mass * 9.81;
  s.torque = s.force * (slider.initial.p_WC - p_WP0).norm();
  const double m = slider.mass;
  const OracleBody start = slider.initial;
  s.oracle_at = [=](const std::vector<double>& times) {
    std::vector<OracleSample> out;
    for (const double t : times) {
      double pos = v0 * t + 0.5 * g.dot(u) * t * t, vel = v0 + g.dot(u) * t, acc = g.dot(u);
      if (driven) {
        const std::array<double, 3> q = law.at(t);
        pos = q[0];
        vel = q[1];
        acc = q[2];
      }
      OracleSample sample;
      OracleBody b = start;
      b.p_WC += pos * u;
      b.v_WC = vel * u;
      sample.bodies.push_back(b);
      // Newton: m a = m g + f; the body does not turn, so the torques about C cancel:
      // τ_P + (p_P − p_C) × f = 0 (gravity acts at C).
      const Eigen::Vector3d f = m * (acc * u - g);
      d::add_reaction(sample, "guide", f, (start.p_WC - p_WP0).cross(f));
      out.push_back(std::move(sample));
    }
    return out;
  };
  return s;
}

/// A spindle on a cylindrical joint to the ground along the vertical u = z, spinning about it at
/// 6 rad/s and thrown up at 0.3 m/s under gravity −9.81 z. The axis is not a principal axis of
/// the spindle's inertia diag(0.02, 0.05, 0.06) (it is (1, 2, 2)/3 in the body frame), and the
/// centre of mass is 0.1 m off it. Neither gravity (along the axis) nor the joint (its forces
/// act on the axis, its torques across it) has a moment about the axis, and the angular
/// momentum about it is ω (u_Bᵀ I u_B + m ρ²): ω stays constant. The centre of mass circles the
/// axis while the axis point falls freely; the joint supplies the centripetal force −m ω² ρ and,
/// about the centre of mass, ω × (I_W ω) (Euler's equations with ω̇ = 0).
inline JointKindScene cylindrical_spindle_scene() {
  namespace d = joint_scene_detail;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  const Eigen::Vector3d u = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d u_B = Eigen::Vector3d(1.0, 2.0, 2.0) / 3.0;
  const double omega = 6.0, v0 = 0.3;
  const Eigen::Vector3d rho0(0.1, 0.0, 0.0);   // from the axis to the centre of mass
  const Eigen::Vector3d axis0(0.0, 0.0, 0.5);  // the axis point level with it at t = 0
  d::SceneBody spindle;
  spindle.name = "spindle";
  spindle.mass = 1.5;
  spindle.I_C_B = Eigen::Vector3d(0.02, 0.05, 0.06).asDiagonal();
  spindle.initial.R_WB = Eigen::Quaterniond::FromTwoVectors(u_B, u).toRotationMatrix();
  spindle.initial.p_WC = axis0 + rho0;
  spindle.initial.w_W = omega * u;
  spindle.initial.v_WC = v0 * u + spindle.initial.w_W.cross(rho0);
  const Eigen::Vector3d p_WP0 = axis0 + 0.2 * u;  // on the axis, 0.2 m above
  JointKindScene s;
  s.kind = "cylindrical";
  s.oracle =
      "constant spin about the guide, free fall along it, the centre of mass circling it; "
      "force -m w^2 rho, torque about C w x (I_W w)";
  s.toml = d::header("cylindrical", 1.0, 0.01, g) + spindle.toml() +
           d::joint("sleeve", "cylindrical", "spindle", spindle.point(p_WP0), "ground", p_WP0,
                    d::axes(spindle.axis(u), u));
  s.length = 5.0;  // the fall: 0.3 − 4.9 m
  s.speed = 10.0;
  s.rate = omega;
  s.force = spindle.mass * omega * omega * rho0.norm();
  s.torque = omega * omega * 0.06;
  const double m = spindle.mass;
  const Eigen::Matrix3d I_B = spindle.I_C_B;
  const OracleBody start = spindle.initial;
  s.oracle_at = [=](const std::vector<double>& times) {
    std::vector<OracleSample> out;
    for (const double t : times) {
      OracleSample sample;
      OracleBody b = start;
      const Eigen::Matrix3d turn = d::rotation(u, omega * t);
      const Eigen::Vector3d rho = turn * rho0;
      const double fall = v0 * t + 0.5 * g.dot(u) * t * t;
      const Eigen::Vector3d axis = axis0 + fall * u;
      b.R_WB = turn * start.R_WB;
      b.p_WC = axis + rho;
      b.v_WC = (v0 + g.dot(u) * t) * u + b.w_W.cross(rho);
      sample.bodies.push_back(b);
      const Eigen::Vector3d f = -m * omega * omega * rho;  // m a = m g + f, a = g − ω² ρ
      const Eigen::Matrix3d I_W = b.R_WB * I_B * b.R_WB.transpose();
      const Eigen::Vector3d tau_C = b.w_W.cross(I_W * b.w_W);  // dH/dt with ω̇ = 0
      const Eigen::Vector3d p_WP = axis + 0.2 * u;
      d::add_reaction(sample, "sleeve", f, tau_C - (p_WP - b.p_WC).cross(f));
      out.push_back(std::move(sample));
    }
    return out;
  };
  return s;
}

/// A Hooke joint: the input shaft (axis x) on a revolute joint to the ground driven at
/// Ω = 2π rad/s, the output shaft (axis e2 = (cos β, sin β, 0), β = 30°) on a revolute joint to
/// the ground, both centred at the origin, joined by a universal joint whose arms are the input's
/// z axis and, at t = 0, the output's n2 = (−sin β, cos β, 0). Gravity −9.81 z acts at the
/// shafts' centres of mass, which lie on their fixed axes: it loads the joints but does no
/// work and does not change the motion. With the input yoke
/// a = R_x(φ1) z and the output yoke b = cos φ2 n2 + sin φ2 z, a·b = 0 gives
/// tan φ2 = cos β tan φ1 (Hooke's law of the cardan joint, e.g. Wittenburg, Kinematics (2016),
/// §14.1), φ̇2 = Ω cos β / (cos² φ1 + cos² β sin² φ1); the drive's torque about x is
/// I2 φ̇2 φ̈2 / Ω, the power that changes the output's kinetic energy ½ I2 φ̇2² (the input turns
/// uniformly, the joints are ideal).
inline JointKindScene hooke_joint_scene() {
  namespace d = joint_scene_detail;
  const double Omega = 2.0 * std::numbers::pi, beta = std::numbers::pi / 6.0;
  const double cb = std::cos(beta);
  const Eigen::Vector3d e2(std::cos(beta), std::sin(beta), 0.0);
  d::SceneBody input;
  input.name = "input";
  input.mass = 1.0;
  input.I_C_B = Eigen::Vector3d(0.004, 0.01, 0.01).asDiagonal();
  input.initial.w_W = Omega * Eigen::Vector3d::UnitX();
  d::SceneBody output;
  output.name = "output";
  output.mass = 0.8;
  output.I_C_B = Eigen::Vector3d(0.003, 0.008, 0.008).asDiagonal();
  output.initial.R_WB = d::rotation(Eigen::Vector3d::UnitZ(), beta);
  output.initial.w_W = Omega * cb * e2;
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  JointKindScene s;
  s.kind = "universal";
  s.oracle = "Hooke joint: tan phi2 = cos(beta) tan phi1, drive torque I2 phi2' phi2'' / Omega";
  s.toml = d::header("hooke_joint", 1.0, 0.01, Eigen::Vector3d(0.0, 0.0, -9.81)) + input.toml() +
           output.toml() +
           d::joint("drive", "revolute", "input", zero, "ground", zero,
                    d::axes(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitX()) +
                        "drive = { law = \"constant-rate\", rate = " + d::number(Omega) + " }\n") +
           d::joint("bearing", "revolute", "output", zero, "ground", zero,
                    d::axes(Eigen::Vector3d::UnitX(), e2)) +
           d::joint("cross", "universal", "input", zero, "output", zero,
                    d::axes(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitY()));
  s.length = 1.0;
  s.speed = 1.0;
  s.rate = 2.0 * Omega;  // φ̇2 varies at twice the input's rate
  s.force = (input.mass + output.mass) * 9.81;
  const double I2 = output.I_C_B(0, 0);
  // The largest drive torque: I2 Ω² cos β sin²β (…) is below I2 Ω² = 0.12 N·m.
  s.torque = I2 * Omega * Omega;
  const OracleBody in0 = input.initial, out0 = output.initial;
  s.oracle_at = [=](const std::vector<double>& times) {
    std::vector<OracleSample> out;
    for (const double t : times) {
      const double phi1 = Omega * t;
      const double c1 = std::cos(phi1), s1 = std::sin(phi1);
      double phi2 = std::atan2(cb * s1, c1);
      phi2 += 2.0 * std::numbers::pi * std::round((phi1 - phi2) / (2.0 * std::numbers::pi));
      const double D = c1 * c1 + cb * cb * s1 * s1;
      const double w2 = Omega * cb / D;
      // φ̈2 = −Ω cos β Ḋ / D², Ḋ = −Ω (1 − cos² β) sin 2φ1.
      const double a2 = Omega * Omega * cb * (1.0 - cb * cb) * std::sin(2.0 * phi1) / (D * D);
      OracleSample sample;
      OracleBody b1 = in0, b2 = out0;
      b1.R_WB = d::rotation(Eigen::Vector3d::UnitX(), phi1);
      b2.R_WB = d::rotation(e2, phi2) * out0.R_WB;
      b2.w_W = w2 * e2;
      sample.bodies = {b1, b2};
      sample.columns.emplace_back("drive.tx", I2 * w2 * a2 / Omega);
      out.push_back(std::move(sample));
    }
    return out;
  };
  return s;
}

/// Two bodies welded by a fixed joint, tumbling under gravity −9.81 z (ω = (1.5, −2, 3) rad/s,
/// their common centre of mass thrown at (0.3, −0.2, 1) m/s), against the merged body: mass
/// m_a + m_b, centre of mass C, inertia Σ R_i I_i R_iᵀ + m_i (|d_i|² 1 − d_i d_iᵀ) about C
/// (d_i = C_i − C), whose attitude is the exact torque-free motion and whose C falls freely.
inline JointKindScene welded_pair_scene() {
  namespace d = joint_scene_detail;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  d::SceneBody a, b;
  a.name = "a";
  a.mass = 1.0;
  a.I_C_B = Eigen::Vector3d(0.01, 0.02, 0.025).asDiagonal();
  a.initial.R_WB = d::rotation(Eigen::Vector3d::UnitZ(), 0.3);
  b.name = "b";
  b.mass = 0.6;
  b.I_C_B = Eigen::Vector3d(0.004, 0.006, 0.009).asDiagonal();
  b.initial.R_WB = d::rotation(Eigen::Vector3d(1.0, 1.0, 0.0), 0.7);
  b.initial.p_WC = Eigen::Vector3d(0.25, 0.1, -0.05);
  const double M = a.mass + b.mass;
  const Eigen::Vector3d C0 = (a.mass * a.initial.p_WC + b.mass * b.initial.p_WC) / M;
  const Eigen::Vector3d V(0.3, -0.2, 1.0), w(1.5, -2.0, 3.0);
  Eigen::Matrix3d I_C = Eigen::Matrix3d::Zero();
  for (d::SceneBody* x : {&a, &b}) {
    const Eigen::Vector3d r = x->initial.p_WC - C0;
    I_C += x->initial.R_WB * x->I_C_B * x->initial.R_WB.transpose() +
           x->mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
    x->initial.w_W = w;
    x->initial.v_WC = V + w.cross(r);
  }
  // The merged body's principal frame Q (a proper rotation) and moments.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> principal(I_C);
  Eigen::Matrix3d Q = principal.eigenvectors();
  if (Q.determinant() < 0.0) Q.col(2) *= -1.0;
  const Eigen::Vector3d moments = principal.eigenvalues();
  const reference::TorqueFreeExact merged(moments, rotation::euler_parameters_from_matrix(Q),
                                          Q.transpose() * w);
  const Eigen::Vector3d p_WP0 = Eigen::Vector3d(0.12, 0.06, -0.02);  // the weld point
  JointKindScene s;
  s.kind = "fixed";
  s.oracle = "the merged rigid body: free fall of C, exact torque-free rotation";
  s.toml = d::header("welded_pair", 1.0, 0.01, g) + a.toml() + b.toml() +
           d::joint("weld", "fixed", "a", a.point(p_WP0), "b", b.point(p_WP0),
                    d::axes(a.axis(Eigen::Vector3d::UnitZ()), b.axis(Eigen::Vector3d::UnitZ())));
  s.length = 1.0;
  s.speed = 10.0;  // the fall reaches 1 − 9.81 m/s
  s.rate = w.norm();
  s.force = b.mass * w.squaredNorm() * 0.3;  // the centripetal pull between the parts
  s.torque = w.squaredNorm() * 0.025;
  const OracleBody a0 = a.initial, b0 = b.initial;
  const double m_a = a.mass;
  const Eigen::Matrix3d I_a = a.I_C_B;
  const Eigen::Vector3d point_a = a.point(p_WP0);
  s.oracle_at = [=](const std::vector<double>& times) {
    std::vector<OracleSample> out;
    for (const double t : times) {
      const reference::RigidAttitude att = merged.at(t);
      const Eigen::Matrix3d R_P = rotation::rotation_matrix(att.theta);
      const Eigen::Matrix3d R_rel = R_P * Q.transpose();
      const Eigen::Vector3d w_W = R_P * att.w_B;
      // Euler's equations of the merged body, principal axes: Λ ω̇ = −ω × Λ ω.
      const Eigen::Vector3d Lw = moments.cwiseProduct(att.w_B);
      const Eigen::Vector3d alpha_W = R_P * (-att.w_B.cross(Lw)).cwiseQuotient(moments);
      const Eigen::Vector3d C = C0 + V * t + 0.5 * g * t * t;
      OracleSample sample;
      for (const OracleBody* x0 : {&a0, &b0}) {
        OracleBody x;
        x.R_WB = R_rel * x0->R_WB;
        x.p_WC = C + R_rel * (x0->p_WC - C0);
        x.v_WC = V + g * t + w_W.cross(x.p_WC - C);
        x.w_W = w_W;
        sample.bodies.push_back(x);
      }
      // Body a's Newton–Euler equations along the merged motion: the weld supplies what
      // gravity does not.
      const OracleBody& xa = sample.bodies[0];
      const Eigen::Vector3d r = xa.p_WC - C;
      const Eigen::Vector3d f = m_a * (alpha_W.cross(r) + w_W.cross(w_W.cross(r)));
      const Eigen::Matrix3d I_W = xa.R_WB * I_a * xa.R_WB.transpose();
      const Eigen::Vector3d tau_C = I_W * alpha_W + w_W.cross(I_W * w_W);
      const Eigen::Vector3d p_WP = xa.p_WC + xa.R_WB * point_a;  // Bo = C for body a
      d::add_reaction(sample, "weld", f, tau_C - (p_WP - xa.p_WC).cross(f));
      out.push_back(std::move(sample));
    }
    return out;
  };
  return s;
}

/// A spherical pendulum: a ball (m = 1, isotropic inertia 1e-3, not spinning) on a massless rod
/// of L = 0.8 m (a distance joint to the ground at the origin), released 60° from the downward
/// vertical with 1.5 m/s across the vertical plane, gravity −9.81 z.
inline JointKindScene spherical_pendulum_scene() {
  namespace d = joint_scene_detail;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  const double L = 0.8, theta0 = std::numbers::pi / 3.0, m = 1.0;
  d::SceneBody ball;
  ball.name = "ball";
  ball.mass = m;
  ball.I_C_B = 1e-3 * Eigen::Matrix3d::Identity();
  ball.initial.p_WC = L * Eigen::Vector3d(std::sin(theta0), 0.0, -std::cos(theta0));
  ball.initial.v_WC = Eigen::Vector3d(0.0, 1.5, 0.0);
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  JointKindScene s;
  s.kind = "distance";
  s.oracle = "point-mass spherical pendulum r'' = g - (r.g + |r'|^2) r / L^2, RKF78 at 1e-13";
  s.toml = d::header("spherical_pendulum", 1.0, 0.01, g) + ball.toml() +
           d::joint("rod", "distance", "ball", zero, "ground", zero, "");
  s.length = L;
  s.speed = 4.0;  // √(2 g L (1 + cos θ0)) + 1.5 bounds it
  s.rate = 5.0;   // speed / L
  s.force = m * (9.81 + 16.0 / L);
  s.torque = s.force * L;
  const OracleBody start = ball.initial;
  s.oracle_at = [=](const std::vector<double>& times) {
    using Vector = std::vector<double>;
    const auto rhs = [&](const Vector& y, Vector& dy, double) {
      const Eigen::Vector3d r(y[0], y[1], y[2]), v(y[3], y[4], y[5]);
      const Eigen::Vector3d a = g - (r.dot(g) + v.squaredNorm()) / (L * L) * r;
      for (int k = 0; k < 3; ++k) {
        dy[static_cast<std::size_t>(k)] = v(k);
        dy[static_cast<std::size_t>(k + 3)] = a(k);
      }
    };
    Vector y = {start.p_WC.x(), start.p_WC.y(), start.p_WC.z(),
                start.v_WC.x(), start.v_WC.y(), start.v_WC.z()};
    std::vector<OracleSample> out;
    namespace odeint = boost::numeric::odeint;
    odeint::integrate_times(
        odeint::make_controlled(1e-13, 1e-13, odeint::runge_kutta_fehlberg78<Vector>()), rhs, y,
        times.begin(), times.end(), 1e-4, [&](const Vector& x, double) {
          OracleSample sample;
          OracleBody b = start;
          b.p_WC = Eigen::Vector3d(x[0], x[1], x[2]);
          b.v_WC = Eigen::Vector3d(x[3], x[4], x[5]);
          sample.bodies.push_back(b);
          // The rod pulls the ball toward the pivot with T = m (r·g + |ṙ|²)/L; the reaction's
          // torque about the ball's point (its centre) is zero.
          const double T = m * (b.p_WC.dot(g) + b.v_WC.squaredNorm()) / L;
          d::add_reaction(sample, "rod", -T * b.p_WC / L, Eigen::Vector3d::Zero());
          out.push_back(std::move(sample));
        });
    return out;
  };
  return s;
}

/// A rod (m = 1, centre of mass 0.5 m along its x axis, products of inertia about the hinge axis)
/// on a revolute joint to the ground about the horizontal y axis at its frame origin, driven by
/// the spin-up law to 3 rad/s over 0.6 s, gravity −9.81 z.
inline JointKindScene driven_hinge_scene() {
  namespace d = joint_scene_detail;
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  d::SceneBody rod;
  rod.name = "rod";
  rod.mass = 1.0;
  rod.I_C_B << 0.01, 0.002, 0.0, 0.002, 0.08, 0.003, 0.0, 0.003, 0.08;
  rod.p_BoC_B = Eigen::Vector3d(0.5, 0.0, 0.0);
  rod.initial.p_WC = rod.p_BoC_B;  // Bo at the origin, the attitude the world's
  const d::SpinUp law{3.0, 0.6};
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY(), zero = Eigen::Vector3d::Zero();
  JointKindScene s;
  s.kind = "driven revolute";
  s.oracle = "rotation = the spin-up law; force m (a_C - g), torque I_P a + w x I_P w - r x m g";
  s.toml =
      d::header("driven_hinge", 1.0, 0.01, g) + rod.toml() +
      d::joint("hinge", "revolute", "rod", zero, "ground", zero,
               d::axes(y, y) + "drive = { law = \"spin-up\", rate = 3.0, spin_up_time = 0.6 }\n");
  s.length = 0.5;
  s.speed = 1.5;
  s.rate = 2.0 * std::numbers::pi / law.T;
  s.force = rod.mass * (9.81 + 9.0 * 0.5);
  s.torque = s.force * 0.5;
  const double m = rod.mass;
  const Eigen::Vector3d c_B = rod.p_BoC_B;
  const Eigen::Matrix3d I_P_B =
      rod.I_C_B + m * (c_B.squaredNorm() * Eigen::Matrix3d::Identity() - c_B * c_B.transpose());
  s.oracle_at = [=](const std::vector<double>& times) {
    std::vector<OracleSample> out;
    for (const double t : times) {
      const std::array<double, 3> q = law.at(t);
      OracleSample sample;
      OracleBody b;
      b.R_WB = d::rotation(y, q[0]);
      b.w_W = q[1] * y;
      const Eigen::Vector3d alpha = q[2] * y;
      const Eigen::Vector3d r = b.R_WB * c_B;  // from the hinge to C
      b.p_WC = r;
      b.v_WC = b.w_W.cross(r);
      const Eigen::Vector3d a_C = alpha.cross(r) + b.w_W.cross(b.w_W.cross(r));
      sample.bodies.push_back(b);
      // About the fixed hinge point: dH_P/dt = I_P α + ω × I_P ω = τ_hinge + r × m g.
      const Eigen::Matrix3d I_W = b.R_WB * I_P_B * b.R_WB.transpose();
      const Eigen::Vector3d tau = I_W * alpha + b.w_W.cross(I_W * b.w_W) - r.cross(m * g);
      d::add_reaction(sample, "hinge", m * (a_C - g), tau);
      out.push_back(std::move(sample));
    }
    return out;
  };
  return s;
}

/// Every scene above.
inline std::vector<JointKindScene> joint_kind_scenes() {
  return {prismatic_guide_scene(false), prismatic_guide_scene(true), cylindrical_spindle_scene(),
          hooke_joint_scene(),          welded_pair_scene(),         spherical_pendulum_scene(),
          driven_hinge_scene()};
}

}  // namespace flexref::testing
