#include "trajectory/joint_violation.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "constraint/ideal_joints.hpp"
#include "rotation/euler_parameters.hpp"
#include "trajectory/column_layout.hpp"

namespace flexref::trajectory {
namespace {

std::string three_digits(double x) {
  char text[40];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

/// Where a body's pose (and modes) sit in a table; the names of what is missing.
struct BodyColumns {
  std::array<int, 3> position{};
  std::array<int, 4> rotation{};
  std::vector<std::size_t> modes;
  std::string missing;  ///< "rod1.x..rod1.z, rod1.e0..rod1.e3"; empty when complete
};

BodyColumns body_columns(const ColumnLayout& layout, const core::Body& body) {
  BodyColumns c;
  const std::string& name = body.description().name;
  std::vector<std::string> missing;
  if (!layout.find_group(ColumnKind::position, name, c.position)) {
    missing.push_back(name + ".x.." + name + ".z");
  }
  if (!layout.find_group(ColumnKind::rotation, name, c.rotation)) {
    missing.push_back(name + ".e0.." + name + ".e3");
  }
  c.modes = layout.mode_columns(ColumnKind::mode, name);
  if (body.mode_count() > 0 && c.modes.size() != static_cast<std::size_t>(body.mode_count())) {
    missing.push_back(name + ".q1.." + name + ".q" + std::to_string(body.mode_count()));
  }
  for (const std::string& m : missing) c.missing += (c.missing.empty() ? "" : ", ") + m;
  return c;
}

/// The bodies at a joint's two ends (the ground: none).
std::vector<int> joint_bodies(const core::ConstraintEquations& constraints, int joint) {
  std::vector<int> bodies;
  const auto [first, count] = constraints.joint_rows(joint);
  for (int r = first; r < first + count; ++r) {
    for (int b : constraints.row_bodies(r)) {
      if (b >= 0 && std::find(bodies.begin(), bodies.end(), b) == bodies.end()) {
        bodies.push_back(b);
      }
    }
  }
  return bodies;
}

/// The largest distance of a body's points — centre of mass, tracked points, the ideal joints'
/// points on it — from its origin: how far its attitude error moves any of them, per radian.
double body_radius(const core::Model& model, int body) {
  const core::RigidBodyDescription& d = model.body(body).description();
  double r = d.p_BoBcm_B.norm();
  for (const core::TrackedPoint& p : d.points) r = std::max(r, p.p_BoP_B.norm());
  if (const auto* joints = dynamic_cast<const constraint::IdealJoints*>(model.constraints())) {
    for (const constraint::IdealJointSpec& j : joints->joints()) {
      if (j.a.body == body) r = std::max(r, j.a.p_BoP_B.norm());
      if (j.b.body == body) r = std::max(r, j.b.p_BoP_B.norm());
    }
  }
  return r;
}

/// The L∞ error of a comparison's quantity named `name`, or NaN when it has none.
double linf_of(const ComparisonReport& report, const std::string& name) {
  for (const QuantityError& q : report.quantities) {
    if (q.name == name) return q.norms.linf;
  }
  return std::nan("");
}

}  // namespace

std::vector<JointViolation> measure_joints(const core::Model& model, const TrajectoryTable& table) {
  std::vector<JointViolation> out;
  const core::ConstraintEquations* constraints = model.constraints();
  if (constraints == nullptr) return out;
  const ColumnLayout layout = ColumnLayout::parse(table.columns);
  const int t_column = table.column("t");
  std::vector<BodyColumns> columns;
  for (const core::Body& b : model.bodies()) columns.push_back(body_columns(layout, b));

  out.resize(static_cast<std::size_t>(constraints->joint_count()));
  std::vector<bool> bodies_needed(model.bodies().size(), false);
  for (int j = 0; j < constraints->joint_count(); ++j) {
    JointViolation& v = out[static_cast<std::size_t>(j)];
    v.name = constraints->joint_name(j);
    for (int b : joint_bodies(*constraints, j)) {
      const std::string& missing = columns[static_cast<std::size_t>(b)].missing;
      if (missing.empty()) continue;
      v.measured = false;
      v.missing += (v.missing.empty() ? "" : ", ") + missing;
    }
  }

  // The model's constraint rows at each row's poses (velocities zero: only Φ is read), the
  // bodies posed as core::Model poses them (the coupled model's q_f; LTE's undeformed body).
  core::State state = model.initial_state();
  core::Workspace ws = model.make_workspace();
  core::ConstraintRows rows;
  rows.resize(constraints->row_count(), model.velocity_layout().size());
  const bool lte = model.formulation() == core::FlexibleFormulation::kLte;
  for (const std::vector<double>& row : table.rows) {
    const double t = t_column >= 0 ? row[static_cast<std::size_t>(t_column)] : 0.0;
    for (std::size_t i = 0; i < state.size(); ++i) {
      const BodyColumns& c = columns[i];
      core::BodyState& s = state[i];
      if (c.missing.empty()) {
        const Eigen::Vector3d p_WBo(row[static_cast<std::size_t>(c.position[0])],
                                    row[static_cast<std::size_t>(c.position[1])],
                                    row[static_cast<std::size_t>(c.position[2])]);
        Eigen::Vector4d theta;
        for (std::size_t k = 0; k < 4; ++k) {
          theta(static_cast<Eigen::Index>(k)) = row[static_cast<std::size_t>(c.rotation[k])];
        }
        s.theta_WB = theta.normalized();
        const core::Body& body = model.body(static_cast<int>(i));
        s.p_WBr = p_WBo + rotation::rotation_matrix(s.theta_WB) * body.p_BoBr_B();
        for (std::size_t m = 0; m < c.modes.size() && m < static_cast<std::size_t>(s.q_f.size());
             ++m) {
          s.q_f(static_cast<Eigen::Index>(m)) = row[c.modes[m]];
        }
      }
      s.v_WBr.setZero();
      s.w_WB_B.setZero();
      s.qd_f.setZero();
      ws.kinematics[i].state = &s;
      ws.kinematics[i].R_WB = rotation::rotation_matrix(s.theta_WB);
      ws.kinematics[i].q_f = lte ? &ws.flexible[i].zero : &s.q_f;
    }
    constraints->evaluate(t, ws.kinematics, model.velocity_layout(), rows);
    for (int r = 0; r < constraints->row_count(); ++r) {
      JointViolation& v = out[static_cast<std::size_t>(constraints->joint_of_row(r))];
      if (!v.measured) continue;
      const double phi = std::abs(rows.phi(r));
      double& largest = constraints->is_length_row(r) ? v.length : v.angle;
      if (!(phi <= largest)) {  // a NaN is kept: never smaller than anything
        if (!(phi <= v.value())) v.time = t;
        largest = phi;
      }
    }
  }
  return out;
}

JointVerdict judge_joints(const core::Model& model, const std::vector<JointViolation>& run,
                          const std::vector<JointViolation>& reference,
                          const ComparisonReport& report, double noise) {
  JointVerdict verdict;
  const core::ConstraintEquations* constraints = model.constraints();
  std::ostringstream why;
  for (std::size_t j = 0; j < run.size(); ++j) {
    const JointViolation& v = run[j];
    if (!v.measured) {
      why << (verdict.off ? "; " : "") << "joint " << v.name
          << " cannot be measured: the run has no " << v.missing;
      verdict.off = true;
      continue;
    }
    double scale_length = 0.0, scale_angle = 0.0;
    for (int b : joint_bodies(*constraints, static_cast<int>(j))) {
      const std::string& name = model.body(b).description().name;
      const double e_p = linf_of(report, name + ".position");
      const double e_r = linf_of(report, name + ".rotation");
      scale_length += e_p + body_radius(model, b) * e_r;
      scale_angle += e_r;
    }
    const double ref_length = j < reference.size() ? reference[j].length : 0.0;
    const double ref_angle = j < reference.size() ? reference[j].angle : 0.0;
    const double excess_length = v.length - ref_length;
    const double excess_angle = v.angle - ref_angle;
    const bool off_length =
        !(excess_length <= std::max(kJointViolationFraction * scale_length, noise));
    const bool off_angle =
        !(excess_angle <= std::max(kJointViolationFraction * scale_angle, noise));
    if (!off_length && !off_angle) continue;
    why << (verdict.off ? "; " : "") << "joint " << v.name << " violated by ";
    if (off_length) {
      why << three_digits(v.length) << " m against an error of " << three_digits(scale_length)
          << " m at it";
    } else {
      why << three_digits(v.angle) << " rad against an error of " << three_digits(scale_angle)
          << " rad at it";
    }
    verdict.off = true;
  }
  if (verdict.off) {
    verdict.why = why.str() + " (a violation above " + three_digits(kJointViolationFraction) +
                  " of the error is not small: trajectory/joint_violation.hpp)";
  }
  return verdict;
}

std::string describe_violation(const JointViolation& joint) {
  if (!joint.measured) return joint.name + " not measured (no " + joint.missing + ")";
  return joint.name + " " + three_digits(joint.length) + " m, " + three_digits(joint.angle) +
         " rad (t = " + three_digits(joint.time) + ")";
}

}  // namespace flexref::trajectory
