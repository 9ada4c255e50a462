#include "examples/mujoco/mujoco_engine.hpp"

#include <mujoco/mujoco.h>

#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <Eigen/QR>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "core/error.hpp"
#include "examples/engine_adapter/scene_mapping.hpp"
#include "examples/mujoco/mjcf_scene.hpp"

namespace flexref::engines {
namespace {

/// What mjcb_control needs: MuJoCo's callbacks are global function pointers, so the loads of
/// the one model this program runs are reached through this pointer.
struct LoadContext {
  const scene::SceneSpec* spec = nullptr;
  std::vector<int> body_ids;  ///< MuJoCo body id of each scene body
  double t_segment = 0.0;     ///< a time inside the current step (its midpoint)
};
LoadContext* g_loads = nullptr;

/// The last MuJoCo warning, reported with the failure it caused.
std::string g_last_warning;

void record_warning(const char* message) { g_last_warning = message; }

/// MuJoCo's errors end the process (its C code cannot be unwound); the message is flexref's.
void report_error(const char* message) {
  std::cerr << "flexref_mujoco: MuJoCo error: " << message << "\n";
  std::_Exit(3);
}

Eigen::Matrix3d rotation_from_rows(const mjtNum* xmat) {
  Eigen::Matrix3d R;
  R << xmat[0], xmat[1], xmat[2], xmat[3], xmat[4], xmat[5], xmat[6], xmat[7], xmat[8];
  return R;
}

/// mjcb_control: the scene's loads at this stage's time d->time, as xfrc_applied.
void apply_loads(const mjModel* m, mjData* d) {
  mju_zero(d->xfrc_applied, 6 * m->nbody);
  const LoadContext& c = *g_loads;
  for (std::size_t b = 0; b < c.body_ids.size(); ++b) {
    const int id = c.body_ids[b];
    LoadPose pose;
    pose.R_WB = rotation_from_rows(d->xmat + 9 * id);
    pose.p_WBo = Eigen::Map<const Eigen::Vector3d>(d->xpos + 3 * id);
    const Eigen::Vector3d p_WBcm = Eigen::Map<const Eigen::Vector3d>(d->xipos + 3 * id);
    const LoadWrench w =
        body_load_wrench(*c.spec, static_cast<int>(b), d->time, c.t_segment, pose, p_WBcm);
    Eigen::Map<Eigen::Vector3d>(d->xfrc_applied + 6 * id) = w.f_W;
    Eigen::Map<Eigen::Vector3d>(d->xfrc_applied + 6 * id + 3) = w.m_W;
  }
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

/// Compiles MJCF text: MuJoCo 2.2 reads models from files (or a virtual file system), so the
/// text goes through a private temporary folder that is removed again.
std::unique_ptr<mjModel, ModelDeleter> compile(const std::string& mjcf) {
  std::string pattern = (std::filesystem::temp_directory_path() / "flexref-mjcf-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) {
    throw std::runtime_error("cannot create a temporary folder for the MJCF model");
  }
  const std::filesystem::path folder(pattern);
  const std::filesystem::path file = folder / "scene.xml";
  {
    std::ofstream out(file);
    out << mjcf;
  }
  char error[1000] = "";
  mjModel* m = mj_loadXML(file.c_str(), nullptr, error, sizeof error);
  std::error_code ec;
  std::filesystem::remove_all(folder, ec);
  if (m == nullptr) throw std::runtime_error(std::string("MuJoCo refused the model: ") + error);
  return std::unique_ptr<mjModel, ModelDeleter>(m);
}

/// The joint velocities (qvel) that give every body its initial velocity: the least-squares
/// solution of J qvel = (v_WBo, ω_W) stacked over the bodies, J from mj_jacBody at the initial
/// configuration (mujoco_engine.hpp). Throws when the fit leaves a residual.
void fit_initial_velocities(const mjModel* m, mjData* d, const RigidScene& scene,
                            const std::vector<int>& body_ids, const std::string& label) {
  mju_zero(d->qvel, m->nv);
  mj_forward(m, d);
  const auto n = static_cast<Eigen::Index>(scene.bodies.size());
  Eigen::MatrixXd A(6 * n, m->nv);
  Eigen::VectorXd y(6 * n);
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> jacp(3, m->nv),
      jacr(3, m->nv);
  for (Eigen::Index b = 0; b < n; ++b) {
    const RigidBodyInput& body = scene.bodies[static_cast<std::size_t>(b)];
    mj_jacBody(m, d, jacp.data(), jacr.data(), body_ids[static_cast<std::size_t>(b)]);
    A.middleRows(6 * b, 3) = jacp;
    A.middleRows(6 * b + 3, 3) = jacr;
    const Eigen::Quaterniond q_WB(body.e_WB[0], body.e_WB[1], body.e_WB[2], body.e_WB[3]);
    y.segment<3>(6 * b) = body.v_WBo;
    y.segment<3>(6 * b + 3) = q_WB.normalized() * body.w_WB_B;
  }
  const Eigen::VectorXd qvel = A.completeOrthogonalDecomposition().solve(y);
  const double residual = (A * qvel - y).lpNorm<Eigen::Infinity>();
  if (!(residual <= 1e-9 * std::max(1.0, y.lpNorm<Eigen::Infinity>()))) {
    throw core::SolverError(label, 0.0, 0,
                            "the bodies' initial velocities do not fit MuJoCo's joints (residual " +
                                std::to_string(residual) + ")");
  }
  Eigen::Map<Eigen::VectorXd>(d->qvel, m->nv) = qvel;
}

bool reset_by_mujoco(const mjData* d) {
  return d->warning[mjWARN_BADQPOS].number > 0 || d->warning[mjWARN_BADQVEL].number > 0 ||
         d->warning[mjWARN_BADQACC].number > 0;
}

}  // namespace

std::string MujocoEngine::version() const { return std::string("MuJoCo ") + mj_versionString(); }

std::vector<std::pair<std::string, std::string>> MujocoEngine::integrators() const {
  // The adapter's default is MuJoCo's most accurate integrator, as Simbody's adapter defaults
  // to Merson: a verification run that names no integrator should not measure a first-order
  // method (docs/decisions.md, "Verifying other integrators").
  return {
      {"rk4",
       "classical 4th-order Runge-Kutta; positions by quaternion exponential of the "
       "combined stage velocities"},
      {"euler",
       "semi-implicit Euler (MuJoCo's own default): velocity first, then position with it"},
      {"implicit", "implicit in velocity (the derivative of the smooth forces), then position"},
      {"implicitfast",
       "implicit in velocity without Coriolis derivatives (MuJoCo 2.3.3 and later)"},
  };
}

void MujocoEngine::add_options(CLI::App& app) {
  app.add_option("--solref", solref_,
                 "TIMECONST DAMPRATIO of the loops' equality constraints (MuJoCo's solref; "
                 "negative: -STIFFNESS -DAMPING); default 2*DT 1, the stiffest MuJoCo "
                 "integrates at the step (docs/engines.md)")
      ->expected(2);
  app.add_option("--solimp", solimp_,
                 "DMIN DMAX WIDTH [MID POWER] of the loops' equality constraints (MuJoCo's "
                 "solimp); default 0.9999 0.9999 0.001 0.5 2")
      ->expected(3, 5);
  app.callback([this] {
    if (!solref_.empty()) {
      const bool time_constant = solref_[0] > 0.0 && solref_[1] > 0.0;
      const bool direct = solref_[0] < 0.0 && solref_[1] <= 0.0;
      if (!(time_constant || direct) || !std::isfinite(solref_[0]) || !std::isfinite(solref_[1])) {
        throw CLI::ValidationError("--solref",
                                   "expected TIMECONST > 0 and DAMPRATIO > 0, or -STIFFNESS < 0 "
                                   "and -DAMPING <= 0");
      }
      softness_.solref = {solref_[0], solref_[1]};
    }
    if (!solimp_.empty()) {
      for (std::size_t i = 0; i < solimp_.size(); ++i) softness_.solimp[i] = solimp_[i];
      const auto& s = softness_.solimp;
      if (!(s[0] >= mjMINIMP && s[0] <= mjMAXIMP && s[1] >= mjMINIMP && s[1] <= mjMAXIMP &&
            s[2] > 0.0 && std::isfinite(s[2]) && s[3] > 0.0 && s[3] < 1.0 && s[4] >= 1.0 &&
            std::isfinite(s[4]))) {
        throw CLI::ValidationError("--solimp",
                                   "expected DMIN, DMAX in [1e-4, 0.9999], WIDTH > 0, MID in "
                                   "(0, 1), POWER >= 1");
      }
    }
  });
}

void MujocoEngine::check_mappable(const scene::Scene& scene, const std::string& integrator) const {
  if (mj_version() != mjVERSION_HEADER) {
    throw MappingError("MuJoCo", "the library is version " + std::to_string(mj_version()) +
                                     " but the program was built against headers " +
                                     std::to_string(mjVERSION_HEADER));
  }
#if mjVERSION_HEADER < 233
  if (integrator == "implicitfast") {
    throw MappingError("--integrator implicitfast",
                       "this MuJoCo (" + std::string(mj_versionString()) +
                           ") has no implicitfast integrator; it came with MuJoCo 2.3.3");
  }
#else
  (void)integrator;
#endif
  check_mujoco_mappable(scene);
}

void MujocoEngine::simulate(const scene::Scene& scene, const StepPlan& plan,
                            const std::string& integrator, const Recorder& record) {
  mju_user_warning = record_warning;
  mju_user_error = report_error;
  const std::string label = version() + " " + integrator;
  const RigidScene plain = rigid_scene(scene, mujoco_joint_support());
  std::unique_ptr<mjModel, ModelDeleter> model;
  try {
    model = compile(scene_mjcf(scene.spec.name, plain, plan.dt, integrator, softness_));
  } catch (const std::runtime_error& e) {
    throw core::SolverError(label, 0.0, 0, e.what());
  }
  const mjModel* m = model.get();
  std::unique_ptr<mjData, DataDeleter> data(mj_makeData(m));
  mjData* d = data.get();

  LoadContext loads;
  loads.spec = &scene.spec;
  const std::size_t n_bodies = scene.spec.bodies.size();
  for (const scene::BodySpec& body : scene.spec.bodies) {
    loads.body_ids.push_back(mj_name2id(m, mjOBJ_BODY, body.description.name.c_str()));
  }
  g_loads = &loads;
  mjcb_control = apply_loads;

  // Initial velocities: a free joint's qvel is (v_WBo, world; ω, body frame), a ball joint's
  // the body-frame ω. The positions are the model's qpos0 (the bodies' initial poses). With
  // ideal joints, the fit through the bodies' Jacobians.
  if (!plain.tree.empty()) fit_initial_velocities(m, d, plain, loads.body_ids, label);
  for (std::size_t b = 0; b < n_bodies && plain.tree.empty(); ++b) {
    const core::RigidBodyDescription& desc = scene.spec.bodies[b].description;
    const int joint = m->body_jntadr[loads.body_ids[b]];
    mjtNum* qvel = d->qvel + m->jnt_dofadr[joint];
    if (desc.motion == core::MotionKind::kFree) {
      Eigen::Map<Eigen::Vector3d> v_WBo(qvel), w_WB_B(qvel + 3);
      v_WBo = desc.initial.v_WBo;
      w_WB_B = desc.initial.w_WB_B;
    } else {
      Eigen::Map<Eigen::Vector3d> w_WB_B(qvel);
      w_WB_B = desc.initial.w_WB_B;
    }
  }

  std::vector<BodySample> samples(n_bodies);
  const auto sample = [&](std::size_t k) {
    loads.t_segment = d->time;
    mj_forward(m, d);  // kinematics and velocities of the current qpos, qvel
    for (std::size_t b = 0; b < n_bodies; ++b) {
      const int id = loads.body_ids[b];
      BodySample& s = samples[b];
      s.p_WBo = Eigen::Map<const Eigen::Vector3d>(d->xpos + 3 * id);
      s.e_WB = Eigen::Map<const Eigen::Vector4d>(d->xquat + 4 * id);
      mjtNum v[6];  // [ω; v] of the body frame at Bo, world frame
      mj_objectVelocity(m, d, mjOBJ_XBODY, id, v, 0);
      const Eigen::Matrix3d R_WB = rotation_from_rows(d->xmat + 9 * id);
      s.w_WB_B = R_WB.transpose() * Eigen::Map<const Eigen::Vector3d>(v);
      s.v_WBo = Eigen::Map<const Eigen::Vector3d>(v + 3);
    }
    record(k, d->time, samples);
  };

  std::size_t next_output = 0;
  if (plan.output_steps.front() == 0) sample(next_output++);
  for (long n = 0; n < plan.step_count; ++n) {
    loads.t_segment = plan.time(n) + 0.5 * plan.dt;
    mj_step(m, d);
    if (reset_by_mujoco(d)) {
      throw core::SolverError(label, plan.time(n), n,
                              "MuJoCo found a bad or huge state (" + g_last_warning +
                                  ") and reset the simulation to its initial state");
    }
    if (next_output < plan.output_steps.size() && plan.output_steps[next_output] == n + 1) {
      sample(next_output++);
    }
  }
  mjcb_control = nullptr;
  g_loads = nullptr;
}

}  // namespace flexref::engines
