#pragma once
/// \file joint_check.hpp
/// The last line of defence of a jointed solution: every output row's violation of every joint
/// row — the rows set aside as redundant included — against a bound the solution's own
/// tolerance implies (docs/joints.md, "What a jointed solution promises"). A reference or a run
/// beyond it is not written as a success: the caller stops with the breach (which joint, when,
/// how far, and why), exit 3.
#include <optional>
#include <string>

#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::core {

/// How far past the tolerance a joint may drift before the solution contradicts it. A solver
/// that keeps its local errors below rtol per step leaves a position error of a few hundred rtol
/// over the horizons it is used on (the references' estimated errors, docs/references.md), and
/// the joints are functions of the positions with unit slope in the relative measure (length
/// rows by the joints' length scale, rotation rows as sines): 1e3 leaves a factor ~10 above the
/// worst drift measured on the bundled jointed scenes at rtol 1e-6 … 1e-12 (docs/joints.md), and
/// is still ~1e-7 relative at the default rtol 1e-10 — where a joint set aside at a singular
/// start or an inconsistent one comes apart by its own size.
inline constexpr double kJointDriftFactor = 1e3;
/// The velocity rows' factor: under Baumgarte stabilization (the index-1 references but IDA and
/// CVODE's BDF) the rates' local errors accumulate at the velocity level over 1/α, α the slowest
/// rate the solution resolves, before the positions see them: measured up to 4.6e3 rtol on the
/// Bricard linkage (CVODE Adams, rtol 1e-8 … 1e-11, at t ≈ 1.2 s where its set-aside row's share
/// in the dependency is smallest), 12 rtol elsewhere. 1e4 is still 1e-6 relative at the default
/// rtol 1e-10.
inline constexpr double kJointRateDriftFactor = 1e4;
/// The bound's floor: the round-off of Φ itself (a sum of products of lengths of size ℓ, a few
/// ε relative) times the same drift factor and a further 10 for the velocity rows' rates.
inline constexpr double kJointRoundoffFloor = 1e4 * 2.220446049250313e-16;

/// The largest relative violation of the position rows a solution computed at relative
/// tolerance `rtol` (and absolute tolerance `atol` on components of size ~ℓ, the joints' length
/// scale) may have; its velocity rows may have kJointRateDriftFactor / kJointDriftFactor times
/// more.
double joint_violation_bound(double rtol, double atol, double length_scale);

/// A row of an output that violates a joint beyond the bound.
struct JointBreach {
  std::string joint;       ///< the joint's name
  double t = 0.0;          ///< the output time, s
  bool velocity = false;   ///< the velocity rows J v + Φ_t (else the position rows Φ)
  double relative = 0.0;   ///< the relative violation
  double absolute = 0.0;   ///< |Φ| (m for a length row, the sine of an angle for a rotation row)
                           ///< or |J v + Φ_t| (m/s or rad/s)
  bool length = true;      ///< a length row (else a rotation row)
  double bound = 0.0;      ///< the bound it exceeds
  bool redundant = false;  ///< the row was set aside as redundant at t = 0
  /// The rows' rank at the breach and at t = 0: a rank that grew means the rows set aside are
  /// independent of the enforced ones there (rows lost: the mechanism started at, or passed, a
  /// singular configuration).
  int rank = 0;
  int rank0 = 0;
  /// "joint 'guide' violated by 0.075 m (relative 0.17, bound 1e-07) at t = 0.1 s: …why".
  std::string describe() const;
};

/// The first output row whose joints are violated beyond `bound` (relative; the position rows,
/// and unless `velocities` is false the velocity rows beyond bound × kJointRateDriftFactor /
/// kJointDriftFactor), or nothing. Evaluates every row at every
/// output state. Allocates.
std::optional<JointBreach> find_joint_breach(const Model& model, const Trajectory& trajectory,
                                             double bound, bool velocities = true);

}  // namespace flexref::core
