#pragma once
/// \file mujoco_engine.hpp
/// MuJoCo through flexref's trajectory contract (docs/engines.md): the scene as MJCF
/// (mjcf_scene.hpp), `mj_step` at the fixed step, the samples read from the engine's own
/// kinematics at the output times.
///
/// Conventions checked against MuJoCo's source (2.2.2, engine_forward.c, engine_support.c):
/// - a free joint's qpos is (position of Bo, world; quaternion w, x, y, z body → world), its
///   qvel (velocity of Bo, world; angular velocity, body frame): mju_quatIntegrate multiplies
///   the quaternion on the right by exp(ω h / 2), so ω is the body-frame angular velocity;
/// - `mj_objectVelocity(mjOBJ_BODY, …)` is at the centre of mass (the inertial frame); the
///   adapter reads mjOBJ_XBODY, the body frame of origin Bo;
/// - `xfrc_applied` is a force at the centre of mass and a torque, world frame; it is set in
///   `mjcb_control`, which `mj_forwardSkip` calls at every stage with d->time at the stage's
///   time (RK4 stages at t, t + h/2, t + h/2, t + h), so time-dependent loads are evaluated
///   where the integrator asks for them, never held over a step;
/// - a non-finite or huge (> 1e10) qpos, qvel or qacc makes MuJoCo *reset the simulation to
///   its initial state* with a warning and carry on; the adapter turns that warning into a
///   solver failure (exit 3) instead of writing the restarted trajectory;
/// - warnings and errors go to flexref's messages, not to MuJoCo's MUJOCO_LOG.TXT in the
///   current directory;
/// - with ideal joints the initial joint velocities are the least-squares fit of the bodies'
///   initial velocities through MuJoCo's body Jacobians (mj_jacBody at the initial
///   configuration); the model's state is consistent with the joints, so the fit is exact to
///   round-off, and a residual above 1e-9 of the velocities' size is a failure, never a start
///   from other velocities.
#include "examples/engine_adapter/engine.hpp"
#include "examples/mujoco/mjcf_scene.hpp"

namespace flexref::engines {

class MujocoEngine final : public Engine {
 public:
  std::string program() const override { return "flexref_mujoco"; }
  std::string version() const override;
  std::vector<std::pair<std::string, std::string>> integrators() const override;
  /// --solref and --solimp (ConstraintSoftness) for the equality constraints of loops.
  void add_options(CLI::App& app) override;
  void check_mappable(const scene::Scene& scene, const std::string& integrator) const override;
  void simulate(const scene::Scene& scene, const StepPlan& plan, const std::string& integrator,
                const Recorder& record) override;

 private:
  ConstraintSoftness softness_;
  std::vector<double> solref_, solimp_;  ///< as given on the command line
};

}  // namespace flexref::engines
