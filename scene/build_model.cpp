#include "scene/build_model.hpp"

#include <cmath>
#include <memory>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "constraint/ideal_joints.hpp"
#include "core/gravity.hpp"
#include "rotation/euler_parameters.hpp"

namespace flexref::scene {
namespace {

core::Body build_body(const BodySpec& spec) {
  const core::RigidBodyDescription& d = spec.description;
  try {
    return core::Body(d);
  } catch (const core::InertiaRangeError&) {
    // The reference-point data core::Body derives (1/m, the parallel-axis shift to the pivot and
    // the inverse) can overflow for extreme but finite input. When the inertia about the centre
    // of mass and the mass are representable themselves, the shift m |c − pivot|² is what
    // overflows: report it at the farther of the centre of mass and the pivot.
    const Eigen::Matrix3d I_inverse = d.I_Bcm_B.inverse();
    const bool own_data_fine = std::isfinite(1.0 / d.mass) && d.I_Bcm_B.allFinite() &&
                               I_inverse.allFinite() && !d.flexible;
    const bool shifted = d.motion != core::MotionKind::kFree;
    if (own_data_fine && shifted) {
      const bool pivot_body = d.motion == core::MotionKind::kPivot;
      const Eigen::Vector3d p_BoBr_B = pivot_body ? d.p_BoPivot_B : Eigen::Vector3d::Zero();
      const double distance = (d.p_BoBcm_B - p_BoBr_B).stableNorm();
      const char* point = pivot_body ? "pivot" : "frame origin";
      std::ostringstream why;
      why.precision(3);
      why << "the inertia about the " << point << ", m d^2 with m = " << d.mass
          << " kg and d = " << distance << " m (the centre of mass from the " << point
          << "), or its inverse is not finite (too large for double precision)";
      // The factor that brings most of the orders of magnitude of m d^2.
      std::string key = "mass";
      if (!(std::abs(std::log10(d.mass)) > 2.0 * std::abs(std::log10(distance)))) {
        key = d.p_BoBcm_B.stableNorm() >= p_BoBr_B.stableNorm() ? "center_of_mass" : "pivot";
      }
      throw SpecError(spec.source, key, why.str());
    }
    throw SpecError(spec.source, "inertia",
                    std::string("the inertia about the ") +
                        (d.motion == core::MotionKind::kPivot ? "pivot" : "centre of mass") +
                        " or its inverse is not finite (values too large or too small)");
  } catch (const std::exception& e) {
    // Flexible bodies: everything but the undeformed inertia of a free or pivot body (a beam
    // without hub has none about its axis) is checked by the reader; a hub with mass has an
    // inertia key, a hub without mass has none.
    if (d.flexible) throw SpecError(spec.source, d.mass > 0.0 ? "inertia" : "mass", e.what());
    throw SpecError(spec.source, "", e.what());
  }
}

/// m_eff of a contact without one: the mass of the pairs' body shared by the pairs, reduced
/// with the other body's for a sphere–sphere pair (docs/contact.md).
double default_effective_mass(const ContactSpec& spec, const std::vector<core::Body>& bodies) {
  const contact::ContactPair& p = spec.pairs.front();
  double mass = bodies[static_cast<std::size_t>(p.body_b)].mass();
  if (p.body_a >= 0) {
    const double m_a = bodies[static_cast<std::size_t>(p.body_a)].mass();
    mass = mass * m_a / (mass + m_a);
  }
  return mass / static_cast<double>(spec.pairs.size());
}

/// The node attachment of a body point: Φ_k of the built body's modal data for a node, none
/// for a point of the rigid part (node = −1).
core::NodeAttachment attachment(const std::vector<core::Body>& bodies, int body, int node,
                                const SpecSource& source, const char* key) {
  if (node < 0) return {};
  const core::Body& b = bodies[static_cast<std::size_t>(body)];
  if (!b.is_flexible()) throw SpecError(source, key, "the body is not flexible");
  try {
    return core::NodeAttachment::of_node(b.description().flexible->modal, node);
  } catch (const std::invalid_argument& e) {
    throw SpecError(source, key, e.what());
  }
}

/// A unit vector perpendicular to the unit vector z (z × the axis z is least aligned with).
Eigen::Vector3d perpendicular_to(const Eigen::Vector3d& z) {
  Eigen::Index k = 0;
  z.cwiseAbs().minCoeff(&k);
  return z.cross(Eigen::Vector3d::Unit(k)).normalized();
}

/// An end's initial pose: the body's attitude R_WB and the end point in the world (the node
/// displaced by Φ_k q0), from the scene's initial state; the ground's identity and its point.
struct EndPose {
  Eigen::Matrix3d R_WB = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_WP = Eigen::Vector3d::Zero();
};

EndPose initial_pose(const constraint::JointEnd& end, const std::vector<core::Body>& bodies) {
  EndPose pose;
  if (end.body == constraint::kGround) {
    pose.p_WP = end.p_BoP_B;
    return pose;
  }
  const core::RigidBodyDescription& d = bodies[static_cast<std::size_t>(end.body)].description();
  pose.R_WB = rotation::rotation_matrix(d.initial.theta_WB.normalized());
  Eigen::Vector3d x = end.p_BoP_B;
  if (end.node >= 0 && d.flexible && d.flexible->q0.size() == end.phi_B.cols()) {
    x += end.phi_B * d.flexible->q0;
  }
  pose.p_WP = d.initial.p_WBo + pose.R_WB * x;
  return pose;
}

/// The ideal joints of the spec with their ends' frames, node rows, drive offsets and default
/// lengths formed from the bodies' initial state (constraint/ideal_joint.hpp).
std::unique_ptr<const core::ConstraintEquations> build_ideal_joints(
    const SceneSpec& spec, const std::vector<core::Body>& bodies,
    core::FlexibleFormulation formulation) {
  std::vector<constraint::IdealJointSpec> joints;
  for (const IdealJointSceneSpec& j : spec.ideal_joints) {
    constraint::IdealJointSpec joint = j.joint;
    for (constraint::JointEnd* end : {&joint.a, &joint.b}) {
      if (end->node < 0) continue;
      const core::Body& b = bodies[static_cast<std::size_t>(end->body)];
      const char* key = end == &joint.a ? "node_a" : "node_b";
      if (formulation == core::FlexibleFormulation::kLte) {
        throw SpecError(j.source, key,
                        "an ideal joint at a node of a flexible body needs the coupled model (the "
                        "LTE model has no elastic feedback on the rigid motion); use --model "
                        "coupled or join the body at its hub");
      }
      end->phi_B = b.description().flexible->modal.mode_rows(end->node);
    }
    const EndPose a = initial_pose(joint.a, bodies);
    const EndPose b = initial_pose(joint.b, bodies);
    // End frames: z the given axes; X_b any perpendicular; X_a the same world direction seen
    // from body a (projected off Z_a), so that the frames coincide when the joint is assembled.
    Eigen::Matrix3d R_b;
    const Eigen::Vector3d z_b = j.axis_b;
    const Eigen::Vector3d x_b = perpendicular_to(z_b);
    R_b << x_b, z_b.cross(x_b), z_b;
    const Eigen::Vector3d z_a = j.axis_a;
    Eigen::Vector3d x_a = a.R_WB.transpose() * (b.R_WB * x_b);
    x_a -= x_a.dot(z_a) * z_a;
    x_a = x_a.norm() > 1e-6 ? Eigen::Vector3d(x_a.normalized()) : perpendicular_to(z_a);
    Eigen::Matrix3d R_a;
    R_a << x_a, z_a.cross(x_a), z_a;
    joint.a.R_BJ = R_a;
    joint.b.R_BJ = R_b;
    const Eigen::Vector3d d = a.p_WP - b.p_WP;
    if (joint.type == constraint::JointType::kDistance && !j.length_given) {
      joint.length = d.norm();
      if (!(joint.length > 0.0)) {
        throw SpecError(j.source, "length",
                        "the two points coincide initially; give the rod's length");
      }
    }
    if (joint.drive.active && joint.type == constraint::JointType::kPrismatic) {
      joint.drive.offset = d.dot(b.R_WB * z_b);
    }
    joints.push_back(std::move(joint));
  }
  try {
    return std::make_unique<constraint::IdealJoints>(std::move(joints),
                                                     static_cast<int>(bodies.size()));
  } catch (const std::invalid_argument& e) {
    throw SpecError(spec.ideal_joints.front().source, "", e.what());
  }
}

/// The element built from one table, labelled as messages name it (ForceElement::label).
template <class Element>
std::unique_ptr<const core::ForceElement> labelled(std::unique_ptr<Element> element,
                                                   const SpecSource& source,
                                                   const std::string& kind,
                                                   const std::string& name) {
  element->set_label(element_label(source, kind, name));
  return element;
}

}  // namespace

std::string element_label(const SpecSource& source, const std::string& kind,
                          const std::string& name) {
  return name.empty() ? source.path : kind + " '" + name + "'";
}

void regenerate_beam_modes(BodySpec& body) {
  if (!body.beam) throw std::invalid_argument("body " + body.description.name + " has no beam");
  const BeamSpec& beam = *body.beam;
  flexible::ModalData data = flexible::make_beam_modal_data(
      beam.parameters, beam.modes, beam.filter, flexible::BeamModeNormalization::kUnitModalMass,
      beam.geometric_stiffening);
  if (beam.damping_ratio.size() == 1) {
    data.damping_ratio.setConstant(data.mode_count(), beam.damping_ratio(0));
  } else if (beam.damping_ratio.size() == data.mode_count()) {
    data.damping_ratio = beam.damping_ratio;
  } else if (beam.damping_ratio.size() != 0) {
    throw std::invalid_argument("body " + body.description.name + ": " +
                                std::to_string(beam.damping_ratio.size()) + " damping ratios for " +
                                std::to_string(data.mode_count()) + " modes");
  }
  std::optional<core::FlexiblePart>& part = body.description.flexible;
  if (!part) part.emplace();
  const Eigen::Index n = data.mode_count();
  if (part->q0.size() != n) part->q0.resize(0);
  if (part->qd0.size() != n) part->qd0.resize(0);
  part->modal = std::move(data);
}

std::unique_ptr<const core::ForceElement> build_contact(const ContactSpec& spec,
                                                        const std::vector<core::Body>& bodies) {
  const double m_eff = spec.effective_mass > 0.0
                           ? spec.effective_mass
                           : (spec.gap ? bodies[static_cast<std::size_t>(spec.gap->body)].mass()
                                       : default_effective_mass(spec, bodies));
  const ContactLawSpec& l = spec.law;
  std::optional<contact::NormalLaw> law;
  try {
    if (l.linear) {
      law = l.damping ? contact::NormalLaw::linear(l.stiffness, *l.damping)
                      : contact::NormalLaw::linear_from_restitution(
                            l.stiffness, l.restitution.value_or(0.5), m_eff);
    } else {
      law = contact::NormalLaw::hunt_crossley(l.stiffness, l.exponent, l.restitution.value_or(0.5),
                                              l.reference_speed);
    }
  } catch (const std::exception& e) {
    // Every parameter is checked by the reader; what remains are extreme values (a restitution
    // of 1e-320) for which the law's damping cannot be computed.
    throw SpecError(spec.source, l.restitution ? "restitution" : "stiffness",
                    std::string("cannot build the contact law: ") + e.what() +
                        "; expected less extreme law parameters");
  }
  try {
    if (spec.gap) {
      const GapSupportSpec& g = *spec.gap;
      return labelled(
          std::make_unique<contact::GapSupport>(
              g.body, g.p_BoN_B, attachment(bodies, g.body, g.node, spec.source, "node"),
              g.geometry, *law, spec.friction, m_eff, spec.name, spec.wear),
          spec.source, "contact", spec.name);
    }
    std::vector<contact::ContactPair> pairs = spec.pairs;
    for (contact::ContactPair& p : pairs) {
      p.node_a = attachment(bodies, p.body_a, p.node_a.node, spec.source, "node");
      p.node_b = attachment(bodies, p.body_b, p.node_b.node, spec.source,
                            p.body_a >= 0 ? "node_b" : "node");
    }
    return labelled(std::make_unique<contact::ContactElement>(std::move(pairs), *law, spec.friction,
                                                              m_eff, spec.name, spec.wear),
                    spec.source, "contact", spec.name);
  } catch (const std::invalid_argument& e) {
    throw SpecError(spec.source, std::string(e.what()).starts_with("wear law") ? "wear" : "",
                    e.what());
  }
}

std::vector<SpecSource> element_sources(const SceneSpec& spec) {
  // The order of build_model below.
  std::vector<SpecSource> sources;
  if (!spec.g_W.isZero(0.0)) sources.push_back({spec.file, 0, "scene"});
  for (const LoadSpec& l : spec.loads) sources.push_back(l.source);
  for (const PotentialSpec& p : spec.potentials) sources.push_back(p.source);
  for (const ContactSpec& c : spec.contacts) sources.push_back(c.source);
  for (const JointSpec& j : spec.joints) sources.push_back(j.source);
  for (const SpringSpec& s : spec.springs) sources.push_back(s.source);
  return sources;
}

core::Model build_model(const SceneSpec& spec, core::FlexibleFormulation formulation,
                        const std::vector<int>& independent_rows) {
  std::vector<core::Body> bodies;
  bodies.reserve(spec.bodies.size());
  for (const BodySpec& b : spec.bodies) bodies.push_back(build_body(b));

  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  if (!spec.g_W.isZero(0.0)) {
    // Flexible bodies take their gravity loads from the inertia invariants (m g, s̃_t Aᵀ g,
    // Sᵀ Aᵀ g; core/gravity_impl.hpp); the mass and centre given here are used for rigid bodies.
    std::vector<core::UniformGravity::BodyMass> masses;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      masses.push_back({static_cast<int>(i), bodies[i].mass(), bodies[i].description().p_BoBcm_B});
    }
    elements.push_back(std::make_unique<core::UniformGravity>(spec.g_W, std::move(masses)));
  }
  for (const LoadSpec& l : spec.loads) {
    if (l.torque) {
      elements.push_back(
          labelled(std::make_unique<core::AppliedTorque>(l.body, l.value, l.frame, l.profile),
                   l.source, "load", ""));
    } else {
      elements.push_back(labelled(std::make_unique<core::AppliedForce>(
                                      l.body, l.value, l.frame, l.p_BoP_B, l.profile,
                                      attachment(bodies, l.body, l.node, l.source, "node")),
                                  l.source, "load", ""));
    }
  }
  for (const PotentialSpec& p : spec.potentials) {
    elements.push_back(
        labelled(std::make_unique<core::PointChargePotential>(p.alpha, p.beta, p.p_WM, p.charges),
                 p.source, "potential", ""));
  }
  for (const ContactSpec& c : spec.contacts) elements.push_back(build_contact(c, bodies));
  for (const JointSpec& j : spec.joints) {
    try {
      if (j.revolute) {
        elements.push_back(
            labelled(std::make_unique<contact::RevoluteBushing>(j.a, j.b, j.parameters), j.source,
                     "joint", j.name));
      } else {
        elements.push_back(
            labelled(std::make_unique<contact::SphericalBushing>(j.a, j.b, j.parameters), j.source,
                     "joint", j.name));
      }
    } catch (const std::invalid_argument& e) {
      throw SpecError(j.source, "", e.what());
    }
  }
  for (const SpringSpec& sp : spec.springs) {
    try {
      elements.push_back(labelled(std::make_unique<contact::SpringDamper>(
                                      sp.body_a, sp.point_a, sp.body_b, sp.point_b, sp.parameters),
                                  sp.source, "spring", sp.name));
    } catch (const std::invalid_argument& e) {
      throw SpecError(sp.source, "", e.what());
    }
  }
  if (spec.ideal_joints.empty()) {
    return core::Model(std::move(bodies), std::move(elements), formulation);
  }
  std::unique_ptr<const core::ConstraintEquations> joints =
      build_ideal_joints(spec, bodies, formulation);
  core::ConstraintOptions options;
  options.project_initial_state = spec.project_initial_state;
  options.independent_rows = independent_rows;
  try {
    return core::Model(std::move(bodies), std::move(elements), formulation, std::move(joints),
                       options);
  } catch (const core::InconsistentInitialStateError& e) {
    throw SpecError(spec.ideal_joints[static_cast<std::size_t>(e.joint())].source, "", e.what());
  } catch (const core::JointDataError& e) {
    const IdealJointSceneSpec& j = spec.ideal_joints[static_cast<std::size_t>(e.joint())];
    const bool node = (e.end() == 0 ? j.joint.a.node : j.joint.b.node) >= 0;
    throw SpecError(j.source, std::string(node ? "node_" : "point_") + (e.end() == 0 ? "a" : "b"),
                    e.what());
  } catch (const core::SingularConfigurationError& e) {
    for (const IdealJointSceneSpec& j : spec.ideal_joints) {
      if (j.joint.name == e.joint()) throw SpecError(j.source, "", e.what());
    }
    throw SpecError(spec.ideal_joints.front().source, "", e.what());
  }
}

}  // namespace flexref::scene
