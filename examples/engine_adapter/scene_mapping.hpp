#pragma once
/// \file scene_mapping.hpp
/// The parts of a scene every engine adapter maps the same way: which bodies and elements an
/// engine's rigid-body model can carry at all (free and pivot rigid bodies, gravity, applied
/// forces and torques), and the applied loads themselves, evaluated exactly as flexref
/// evaluates them (core/applied_load.hpp) so that the engine integrates the same model.
#include <Eigen/Core>
#include <string>

#include "examples/engine_adapter/engine.hpp"
#include "examples/engine_adapter/joint_tree.hpp"
#include "scene/scene.hpp"

namespace flexref::engines {

/// Throws MappingError for the first part of the scene no rigid-body engine adapter maps:
/// a flexible or prescribed body, a potential. `engine` names the engine in the message.
/// Contacts and joints are the engine's own decision.
void check_rigid_scene(const scene::Scene& scene, const std::string& engine);

/// The resultant of the scene's [[load]]s on body `body` at time t, with the moment taken
/// about the world point p_WR (the engine's choice: MuJoCo applies wrenches at the centre of
/// mass, Simbody at the frame origin). Piecewise profiles take their branch from t_segment, a
/// time strictly inside the current step, as flexref's integrators do
/// (core/time_profile.hpp): a step that ends on a load switch sees the left limit, the next
/// one the right limit.
LoadWrench body_load_wrench(const scene::SceneSpec& spec, int body, double t, double t_segment,
                            const LoadPose& pose, const Eigen::Vector3d& p_WR);

/// Whether the scene has a load whose profile jumps (a rectangular pulse): an engine that
/// cannot tell the two sides of a switch apart must restart its integrator there.
bool has_load_jumps(const scene::SceneSpec& spec);

/// The scene as plain data for an engine's own translation unit. Call after the engine's
/// checks: contacts become SpherePlaneInput (sphere-plane pairs with the Hunt–Crossley law),
/// bushings SpringInput (their stiffness), whatever else they say; springs LinearSpringInput;
/// ideal joints IdealJointInput placed by plan_joint_tree(scene, support) (which throws
/// MappingError for a joint the engine cannot carry). With ideal joints the bodies' initial
/// state is the model's, consistent with the joints (core::Model projects the scene's), so that
/// the engine starts on the manifold flexref's references start on.
RigidScene rigid_scene(const scene::Scene& scene, const JointSupport& support);

}  // namespace flexref::engines
