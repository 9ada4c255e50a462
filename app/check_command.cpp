#include "app/check_command.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <numbers>
#include <span>
#include <string>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/genalpha_step.hpp"
#include "app/input_checks.hpp"
#include "constraint/mobility.hpp"
#include "core/output_times.hpp"
#include "core/step_limit.hpp"
#include "lie/genalpha_parameters.hpp"
#include "reference/exact_solution.hpp"
#include "scene/build_model.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::app {

int check_command(const CheckOptions& options) {
  const scene::Scene scene = load_scene(options.scene, options.model);
  const core::Model& model = *scene.model;
  std::cout << "scene " << scene.name << " (" << options.scene << "): OK\n";
  if (!scene.description.empty()) std::cout << "  " << scene.description << "\n";
  std::cout << "  end time " << scene.end_time << " s, output every " << scene.output_step
            << " s\n";
  const constraint::Mobility mobility = constraint::mobility(model);
  const std::span<const core::Body> bodies(model.bodies());
  std::cout << "  " << model.num_bodies() << " bodies, " << mobility.coordinates
            << " degrees of freedom" << (model.has_constraints() ? " before the ideal joints" : "")
            << "\n";
  for (const core::Body& b : model.bodies()) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(b.I_Br_B());
    const char* motion = b.is_free() ? "free" : b.is_prescribed() ? "prescribed" : "pivot";
    const char* about = b.is_free()         ? "the centre of mass"
                        : b.is_prescribed() ? "the frame origin"
                                            : "the pivot";
    std::cout << "  body " << b.name() << ": " << motion << (b.is_flexible() ? ", flexible" : "")
              << ", mass " << b.mass() << " kg, principal inertia about " << about << " ["
              << eig.eigenvalues().transpose() << "] kg·m²"
              << (b.is_flexible() ? " (undeformed, hub included)" : "") << ", "
              << b.description().points.size() << " tracked points\n";
    if (b.is_prescribed()) {
      const core::PrescribedRotation& p = b.description().prescribed;
      std::cout << "    prescribed rotation about [" << p.axis_W.transpose()
                << "] (world): " << p.law.describe() << "\n";
    }
    if (!b.is_flexible()) continue;
    const flexible::ModalData& modal = b.description().flexible->modal;
    const Eigen::VectorXd& w = b.natural_frequencies();
    std::cout << "    " << b.mode_count() << " modes on " << modal.node_count()
              << " nodes; natural frequencies with the frame held fixed:\n";
    for (Eigen::Index k = 0; k < w.size(); ++k) {
      const std::string name = static_cast<std::size_t>(k) < modal.mode_names.size()
                                   ? modal.mode_names[static_cast<std::size_t>(k)]
                                   : "mode-" + std::to_string(k + 1);
      std::printf("      %2d  %-16s %14.6g rad/s %14.6g Hz\n", static_cast<int>(k + 1),
                  name.c_str(), w(k), w(k) / (2.0 * std::numbers::pi));
    }
    std::fflush(stdout);
    if (w.size() > 0 && w.maxCoeff() > 0.0) {
      std::cout << "    explicit step limit (central differences) 2/omega_max = "
                << 2.0 / w.maxCoeff() << " s\n";
    }
  }
  if (const core::ConstraintEquations* joints = model.constraints(); joints != nullptr) {
    // Ideal joints (docs/joints.md): the mobility by counting and in fact, and the rows the
    // model left out as redundant (their reactions are the minimum-norm ones).
    for (int j = 0; j < joints->joint_count(); ++j) {
      const auto uj = static_cast<std::size_t>(j);
      std::cout << "  " << joints->describe(j, bodies)
                << (uj < scene.spec.ideal_joints.size()
                        ? " [line " + std::to_string(scene.spec.ideal_joints[uj].source.line) + "]"
                        : std::string())
                << "\n";
    }
    std::cout << "  ideal joints: " << joints->joint_count() << " joints, " << mobility.rows
              << " rows of rank " << mobility.rank << " at the initial configuration; degrees of "
              << "freedom by counting " << mobility.coordinates << " - " << mobility.rows << " = "
              << mobility.by_counting() << ", in fact " << mobility.coordinates << " - "
              << mobility.rank << " = " << mobility.in_fact() << "\n";
    if (mobility.redundant.empty()) {
      std::cout << "  redundant rows: none\n";
    } else {
      std::cout << "  redundant rows (" << mobility.redundant.size()
                << ", no multiplier of their own; minimum-norm reactions):";
      for (std::size_t k = 0; k < mobility.redundant.size(); ++k) {
        const constraint::RedundantRow& r = mobility.redundant[k];
        std::cout << (k == 0 ? " " : ", ") << r.joint << " row " << r.joint_row + 1 << " ("
                  << r.label << ")";
      }
      std::cout << "\n";
    }
    const core::InitialProjection p = model.consistent_initial_state().projection;
    std::cout << "  initial state: relative violation " << p.position << " (positions), "
              << p.velocity << " (velocities) before the projection onto the joints\n";
  }
  // Each element with the table it comes from, so that a label below ("spring[1]", "joint
  // 'O'") leads back to the file.
  const std::vector<scene::SpecSource> sources = scene::element_sources(scene.spec);
  const auto elements = model.elements();
  for (std::size_t e = 0; e < elements.size(); ++e) {
    std::cout << "  " << elements[e]->describe_with_names(bodies);
    const std::string& label = elements[e]->label();
    if (!label.empty() && e < sources.size() && sources[e].line > 0) {
      std::cout << " [" << label << ", line " << sources[e].line << "]";
    }
    std::cout << "\n";
  }
  // Penalty elements: each contact's and joint's stiffest mode (docs/contact.md,
  // docs/joints.md) and the explicit step it allows.
  for (const core::PenaltyMode& m : core::penalty_modes(model)) {
    if (m.label.ends_with(" friction")) {  // contact/gap_support.cpp: a damper, not a spring
      std::cout << "  " << m.label
                << ": regularized friction c_t = mu F_n / v_reg, rate c_t/m_eff = " << m.frequency
                << " 1/s, explicit step limit 2 m_eff/c_t = " << m.step_limit << " s\n";
      continue;
    }
    const bool angular = m.label.ends_with(" angular");
    std::cout << "  " << m.label << ": omega = sqrt(k/" << (angular ? "I_eff" : "m_eff")
              << ") = sqrt(" << m.stiffness << (angular ? " N·m/rad / " : " N/m / ") << m.inertia
              << (angular ? " kg·m²" : " kg") << ") = " << m.frequency
              << " rad/s, explicit step limit 2/omega = " << m.step_limit << " s"
              << (m.kind == "joint" || m.kind == "spring" ? " (damping, if any, included)" : "")
              << "\n";
  }
  const core::StepLimit limit = core::explicit_step_limit(model);
  if (!model.discontinuities().empty()) {
    std::cout << "  load switches at t =";
    for (double t : model.discontinuities()) std::cout << ' ' << t;
    std::cout << " s (every integrator steps onto them)\n";
  }
  const core::State s0 = model.initial_state();
  core::Workspace ws = model.make_workspace();
  const double e0 = model.kinetic_energy(s0) + model.potential_energy({0.0, 0.0}, s0, ws);
  const Eigen::Vector3d h0 = model.angular_momentum_W(s0);
  std::cout << "  initial energy " << e0 << " J, angular momentum about the origin ["
            << h0.transpose() << "] N·m·s\n";
  if (limit.bounded()) {
    std::cout << "  explicit step limit: " << limit.h << " s ("
              << (limit.what.starts_with("flexible body")
                      ? std::string("2/omega_max of the stiffest flexible body")
                      : "of " + limit.what + ", the stiffest penalty element")
              << "; `run` warns above it)\n";
  } else {
    std::cout << "  explicit step limit: none from elastic modes or penalty elements (rigid "
                 "bodies only); the rotation schemes' accuracy is governed by |W| h\n";
  }
  // genalpha is implicit: no stability limit, a step that resolves the fastest rate at t0
  // (app/genalpha_step.hpp).
  const double rho_inf = lie::kDefaultRhoInfinity;
  const GenalphaStepAdvice ga =
      genalpha_step_advice(model, core::output_times(scene.end_time, scene.output_step), rho_inf);
  if (ga.rate > 0.0) {
    const double c = genalpha_period_error_coefficient(rho_inf);
    std::cout << "  genalpha step (implicit, no stability limit): ";
    if (ga.step > 0.0) {
      std::cout << "use --dt " << ga.step << " or less";
    } else {
      std::cout << "no step of the form {1, 2, 5}·10^k below the bound is on the output grid";
    }
    std::cout << "; h <= " << ga.bound
              << " s keeps h omega <= " << std::sqrt(kGenalphaPeriodError / c)
              << ", a period error within " << 100.0 * kGenalphaPeriodError
              << " % at rho_inf = " << rho_inf << ", on the fastest rate at t0, omega = " << ga.rate
              << " rad/s of " << ga.what << "\n";
    if (ga.step > 0.0) {
      // ΔT/T = c (h ω)² per period accumulates over the ωT/2π periods of the run as a phase
      // error ΔT/T · ωT (rad), for a motion that keeps this rate.
      const double h_omega = ga.step * ga.rate;
      const double turns = ga.rate * scene.end_time;
      std::cout << "    at that step, a motion that kept this rate over the whole run (omega T = "
                << turns << " rad) would drift in phase by about " << c * h_omega * h_omega * turns
                << " rad; `converge --schemes genalpha` measures the error\n";
    }
  } else {
    std::cout << "  genalpha step (implicit, no stability limit): no rate at t0 (bodies at rest, "
                 "no stiffness, no drive, no force that moves them); the motion the run develops "
                 "sets it\n";
  }
  if (model.has_flexible_bodies()) {
    std::cout << "  exact solution: none (flexible bodies)\n";
  } else {
    const auto exact = reference::classify_exact_solution(model);
    std::cout << "  exact solution: "
              << (exact.kind.empty() ? "none (" + exact.reason + ")" : exact.kind) << "\n";
  }
  return kExitOk;
}

RegisteredCommand register_check_command(CLI::App& app) {
  auto options = std::make_shared<CheckOptions>();
  CLI::App* cmd = app.add_subcommand("check", "validate a scene and print its model");
  cmd->add_option("scene", options->scene, "scene file (TOML)")->required();
  add_model_option(cmd, options->model);

  return {cmd, [options] { return check_command(*options); }};
}

}  // namespace flexref::app
