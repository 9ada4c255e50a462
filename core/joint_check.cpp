#include "core/joint_check.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flexref::core {

double joint_violation_bound(double rtol, double atol, double length_scale) {
  const double atol_relative = length_scale > 0.0 ? atol / length_scale : atol;
  return std::max(kJointDriftFactor * std::max(rtol, atol_relative), kJointRoundoffFloor);
}

std::string JointBreach::describe() const {
  std::ostringstream out;
  out.precision(3);
  out << "joint '" << joint << "' is violated " << (velocity ? "in velocity " : "") << "by "
      << absolute << " "
      << (velocity ? (length ? "m/s" : "rad/s") : (length ? "m" : "(sine of an angle)"))
      << " at t = " << t << " s (relative " << relative << ", more than the bound " << bound
      << " its tolerance allows): ";
  if (rank > rank0) {
    out << "rows lost — its constraints were set aside as dependent on the others at t = 0 (rank "
        << rank0 << ") but are independent of them here (rank " << rank
        << "): the mechanism started at or passed a singular configuration, where the motion is "
           "not determined";
  } else if (redundant) {
    out << "inconsistent joints — its rows depend on the enforced ones yet are not satisfied "
           "where those are: the joints cannot all hold together";
  } else {
    out << "the solver's drift off the joints exceeds what its tolerance allows; tighten the "
           "tolerance or use a solver that holds the joints exactly (ida, or cvode --method bdf, "
           "which projects)";
  }
  return out.str();
}

std::optional<JointBreach> find_joint_breach(const Model& model, const Trajectory& trajectory,
                                             double bound, bool velocities) {
  if (!model.has_constraints()) return std::nullopt;
  const ConstraintEquations& equations = *model.constraints();
  Workspace ws = model.make_workspace();
  const std::vector<int>& independent = model.independent_rows();
  // The velocity rows relative to the largest speed so far: a mechanism at a turning point of its
  // motion (a Bricard linkage's rods at rest for an instant) keeps the velocity errors of its
  // motion, which its instantaneous speed would magnify without bound.
  double speed = 0.0;
  for (std::size_t k = 0; k < trajectory.times.size() && k < trajectory.states.size(); ++k) {
    const double t = trajectory.times[k];
    RelativeJointViolation v = model.relative_joint_violation(t, trajectory.states[k], ws);
    if (v.speed > speed) speed = v.speed;
    if (speed > 0.0) v.velocity *= v.speed / speed;
    const bool position = v.position > bound;
    // A NaN violation is a breach too (std::max and > would let it through).
    const bool position_nan = std::isnan(v.position);
    const double rate_bound = bound * (kJointRateDriftFactor / kJointDriftFactor);
    const bool velocity = velocities && (v.velocity > rate_bound || std::isnan(v.velocity));
    if (!position && !position_nan && !velocity) continue;
    JointBreach breach;
    const bool at_position = position || position_nan;
    const int row = at_position ? v.position_row : v.velocity_row;
    breach.joint = equations.joint_name(equations.joint_of_row(row));
    breach.t = t;
    breach.velocity = !at_position;
    breach.relative = at_position ? v.position : v.velocity;
    breach.absolute = at_position ? v.position_absolute : v.velocity_absolute;
    breach.length = equations.is_length_row(row);
    breach.bound = at_position ? bound : bound * (kJointRateDriftFactor / kJointDriftFactor);
    breach.redundant = std::find(independent.begin(), independent.end(), row) == independent.end();
    breach.rank0 = static_cast<int>(independent.size());
    // The rank at the breach decided above the state's own distance from the joints: rows that
    // depend on the others on the manifold are independent by about that distance off it.
    breach.rank = model.constraint_rank(
        t, trajectory.states[k], ws,
        std::max(kRedundantRowTolerance, kJointDriftFactor * std::max(v.position, v.velocity)));
    return breach;
  }
  return std::nullopt;
}

}  // namespace flexref::core
