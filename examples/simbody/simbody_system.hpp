#pragma once
/// \file simbody_system.hpp
/// A RigidScene as a Simbody MultibodySystem, integrated at a fixed step (docs/engines.md,
/// "Simbody"). This translation unit is compiled as C++17: Simbody 3.7's headers do not
/// compile as C++20 (their index types' operator==(int) makes C++20's rewritten comparisons
/// ambiguous), so it sees flexref only through rigid_scene.hpp.
///
/// The mapping:
/// - a free body: MobilizedBody::Free from Ground with both mobilizer frames at the world and
///   body frames, so its quaternion is the body → world attitude and its speeds are (ω, world
///   frame; velocity of Bo, world frame); a pivot body: MobilizedBody::Ball with F on Ground at
///   the pivot's world position and M on the body at the pivot, axes aligned;
/// - mass properties with the inertia shifted from the centre of mass to the body origin
///   (Simbody's MassProperties take the inertia about the body origin, flexref's about Bcm);
/// - gravity as Force::UniformGravity, the loads as one Force::Custom evaluated at every
///   stage's state and time;
/// - a Hunt–Crossley sphere on a plane as HuntCrossleyForce on a HalfSpace, with stiffness and
///   dissipation chosen so that Simbody's f = (4/3) sqrt(R) E_eff δ^1.5 (1 + 3/2 c δ̇) is
///   flexref's k δ^1.5 (1 + α δ̇) (setBodyParameters takes a modulus E and stores E^(2/3)); one
///   contact set per sphere, because HuntCrossleyForce::calcForce (Simbody 3.7) *returns* at the
///   first contact of a set whose force is not positive instead of skipping it, dropping every
///   later contact of the set;
/// - an undamped spherical bushing as Force::LinearBushing with translational stiffness k and
///   no rotational stiffness (its force −k·p_FM is flexref's k·d).
///
/// Fixed-step mode (Simbody 3.7, AbstractIntegratorRep.cpp):
/// - setFixedStepSize(h) sets the initial, minimum and maximum step to h; an error-controlled
///   integrator then accepts every step whatever its error estimate;
/// - setAllowInterpolation(false): stepTo(t) lands on t with a step instead of stepping past it
///   and returning a cubic Hermite interpolant (which adds its own O(h⁴) error at every output
///   time that is not an internal step);
/// - the accuracy (setAccuracy, default 1e-3) still matters: a step whose error estimate
///   exceeds 2^p × accuracy is not projected (its quaternions are then not renormalized), the
///   constraint tolerance defaults to accuracy/10, and Verlet iterates its velocities only to
///   min(1e-4, accuracy/10);
/// - loop closures (constraints) are projected after a step only when its error estimate is
///   within 2^p × accuracy and their violation exceeds the constraint tolerance (accuracy/10
///   by default); --constraint-tolerance projects after every step to the tolerance given
///   (docs/engines.md measures both);
/// - the attitude written is the body's rotation as Simbody computes it, from the quaternion
///   normalized internally; the stored quaternion itself may be off unit length by up to the
///   constraint tolerance between projections;
/// - at a load switch the integrator is restarted at the switch state, as an event handler
///   would: the derivative cached at the end of a step would otherwise be reused as the first
///   stage of the next one, on the wrong side of the jump.
#include <stdexcept>
#include <string>

#include "examples/engine_adapter/rigid_scene.hpp"

namespace flexref::engines {

struct SimbodyOptions {
  std::string integrator = "merson";
  double accuracy = 0.0;  ///< setAccuracy; 0: Simbody's default (1e-3)
  /// setConstraintTolerance with setProjectEveryStep(true); 0: Simbody's default (the
  /// accuracy / 10, projected only when the violation exceeds it).
  double constraint_tolerance = 0.0;
};

/// Simbody failed: at which time and step, and its message.
class SimbodyFailure : public std::runtime_error {
 public:
  SimbodyFailure(double time, long step, const std::string& what)
      : std::runtime_error(what), time_(time), step_(step) {}
  double time() const { return time_; }
  long step() const { return step_; }

 private:
  double time_;
  long step_;
};

/// The integrators run_simbody knows, with a line each; the first is the default.
std::vector<std::pair<std::string, std::string>> simbody_integrators();

/// Integrates the scene and calls `record` at every output time. Throws SimbodyFailure.
void run_simbody(const RigidScene& scene, const StepPlan& plan, const SimbodyOptions& options,
                 const Recorder& record);

}  // namespace flexref::engines
