#pragma once

/// \file flexible_models.hpp
/// Flexible-body test problems built in code from core types (no scene files), with the
/// parameters of docs/design/scenes.md:
///
///   flexible_spinner     free rigid hub (m_h = 10, J_h = diag(0.5, 0.5, 1)) carrying a radial
///                        clamped-free beam along x from r = 0.1 to 1.1 (ρA = 1, EI = 3.2 in both
///                        planes, EA = 1e5); spin Ω0 = 1 about z; hub torque (0, 0, 5)·sin²(πt/0.5)
///                        on [0, 0.5). Modes: the lowest bending modes of both planes.
///   rotating_cantilever  the same beam clamped on a prescribed hub turning at constant Ω about z
///                        (no hub mass: the prescribed frame carries it).
///   spin_up_beam         Kane–Ryan–Banerjee: L = 10, EI = 1.4e4 (both planes), EA = 2.8e7,
///                        ρA = 1.2, clamped at the hub axis, spin-up law to Ω_s over T_s = 15.
///
/// The tracked point "tip" is the beam's last node.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/applied_load.hpp"
#include "core/body.hpp"
#include "core/model.hpp"
#include "core/time_profile.hpp"
#include "flexible/beam_model.hpp"

namespace flexref::testing {

using FlexibleElements = std::vector<std::unique_ptr<const core::ForceElement>>;

/// Bending-only modal data of a uniform clamped-free beam along x from `origin`.
inline flexible::ModalData beam_bending_modes(const Eigen::Vector3d& origin, double length,
                                              double EI, double EA, double rho_A, int elements,
                                              int modes, bool geometric_stiffening = false) {
  flexible::BeamParameters p;
  p.origin = origin;
  p.length = length;
  p.elements = elements;
  p.EA = EA;
  p.EI_y = EI;
  p.EI_z = EI;
  p.rho_A = rho_A;
  flexible::BeamModeFilter filter;
  filter.axial = false;
  return flexible::make_beam_modal_data(
      p, modes, filter, flexible::BeamModeNormalization::kUnitModalMass, geometric_stiffening);
}

/// A flexible body from modal data, with the tip node tracked.
inline core::RigidBodyDescription flexible_body(std::string name, flexible::ModalData modal) {
  core::RigidBodyDescription d;
  d.name = std::move(name);
  d.mass = 0.0;
  d.I_Bcm_B.setZero();
  // The tip: the node farthest along the beam (x).
  Eigen::Index tip_node = 0;
  modal.p_BoNode_B.row(0).maxCoeff(&tip_node);
  d.points.push_back({"tip", modal.p_BoNode_B.col(tip_node), static_cast<int>(tip_node)});
  d.flexible = core::FlexiblePart{std::move(modal), {}, {}};
  return d;
}

/// flexible_spinner with n bending modes (n even: both planes alternate) on `elements`.
inline core::Model flexible_spinner_model(core::FlexibleFormulation formulation, int modes = 4,
                                          int elements = 10, double torque_z = 5.0,
                                          bool geometric_stiffening = false) {
  core::RigidBodyDescription d =
      flexible_body("spinner", beam_bending_modes(Eigen::Vector3d(0.1, 0.0, 0.0), 1.0, 3.2, 1e5,
                                                  1.0, elements, modes, geometric_stiffening));
  d.mass = 10.0;
  d.I_Bcm_B = Eigen::Vector3d(0.5, 0.5, 1.0).asDiagonal();
  d.initial.w_WB_B = Eigen::Vector3d(0.0, 0.0, 1.0);
  d.points.push_back({"hub_rim", Eigen::Vector3d(0.0, 0.1, 0.0), -1});
  FlexibleElements elements_list;
  elements_list.push_back(std::make_unique<core::AppliedTorque>(
      0, Eigen::Vector3d(0.0, 0.0, torque_z), core::LoadFrame::kWorld,
      core::TimeProfile::sin2_pulse(0.0, 0.5)));
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  return core::Model(std::move(bodies), std::move(elements_list), formulation);
}

/// A flexible body turning at constant Ω about the world z axis (prescribed), released from q0.
inline core::Model constant_rate_model(core::RigidBodyDescription d,
                                       core::FlexibleFormulation formulation, double omega,
                                       const Eigen::VectorXd& q0 = {}) {
  d.motion = core::MotionKind::kPrescribed;
  d.prescribed.axis_W = Eigen::Vector3d::UnitZ();
  d.prescribed.law.kind = core::AngleLaw::Kind::kConstantRate;
  d.prescribed.law.rate = omega;
  d.flexible->q0 = q0;
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  return core::Model(std::move(bodies), {}, formulation);
}

/// The spinner's beam on a hub turning at constant Ω about z (prescribed), n bending modes.
inline core::Model rotating_cantilever_model(core::FlexibleFormulation formulation, double omega,
                                             int modes = 2, int elements = 10,
                                             const Eigen::VectorXd& q0 = {}) {
  return constant_rate_model(
      flexible_body("beam", beam_bending_modes(Eigen::Vector3d(0.1, 0.0, 0.0), 1.0, 3.2, 1e5, 1.0,
                                               elements, modes)),
      formulation, omega, q0);
}

/// Kane–Ryan–Banerjee spin-up beam (docs/design/scenes.md), n bending modes.
/// `geometric_stiffening`: with the beam's geometric stiffness (flexible/geometric_stiffness.hpp).
inline core::Model spin_up_beam_model(core::FlexibleFormulation formulation, double omega_s,
                                      int modes = 4, int elements = 10,
                                      bool geometric_stiffening = false) {
  core::RigidBodyDescription d =
      flexible_body("beam", beam_bending_modes(Eigen::Vector3d::Zero(), 10.0, 1.4e4, 2.8e7, 1.2,
                                               elements, modes, geometric_stiffening));
  d.motion = core::MotionKind::kPrescribed;
  d.prescribed.axis_W = Eigen::Vector3d::UnitZ();
  d.prescribed.law.kind = core::AngleLaw::Kind::kSpinUp;
  d.prescribed.law.rate = omega_s;
  d.prescribed.law.spin_up_time = 15.0;
  std::vector<core::Body> bodies;
  bodies.emplace_back(std::move(d));
  return core::Model(std::move(bodies), {}, formulation);
}

}  // namespace flexref::testing
