#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "core/output_times.hpp"
#include "core/step_limit.hpp"
#include "lie/run_scheme.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::app {
namespace {

std::string text(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

}  // namespace

void check_scene_extremes(const scene::Scene& scene, double end_time) {
  const core::Model& model = *scene.model;
  const double h_min = core::smallest_resolved_step(end_time);
  const auto refuse = [&](const std::string& key, const std::string& why) {
    throw core::InputError(scene.file, 0, key, why);
  };
  // Every motion must be slower than what double precision resolves over [0, end_time]: a
  // period below h_min cannot be followed by any integrator, fixed-step or adaptive.
  const auto resolvable = [&](double omega) { return 2.0 / omega >= h_min; };
  for (const core::PenaltyMode& m : core::stiff_modes(model)) {
    const bool flexible = m.kind == "flexible body";
    const std::string key =
        flexible ? "body[" + std::to_string(model.body_index(m.label) + 1) + "]" : m.label;
    // A friction mode is a damper (stiffness 0, rate c/m: contact/gap_support.cpp); every
    // other mode is a spring and needs a positive stiffness.
    const bool damper = m.label.ends_with(" friction");
    if (!(m.frequency > 0.0) || !std::isfinite(m.frequency) || !std::isfinite(m.stiffness) ||
        !(damper ? m.stiffness >= 0.0 : m.stiffness > 0.0)) {
      refuse(key, "its stiffness " + text(m.stiffness) + " and inertia " + text(m.inertia) +
                      " give the frequency " + text(m.frequency) +
                      " rad/s: a value of the scene under- or overflows double precision");
    }
    if (!resolvable(m.frequency)) {
      refuse(key, "omega = " + text(m.frequency) + " rad/s gives the step limit 2/omega = " +
                      text(2.0 / m.frequency) + " s, below the " + text(h_min) +
                      " s that double precision resolves at t = " + text(end_time) +
                      " s: no integrator can follow it; lower the stiffness or the end time");
    }
  }
  const core::State s0 = model.initial_state();
  for (int i = 0; i < model.num_bodies(); ++i) {
    const double spin = s0[static_cast<std::size_t>(i)].w_WB_B.norm();
    if (!std::isfinite(spin) || (spin > 0.0 && !resolvable(spin))) {
      refuse("body[" + std::to_string(i + 1) + "].angular_velocity",
             "|W| = " + text(spin) + " rad/s turns by 2 rad in " + text(2.0 / spin) +
                 " s, below the " + text(h_min) + " s that double precision resolves at t = " +
                 text(end_time) + " s: no integrator can follow it");
    }
  }
  core::Workspace ws = model.make_workspace();
  const double kinetic = model.kinetic_energy(s0);
  const double potential = model.potential_energy(core::LoadContext{0.0, 0.0}, s0, ws);
  // The equations multiply energies by rates and inverse inertias: keep a wide margin below
  // the overflow threshold (1.8e308) so that no intermediate product can overflow.
  constexpr double kEnergyCeiling = 1e100;
  if (!(std::abs(kinetic) < kEnergyCeiling) || !(std::abs(potential) < kEnergyCeiling)) {
    refuse("", "the initial energy (kinetic " + text(kinetic) + " J, potential " + text(potential) +
                   " J) is beyond 1e100 J: the scene's values overflow " +
                   "double precision in the equations of motion");
  }
}

scene::Scene load_scene(const std::string& path, core::FlexibleFormulation formulation) {
  scene::Scene scene = scene::read_scene(path, formulation);
  check_scene_extremes(scene, scene.end_time);
  return scene;
}

std::vector<double> limited_output_times(double end_time, double output_step,
                                         const WorkLimits& limits) {
  const double rows = std::floor(end_time / output_step) + 1.0;
  if (rows > limits.max_rows) {
    throw std::invalid_argument(
        "end time " + text(end_time) + " s at output_step " + text(output_step) + " s gives " +
        text(rows) + " output rows, beyond the limit of " + text(limits.max_rows) +
        " rows per file: raise output_step, shorten the end time or raise --max-rows");
  }
  return core::output_times(end_time, output_step);
}

long check_scheme_run(const core::Model& model, double dt, const std::vector<double>& times,
                      const WorkLimits& limits, const std::string& what) {
  long steps = 0;
  try {
    steps = lie::validate_step_grid(model, dt, times);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(what + " " + text(dt) + ": " + e.what());
  }
  if (static_cast<double>(steps) > limits.max_steps) {
    throw std::invalid_argument(what + " " + text(dt) + ": " + std::to_string(steps) +
                                " steps to t = " + text(times.back()) + " s, beyond the limit of " +
                                text(limits.max_steps) +
                                " steps per run: choose a larger step or raise --max-steps");
  }
  return steps;
}

}  // namespace flexref::app
