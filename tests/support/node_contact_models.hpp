#pragma once
/// \file node_contact_models.hpp
/// Models with loads and contacts at the nodes of flexible bodies (core/node_attachment.hpp,
/// contact/gap_support.hpp), built in code. Header-only.
///
///   stiff_particle_body   a free flexible body: a hub (m_hub, J_hub) and one node at the frame
///                         origin with mass m_node, Φ = I₃ (the node translates relative to the
///                         hub) and modal stiffness K per direction. K → ∞ is a rigid body of
///                         mass m_hub + m_node (the rigid limit).
///   modal_oscillator_body a fixed frame (prescribed, rate 0) with one node of mass m at the
///                         origin and one mode Φ = e_z of stiffness K: q̈ + (K/m) q = Q/m.
#include <Eigen/Core>
#include <string>
#include <utility>

#include "core/body.hpp"
#include "core/node_attachment.hpp"
#include "flexible/modal_data.hpp"

namespace flexref::testing {

inline flexible::ModalData single_node_modes(double node_mass, const Eigen::MatrixXd& phi,
                                             double stiffness) {
  flexible::ModalData m;
  m.mass = Eigen::VectorXd::Constant(1, node_mass);
  m.p_BoNode_B = Eigen::Matrix3Xd::Zero(3, 1);
  m.phi = phi;
  m.stiffness = Eigen::VectorXd::Constant(phi.cols(), stiffness);
  m.damping_ratio = Eigen::VectorXd::Zero(phi.cols());
  m.node_names = {"n0"};
  return m;
}

inline core::RigidBodyDescription stiff_particle_body(std::string name, double hub_mass,
                                                      double hub_inertia, double node_mass,
                                                      double stiffness) {
  core::RigidBodyDescription d;
  d.name = std::move(name);
  d.mass = hub_mass;
  d.I_Bcm_B = Eigen::Matrix3d::Identity() * hub_inertia;
  d.flexible = core::FlexiblePart{
      single_node_modes(node_mass, Eigen::MatrixXd::Identity(3, 3), stiffness), {}, {}};
  d.points.push_back({"node", Eigen::Vector3d::Zero(), 0});
  return d;
}

inline core::RigidBodyDescription modal_oscillator_body(std::string name, double mass,
                                                        double stiffness, double qd0) {
  core::RigidBodyDescription d;
  d.name = std::move(name);
  d.mass = 0.0;
  d.I_Bcm_B.setZero();
  d.motion = core::MotionKind::kPrescribed;
  d.prescribed.axis_W = Eigen::Vector3d::UnitZ();
  d.prescribed.law.kind = core::AngleLaw::Kind::kConstantRate;
  d.prescribed.law.rate = 0.0;
  Eigen::MatrixXd phi = Eigen::MatrixXd::Zero(3, 1);
  phi(2, 0) = 1.0;
  d.flexible = core::FlexiblePart{single_node_modes(mass, phi, stiffness), Eigen::VectorXd::Zero(1),
                                  Eigen::VectorXd::Constant(1, qd0)};
  d.points.push_back({"node", Eigen::Vector3d::Zero(), 0});
  return d;
}

/// The attachment of node k of a description's modal data.
inline core::NodeAttachment node_of(const core::RigidBodyDescription& d, int node) {
  return core::NodeAttachment::of_node(d.flexible->modal, node);
}

}  // namespace flexref::testing
