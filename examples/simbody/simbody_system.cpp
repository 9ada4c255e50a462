#include "examples/simbody/simbody_system.hpp"

#include <Simbody.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>

#include "examples/simbody/simbody_joints.hpp"

namespace flexref::engines {
namespace {

SimTK::Vec3 vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

Eigen::Vector3d eigen(const SimTK::Vec3& v) { return {v[0], v[1], v[2]}; }

Eigen::Matrix3d eigen(const SimTK::Mat33& m) {
  Eigen::Matrix3d out;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out(i, j) = m(i, j);
  }
  return out;
}

SimTK::Rotation rotation(const Eigen::Vector4d& e_WB) {
  return SimTK::Rotation(SimTK::Quaternion(e_WB[0], e_WB[1], e_WB[2], e_WB[3]));
}

/// Simbody's mass properties: the inertia about the body ORIGIN, body frame.
SimTK::MassProperties mass_properties(const RigidBodyInput& b) {
  const Eigen::Vector3d& c = b.p_BoBcm_B;
  const Eigen::Matrix3d I_Bo_B =
      b.I_Bcm_B + b.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  SimTK::Mat33 I;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) I(i, j) = I_Bo_B(i, j);
  }
  return SimTK::MassProperties(b.mass, vec3(c), SimTK::Inertia(I));
}

/// The scene's loads as body forces at the body origins, at every evaluation.
class SceneLoads final : public SimTK::Force::Custom::Implementation {
 public:
  SceneLoads(const RigidScene& scene, std::vector<SimTK::MobilizedBody> bodies,
             const double* t_segment)
      : scene_(scene), bodies_(std::move(bodies)), t_segment_(t_segment) {}

  void calcForce(const SimTK::State& state, SimTK::Vector_<SimTK::SpatialVec>& body_forces,
                 SimTK::Vector_<SimTK::Vec3>&, SimTK::Vector&) const override {
    for (std::size_t b = 0; b < bodies_.size(); ++b) {
      const SimTK::Transform& X_WB = bodies_[b].getBodyTransform(state);
      LoadPose pose;
      pose.R_WB = eigen(X_WB.R().asMat33());
      pose.p_WBo = eigen(X_WB.p());
      const LoadWrench w =
          scene_.loads(static_cast<int>(b), state.getTime(), *t_segment_, pose, pose.p_WBo);
      // Simbody's body forces: (moment about the body origin, force), ground frame.
      body_forces[bodies_[b].getMobilizedBodyIndex()] +=
          SimTK::SpatialVec(vec3(w.m_W), vec3(w.f_W));
    }
  }
  SimTK::Real calcPotentialEnergy(const SimTK::State&) const override { return 0.0; }

 private:
  const RigidScene& scene_;
  std::vector<SimTK::MobilizedBody> bodies_;
  const double* t_segment_;
};

/// The system of a scene (see the header for the mapping).
class SimbodySystem {
 public:
  SimbodySystem(const RigidScene& scene, const double* t_segment)
      : scene_(scene), matter_(system_), forces_(system_), contacts_(system_) {
    SimTK::MobilizedBody& ground = matter_.updGround();
    bodies_.resize(scene.bodies.size());
    // Without ideal joints every body is a root, in the scene's order; with them, parents first
    // (simbody_joints.hpp).
    std::vector<int> order(scene.bodies.size());
    for (std::size_t b = 0; b < order.size(); ++b) order[b] = static_cast<int>(b);
    if (!scene.tree.empty()) order = scene.tree_order;
    for (int i : order) {
      const RigidBodyInput& b = scene.bodies[static_cast<std::size_t>(i)];
      const SimTK::Body::Rigid info(mass_properties(b));
      SimTK::MobilizedBody& mobod = bodies_[static_cast<std::size_t>(i)];
      const TreeLink link =
          scene.tree.empty() ? TreeLink{} : scene.tree[static_cast<std::size_t>(i)];
      if (link.joint >= 0) {
        SimTK::MobilizedBody& parent =
            link.parent < 0 ? ground : bodies_[static_cast<std::size_t>(link.parent)];
        mobod = add_tree_body(parent, info, scene, i);
      } else if (!b.pivot) {
        mobod = SimTK::MobilizedBody::Free(ground, SimTK::Transform(), info, SimTK::Transform());
      } else {
        const Eigen::Vector3d p_WPivot =
            b.p_WBo +
            Eigen::Quaterniond(b.e_WB[0], b.e_WB[1], b.e_WB[2], b.e_WB[3]) * b.p_BoPivot_B;
        mobod = SimTK::MobilizedBody::Ball(ground, SimTK::Transform(vec3(p_WPivot)), info,
                                           SimTK::Transform(vec3(b.p_BoPivot_B)));
      }
    }
    for (int l : scene.loops) add_loop_closure(matter_, bodies_, scene, l);
    if (scene.g_W != Eigen::Vector3d::Zero()) {
      SimTK::Force::UniformGravity(forces_, matter_, vec3(scene.g_W));
    }
    if (scene.has_loads) SimTK::Force::Custom(forces_, new SceneLoads(scene, bodies_, t_segment));
    for (const SpherePlaneInput& c : scene.contacts) {
      // HalfSpace occupies x > 0 of its frame: its x axis points into the solid, −n.
      const SimTK::Rotation R_WH(SimTK::UnitVec3(-vec3(c.n_W)), SimTK::XAxis);
      const SimTK::ContactSetIndex set = contacts_.createContactSet();
      contacts_.addBody(set, ground, SimTK::ContactGeometry::HalfSpace(),
                        SimTK::Transform(R_WH, vec3(c.p_WQ)));
      contacts_.addBody(set, bodies_[static_cast<std::size_t>(c.body)],
                        SimTK::ContactGeometry::Sphere(c.radius),
                        SimTK::Transform(vec3(c.p_BoC_B)));
      // Both surfaces get the same modulus E. Simbody stores E^(2/3) per surface and combines
      // two equal ones into E_eff = (E^(2/3)/2)^(3/2) = E/2^(3/2) (HuntCrossleyForce.cpp), so
      // its f = (4/3) sqrt(R) E_eff δ^(3/2) (1 + 3/2 c δ̇) is k δ^(3/2) (1 + α δ̇) for
      // E = 2^(3/2) · 3k/(4 sqrt(R)) and c = 2α/3.
      const double E = std::pow(2.0, 1.5) * 3.0 * c.stiffness / (4.0 * std::sqrt(c.radius));
      SimTK::HuntCrossleyForce force(forces_, contacts_, set);
      for (int surface = 0; surface < 2; ++surface) {
        force.setBodyParameters(SimTK::ContactSurfaceIndex(surface), E, 2.0 * c.alpha / 3.0, 0.0,
                                0.0, 0.0);
      }
    }
    for (const SpringInput& s : scene.springs) {
      const SimTK::MobilizedBody& a = bodies_[static_cast<std::size_t>(s.body_a)];
      const SimTK::MobilizedBody& b =
          s.body_b < 0 ? ground : bodies_[static_cast<std::size_t>(s.body_b)];
      const double k = s.stiffness;
      SimTK::Force::LinearBushing(forces_, b, SimTK::Transform(vec3(s.point_b)), a,
                                  SimTK::Transform(vec3(s.point_a)), SimTK::Vec6(0, 0, 0, k, k, k),
                                  SimTK::Vec6(0));
    }
    for (const LinearSpringInput& s : scene.linear_springs) {
      const SimTK::MobilizedBody& a = bodies_[static_cast<std::size_t>(s.body_a)];
      const SimTK::MobilizedBody& b =
          s.body_b < 0 ? ground : bodies_[static_cast<std::size_t>(s.body_b)];
      SimTK::Force::TwoPointLinearSpring(forces_, a, vec3(s.point_a), b, vec3(s.point_b),
                                         s.stiffness, s.rest_length);
      if (s.damping != 0.0) {
        SimTK::Force::TwoPointLinearDamper(forces_, a, vec3(s.point_a), b, vec3(s.point_b),
                                           s.damping);
      }
    }
    system_.realizeTopology();
  }
  SimbodySystem(const SimbodySystem&) = delete;
  SimbodySystem& operator=(const SimbodySystem&) = delete;

  const SimTK::MultibodySystem& system() const { return system_; }
  const SimTK::MobilizedBody& body(std::size_t b) const { return bodies_[b]; }

  /// The scene's initial poses and velocities.
  SimTK::State initial_state() const {
    SimTK::State state = system_.getDefaultState();
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      const RigidBodyInput& b = scene_.bodies[i];
      const SimTK::Rotation R_WB = rotation(b.e_WB);
      const SimTK::Vec3 w_WB_W = R_WB * vec3(b.w_WB_B);
      const bool jointed = !scene_.tree.empty() && scene_.tree[i].joint >= 0;
      if (jointed) {
        // q = 0 is the initial configuration (simbody_joints.hpp); the u's fit the velocities.
        set_tree_velocity(state, bodies_[i], scene_, static_cast<int>(i));
      } else if (!b.pivot) {
        bodies_[i].setQToFitTransform(state, SimTK::Transform(R_WB, vec3(b.p_WBo)));
        bodies_[i].setUToFitVelocity(state, SimTK::SpatialVec(w_WB_W, vec3(b.v_WBo)));
      } else {
        bodies_[i].setQToFitRotation(state, R_WB);
        bodies_[i].setUToFitAngularVelocity(state, w_WB_W);
      }
    }
    return state;
  }

 private:
  const RigidScene& scene_;
  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  SimTK::GeneralForceSubsystem forces_;
  SimTK::GeneralContactSubsystem contacts_;
  std::vector<SimTK::MobilizedBody> bodies_;
};

std::unique_ptr<SimTK::Integrator> make_integrator(const std::string& name,
                                                   const SimTK::MultibodySystem& system,
                                                   double dt) {
  if (name == "euler") return std::make_unique<SimTK::ExplicitEulerIntegrator>(system);
  if (name == "rk2") return std::make_unique<SimTK::RungeKutta2Integrator>(system);
  if (name == "rk3") return std::make_unique<SimTK::RungeKutta3Integrator>(system);
  if (name == "merson") return std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system);
  if (name == "feldberg") return std::make_unique<SimTK::RungeKuttaFeldbergIntegrator>(system);
  if (name == "verlet") return std::make_unique<SimTK::VerletIntegrator>(system);
  if (name == "semi-euler") return std::make_unique<SimTK::SemiExplicitEulerIntegrator>(system, dt);
  if (name == "semi-euler2") return std::make_unique<SimTK::SemiExplicitEuler2Integrator>(system);
  throw std::invalid_argument("unknown Simbody integrator '" + name + "'");
}

}  // namespace

std::vector<std::pair<std::string, std::string>> simbody_integrators() {
  return {
      {"merson", "Runge-Kutta-Merson, 4th order (RungeKuttaMersonIntegrator)"},
      {"euler", "explicit Euler, 1st order (ExplicitEulerIntegrator)"},
      {"rk2", "explicit trapezoid rule, 2nd order (RungeKutta2Integrator)"},
      {"rk3", "Butcher's 3rd-order Runge-Kutta (RungeKutta3Integrator)"},
      {"feldberg", "Runge-Kutta-Fehlberg 4(5), declared 5th order (RungeKuttaFeldbergIntegrator)"},
      {"verlet", "velocity Verlet, declared order 2 to 3 (VerletIntegrator)"},
      {"semi-euler", "semi-explicit (symplectic) Euler, 1st order (SemiExplicitEulerIntegrator)"},
      {"semi-euler2",
       "semi-explicit Euler with step doubling, 1st order (SemiExplicitEuler2Integrator)"},
  };
}

void run_simbody(const RigidScene& scene, const StepPlan& plan, const SimbodyOptions& options,
                 const Recorder& record) {
  // Stops: the output steps and the load switches, ascending.
  std::vector<long> stops = plan.output_steps;
  stops.insert(stops.end(), plan.switch_steps.begin(), plan.switch_steps.end());
  std::sort(stops.begin(), stops.end());
  stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
  // The stretch between load switches that starts at step n, as a time inside it.
  const auto segment_middle = [&](long n) {
    const auto next = std::upper_bound(plan.switch_steps.begin(), plan.switch_steps.end(), n);
    const long end = next == plan.switch_steps.end() ? plan.step_count : *next;
    return 0.5 * (plan.time(n) + plan.time(end));
  };
  double t_segment = segment_middle(0);
  long n = 0;
  try {
    const SimbodySystem model(scene, &t_segment);
    const SimTK::MultibodySystem& system = model.system();
    std::unique_ptr<SimTK::Integrator> integ = make_integrator(options.integrator, system, plan.dt);
    integ->setFixedStepSize(plan.dt);
    integ->setAllowInterpolation(false);
    if (options.accuracy > 0.0) integ->setAccuracy(options.accuracy);
    if (options.constraint_tolerance > 0.0) {
      integ->setConstraintTolerance(options.constraint_tolerance);
      integ->setProjectEveryStep(true);
    }
    integ->initialize(model.initial_state());

    std::vector<BodySample> samples(scene.bodies.size());
    std::size_t next_output = 0;
    const auto sample = [&]() {
      const SimTK::State& s = integ->getState();
      system.realize(s, SimTK::Stage::Velocity);
      for (std::size_t b = 0; b < samples.size(); ++b) {
        const SimTK::MobilizedBody& body = model.body(b);
        const SimTK::Transform& X_WB = body.getBodyTransform(s);
        const SimTK::Quaternion q = X_WB.R().convertRotationToQuaternion();
        samples[b].p_WBo = eigen(X_WB.p());
        samples[b].e_WB = Eigen::Vector4d(q[0], q[1], q[2], q[3]);
        samples[b].v_WBo = eigen(body.getBodyOriginVelocity(s));
        samples[b].w_WB_B = eigen(~X_WB.R() * body.getBodyAngularVelocity(s));
      }
      record(next_output++, s.getTime(), samples);
    };
    if (plan.output_steps.front() == 0) sample();
    for (long stop : stops) {
      if (stop == 0) continue;
      const double t_stop = plan.time(stop);
      // stepTo returns once at the start of a continuous interval without advancing.
      while (integ->getTime() < t_stop) integ->stepTo(t_stop);
      n = stop;
      if (next_output < plan.output_steps.size() && plan.output_steps[next_output] == stop) {
        sample();
      }
      if (std::binary_search(plan.switch_steps.begin(), plan.switch_steps.end(), stop) &&
          stop < plan.step_count) {
        // A load switch: the next stretch's branch, and a restart so that no derivative of the
        // previous stretch is reused.
        t_segment = segment_middle(stop);
        const SimTK::State at_switch = integ->getState();
        integ->initialize(at_switch);
      }
    }
  } catch (const std::exception& e) {
    throw SimbodyFailure(plan.time(n), n, e.what());
  }
}

}  // namespace flexref::engines
