#include <Eigen/Eigenvalues>
#include <cstdio>
#include <iostream>

#include "app/commands.hpp"
#include "app/scene_reader.hpp"
#include "reference/exact_solution.hpp"

namespace flexref::app {

int check_command(const CheckOptions& options) {
  const Scene scene = read_scene(options.scene);
  const core::Model& model = *scene.model;
  std::cout << "scene " << scene.name << " (" << options.scene << "): OK\n";
  if (!scene.description.empty()) std::cout << "  " << scene.description << "\n";
  std::cout << "  end time " << scene.end_time << " s, output every " << scene.output_step
            << " s\n";
  int dofs = 0;
  for (const core::Body& b : model.bodies()) dofs += b.is_free() ? 6 : 3;
  std::cout << "  " << model.num_bodies() << " bodies, " << dofs << " degrees of freedom\n";
  for (const core::Body& b : model.bodies()) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(b.I_Br_B());
    std::cout << "  body " << b.name() << ": " << (b.is_free() ? "free" : "pivot") << ", mass "
              << b.mass() << " kg, principal inertia about "
              << (b.is_free() ? "the centre of mass" : "the pivot") << " ["
              << eig.eigenvalues().transpose() << "] kg·m², " << b.description().points.size()
              << " tracked points\n";
  }
  for (const auto& e : model.elements()) std::cout << "  " << e->describe() << "\n";
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
  std::cout << "  explicit step limit: none from elastic modes or penalty elements (rigid "
               "bodies only); the rotation schemes' accuracy is governed by |W| h\n";
  const auto exact = reference::classify_exact_solution(model);
  std::cout << "  exact solution: "
            << (exact.kind.empty() ? "none (" + exact.reason + ")" : exact.kind) << "\n";
  return kExitOk;
}

}  // namespace flexref::app
