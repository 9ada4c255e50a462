#pragma once
/// \file scene_spec.hpp
/// A scene as plain data: what a scene file says, validated, before any Model is built
/// (docs/design/README.md, "scene file → SceneSpec → Model"). Studies that vary a scene (the
/// LTE map's hub and spin, a stability sweep's stiffness, a modal-truncation study's mode
/// count) copy and edit a SceneSpec and call build_model; none of them edits scene text.
///
/// Every part keeps where it came from (SpecSource) so that a problem found while building
/// the model is reported at the file, line and key of the table that caused it.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "constraint/ideal_joint.hpp"
#include "contact/bushing.hpp"
#include "contact/contact.hpp"
#include "contact/contact_laws.hpp"
#include "contact/gap_support.hpp"
#include "contact/spring_damper.hpp"
#include "core/applied_load.hpp"
#include "core/body.hpp"
#include "core/point_charge_potential.hpp"
#include "core/time_profile.hpp"
#include "flexible/beam_model.hpp"

namespace flexref::scene {

/// The table a part of the scene came from; empty (line 0) for parts built in code.
struct SpecSource {
  std::string file;
  int line = 0;
  std::string path;  ///< "body[2]", "contact[1]": tables count from 1 as in the file
};

/// [body.beam]: the built-in beam finite-element model that generated a body's modes.
struct BeamSpec {
  flexible::BeamParameters parameters;
  int modes = 0;
  flexible::BeamModeFilter filter;
  /// Modal damping ratios: empty (none), one value for every mode, or one per mode.
  Eigen::VectorXd damping_ratio;
  /// `geometric_stiffening = true`: the modal data carry the beam's unit-load geometric
  /// stiffness (flexible/geometric_stiffness.hpp); clamped-free beams only.
  bool geometric_stiffening = false;
};

struct BodySpec {
  /// The body (its flexible part, when present, holds the resolved modal data and q0, qd0).
  core::RigidBodyDescription description;
  /// Where the modes came from: the beam model (regenerate_beam_modes() after editing it) or a
  /// modal-data file (resolved path); neither for a rigid body.
  std::optional<BeamSpec> beam;
  std::string modal_file;
  SpecSource source;
};

/// [[load]]: a force at a body point or a torque, with its time profile.
struct LoadSpec {
  bool torque = false;
  int body = 0;
  Eigen::Vector3d value = Eigen::Vector3d::Zero();  ///< N or N·m, in `frame`
  core::LoadFrame frame = core::LoadFrame::kWorld;
  Eigen::Vector3d p_BoP_B = Eigen::Vector3d::Zero();  ///< point of application (forces)
  /// The node of a flexible body the force acts at (−1: the body point p_BoP_B of the rigid
  /// part); build_model takes Φ_k from the built body.
  int node = -1;
  core::TimeProfile profile = core::TimeProfile::constant();
  SpecSource source;
};

/// [[potential]] kind = "point_charge" (core/point_charge_potential.hpp).
struct PotentialSpec {
  double alpha = 0.0;
  double beta = 0.0;
  Eigen::Vector3d p_WM = Eigen::Vector3d::Zero();
  std::vector<core::PointChargePotential::Charge> charges;
  SpecSource source;
};

/// The normal law of a [[contact]] table, as given (docs/contact.md).
struct ContactLawSpec {
  bool linear = false;     ///< law = "linear", else Hunt–Crossley
  double stiffness = 1e6;  ///< N/m (linear) or N/m^n
  double exponent = 1.5;   ///< Hunt–Crossley n
  /// Coefficient of restitution; absent: 0.5 for Hunt–Crossley, and for the linear law the
  /// damping below is used.
  std::optional<double> restitution;
  double reference_speed = 1.0;   ///< m/s, Hunt–Crossley
  std::optional<double> damping;  ///< N·s/m, linear law given by its damping
};

/// [[contact]] kind = "gap-support" (contact/gap_support.hpp): the support point's body and
/// node (−1: the body point p_BoN_B of the rigid part) and the support geometry.
struct GapSupportSpec {
  int body = 0;
  int node = -1;
  Eigen::Vector3d p_BoN_B = Eigen::Vector3d::Zero();
  contact::GapSupportGeometry geometry;
};

struct ContactSpec {
  /// Sphere pairs; a pair's node_a/node_b carry the node index only (−1: rigid part), and
  /// build_model fills Φ_k from the built bodies (a study may change the mode count).
  std::vector<contact::ContactPair> pairs;
  /// A gap support instead of pairs.
  std::optional<GapSupportSpec> gap;
  /// Non-empty: the contact's wear outputs are written under this name (docs/output.md).
  std::string name;
  /// The contact's wear law (docs/wear.md; a named contact only): its worn depths become states.
  std::optional<core::WearLaw> wear;
  ContactLawSpec law;
  contact::FrictionLaw friction;
  /// kg; 0: the mass of the pairs' body shared by the pairs (reduced with the other body's for
  /// sphere–sphere pairs), which build_model computes from the built bodies.
  double effective_mass = 0.0;
  SpecSource source;
};

/// [[joint]]: a spherical or revolute bushing.
struct JointSpec {
  std::string name;  ///< optional: how messages name it ("joint 'NAME'"; else "joint[k]")
  bool revolute = false;
  contact::BushingEnd a;
  contact::BushingEnd b;
  contact::BushingParameters parameters;
  SpecSource source;
};

/// [[joint]] model = "ideal" (constraint/ideal_joint.hpp) as given: the ends' bodies, points or
/// nodes and axes, the drive; build_model forms the ends' joint frames, the node rows Φ_k, the
/// drive's offset and a distance joint's default length from the bodies' initial state.
struct IdealJointSceneSpec {
  constraint::IdealJointSpec joint;
  Eigen::Vector3d axis_a = Eigen::Vector3d::UnitZ();  ///< body_a frame, unit
  Eigen::Vector3d axis_b = Eigen::Vector3d::UnitZ();  ///< body_b frame (ground: world), unit
  bool length_given = false;                          ///< distance: `length` was given
  SpecSource source;
};

/// [[spring]]: a linear spring–damper between two points (contact/spring_damper.hpp).
struct SpringSpec {
  std::string name;  ///< optional: how messages name it ("spring 'NAME'"; else "spring[k]")
  int body_a = 0;
  int body_b = contact::kGround;
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< body_a frame, from Bo
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< body_b frame, or world (ground)
  contact::SpringDamperParameters parameters;
  SpecSource source;
};

struct SceneSpec {
  std::string name;
  std::string file;          ///< path or name as given to the reader ("" when built in code)
  std::string description;   ///< optional free text
  double end_time = 0.0;     ///< s, > 0
  double output_step = 0.0;  ///< s, in (0, end_time]
  Eigen::Vector3d g_W = Eigen::Vector3d::Zero();  ///< gravity, m/s², world frame
  std::vector<BodySpec> bodies;
  std::vector<LoadSpec> loads;
  std::vector<PotentialSpec> potentials;
  std::vector<ContactSpec> contacts;
  std::vector<JointSpec> joints;
  std::vector<IdealJointSceneSpec> ideal_joints;
  std::vector<SpringSpec> springs;
  /// [scene] project_initial_state: project an initial state that violates the ideal joints
  /// by more than the accepted tolerance instead of refusing it (core::ConstraintOptions).
  bool project_initial_state = false;
};

/// Recomputes a beam body's modal data from its BeamSpec (after a study edits the beam), keeping
/// q0 and qd0 when their size still matches and dropping them otherwise. Throws
/// std::invalid_argument when the body has no beam or the beam model cannot be solved.
void regenerate_beam_modes(BodySpec& body);

}  // namespace flexref::scene
