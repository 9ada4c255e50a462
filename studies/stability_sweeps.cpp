#include "studies/stability_sweeps.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "contact/contact.hpp"
#include "core/step_limit.hpp"
#include "flexible/beam_model.hpp"
#include "lie/method_registry.hpp"
#include "lie/stepper.hpp"
#include "scene/build_model.hpp"
#include "studies/mpi/distribution.hpp"
#include "studies/parallel.hpp"
#include "studies/progress.hpp"
#include "studies/stability.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::studies {

namespace {

constexpr double kGravity = 9.81;        // m/s²
constexpr double kBallMass = 1.0;        // kg
constexpr double kBallRadius = 0.1;      // m
constexpr double kBallOvershoot = 0.05;  // initial penetration (1 + this) δ_s

/// The flexible spinner's beam and hub (scenes/flexible_spinner.toml, docs/design/scenes.md)
/// with bending stiffness EI, torque-free, spinning at 1 rad/s with deflected modes (LTE).
scene::SceneSpec spinner(double EI) {
  scene::BeamSpec beam;
  beam.parameters.origin = Eigen::Vector3d(0.1, 0.0, 0.0);
  beam.parameters.length = 1.0;
  beam.parameters.elements = 10;
  beam.parameters.EA = 1e5;
  beam.parameters.EI_y = EI;
  beam.parameters.EI_z = EI;
  beam.parameters.rho_A = 1.0;
  beam.modes = 4;
  beam.filter.axial = false;
  scene::BodySpec body;
  core::RigidBodyDescription& d = body.description;
  d.name = "spinner";
  d.mass = 10.0;
  d.I_Bcm_B = Eigen::Vector3d(0.5, 0.5, 1.0).asDiagonal();
  d.initial.w_WB_B = Eigen::Vector3d(0.0, 0.0, 1.0);
  body.beam = beam;
  scene::regenerate_beam_modes(body);
  d.flexible->q0 = Eigen::Vector4d(0.02, 0.01, 0.005, 0.0);
  scene::SceneSpec spec;
  spec.name = "spinner";
  spec.bodies.push_back(std::move(body));
  return spec;
}

/// A ball on a linear, undamped penalty floor under gravity, resting (1 + overshoot) times its
/// static penetration deep.
scene::SceneSpec ball(double k) {
  scene::BodySpec body;
  core::RigidBodyDescription& d = body.description;
  d.name = "ball";
  d.mass = kBallMass;
  d.I_Bcm_B = 0.4 * kBallMass * kBallRadius * kBallRadius * Eigen::Matrix3d::Identity();
  const double delta_static = kBallMass * kGravity / k;
  d.initial.p_WBo = Eigen::Vector3d(0.0, 0.0, kBallRadius - (1.0 + kBallOvershoot) * delta_static);
  scene::ContactSpec floor;
  floor.pairs.push_back(contact::ContactPair::sphere_plane(
      0, Eigen::Vector3d::Zero(), kBallRadius, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()));
  floor.law.linear = true;
  floor.law.stiffness = k;
  floor.law.damping = 0.0;
  floor.friction = contact::FrictionLaw{0.0, 1e-3};
  floor.effective_mass = kBallMass;
  scene::SceneSpec spec;
  spec.name = "ball";
  spec.g_W = Eigen::Vector3d(0.0, 0.0, -kGravity);
  spec.bodies.push_back(std::move(body));
  spec.contacts.push_back(std::move(floor));
  return spec;
}

}  // namespace

core::Model make_linear_sweep_model(StabilityParameter parameter, double value, double& omega) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument("stability: swept values must be positive and finite");
  }
  if (parameter == StabilityParameter::kModalFrequency) {
    // ω ∝ √EI: scale EI from the spinner's 3.2 N·m² to put ω_max at the swept value.
    const double omega_base =
        core::explicit_step_limit(scene::build_model(spinner(3.2), core::FlexibleFormulation::kLte))
            .frequency;
    core::Model model =
        scene::build_model(spinner(3.2 * (value / omega_base) * (value / omega_base)),
                           core::FlexibleFormulation::kLte);
    omega = core::explicit_step_limit(model).frequency;
    return model;
  }
  if (parameter == StabilityParameter::kContactStiffness) {
    core::Model model = scene::build_model(ball(value));
    omega = core::explicit_step_limit(model).frequency;
    return model;
  }
  throw std::invalid_argument(std::string("stability: unknown linear parameter '") +
                              to_string(parameter) +
                              "'; expected modal_frequency or contact_stiffness");
}

std::string classify_linear_run(const core::Model& model, StabilityParameter parameter,
                                const std::string& scheme, double h,
                                const LinearSweepOptions& options) {
  const auto stepper = lie::make_stepper(scheme, model, options.method_options);
  const core::State s0 = model.initial_state();
  stepper->initialize(0.0, s0);
  const bool modal = parameter == StabilityParameter::kModalFrequency;
  // Amplitude measure and its initial value.
  double initial = 0.0;
  double z_rest = 0.0;
  if (modal) {
    initial = s0[0].q_f.cwiseAbs().maxCoeff();
  } else {
    // δ_s from the initial penetration (1 + overshoot) δ_s.
    const double delta0 = kBallRadius - s0[0].p_WBr.z();
    const double delta_s = delta0 / (1.0 + kBallOvershoot);
    z_rest = kBallRadius - delta_s;
    initial = std::abs(s0[0].p_WBr.z() - z_rest);
  }
  for (long n = 0; n < options.steps; ++n) {
    const lie::StepStatus status = stepper->step(h);
    if (!status.ok) return "step failure: " + status.message;
    const core::BodyState& s = stepper->state()[0];
    const double amplitude = modal ? s.q_f.cwiseAbs().maxCoeff() : std::abs(s.p_WBr.z() - z_rest);
    if (!std::isfinite(amplitude) || !s.theta_WB.allFinite()) return "non-finite";
    if (amplitude > options.growth_factor * initial) return "amplitude growth";
  }
  return "stable";
}

std::vector<LinearSweepPoint> run_linear_sweep(const LinearSweepOptions& options) {
  lie::check_method_options(options.method_options, options.schemes);
  const std::size_t n_schemes = options.schemes.size();
  std::vector<LinearSweepPoint> points(options.values.size() * n_schemes);
  require_codec_size<LinearSweepPoint, 96>();
  const auto fields = [](auto& io, auto& p) {
    io(p.scheme, p.value, p.omega, p.h_max, p.h_theory, p.classification);
  };
  const SlotCodec codec{[&points, fields](int i, SlotWriter& w) {
                          auto put = [&w](const auto&... x) { (w.put(x), ...); };
                          fields(put, points[static_cast<std::size_t>(i)]);
                        },
                        [&points, fields](int i, SlotReader& r) {
                          auto get = [&r](auto&... x) { (r.get(x), ...); };
                          fields(get, points[static_cast<std::size_t>(i)]);
                        }};
  ProgressLine progress("stability", "bisections", options.progress);
  distributed_for(
      static_cast<int>(points.size()), options.jobs,
      [&](int task) {
        const auto u = static_cast<std::size_t>(task);
        LinearSweepPoint& p = points[u];
        p.scheme = options.schemes[u % n_schemes];
        p.value = options.values[u / n_schemes];
        const core::Model model = make_linear_sweep_model(options.parameter, p.value, p.omega);
        p.h_theory = 2.0 / p.omega;
        const auto stable = [&](double h) {
          return classify_linear_run(model, options.parameter, p.scheme, h, options) == "stable";
        };
        // Start a decade under the theoretical limit; cap a decade above it.
        const StableStepBracket b = bisect_largest_stable(
            stable, 0.1 * p.h_theory, 10.0 * p.h_theory, options.relative_tolerance);
        p.h_max = b.h_stable;
        p.classification =
            std::isfinite(b.h_unstable)
                ? classify_linear_run(model, options.parameter, p.scheme, b.h_unstable, options)
                : "stable to cap";
      },
      codec);
  return points;
}

std::string linear_sweep_csv(StabilityParameter parameter,
                             const std::vector<LinearSweepPoint>& points) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "scheme,parameter,value,omega,h_max,h_theory,h_max_times_omega,classification\n";
  for (const LinearSweepPoint& p : points) {
    out << p.scheme << ',' << to_string(parameter) << ',' << p.value << ',' << p.omega << ','
        << p.h_max << ',' << p.h_theory << ',' << p.h_max * p.omega << ','
        << trajectory::csv_text(p.classification) << '\n';
  }
  return out.str();
}

std::string format_linear_sweep_table(StabilityParameter parameter,
                                      const std::vector<LinearSweepPoint>& points) {
  std::ostringstream out;
  const std::string label =
      parameter == StabilityParameter::kModalFrequency ? "w_max [rad/s]" : "k [N/m]";
  out << std::left << std::setw(10) << "scheme" << std::setw(14) << label << std::setw(14)
      << "omega [rad/s]" << std::setw(13) << "h_max [s]" << std::setw(13) << "2/omega [s]"
      << std::setw(10) << "h*omega"
      << "first unstable step\n";
  for (const LinearSweepPoint& p : points) {
    std::ostringstream row;
    row << std::setprecision(4);
    row << std::left << std::setw(10) << p.scheme << std::setw(14) << p.value << std::setw(14)
        << p.omega << std::setw(13) << p.h_max << std::setw(13) << p.h_theory << std::setw(10)
        << p.h_max * p.omega << p.classification << "\n";
    out << row.str();
  }
  return out.str();
}

}  // namespace flexref::studies
