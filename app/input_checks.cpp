#include "app/input_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "core/step_limit.hpp"
#include "lie/run_scheme.hpp"
#include "scene/build_model.hpp"
#include "scene/initial_energy.hpp"
#include "scene/scene_reader.hpp"

namespace flexref::app {
namespace {

std::string text(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

/// The 0-based index in the table path "contact[3]" after `prefix` ("contact["), or −1.
int table_index(const std::string& path, const std::string& prefix) {
  if (!path.starts_with(prefix)) return -1;
  return std::atoi(path.c_str() + prefix.size()) - 1;
}

/// Where a penalty mode comes from in the scene: its table's path and line and, for a contact
/// whose effective mass the scene does not give, the body whose mass it takes ("" otherwise).
struct ModeOrigin {
  std::string path;  ///< "contact[1]", "spring[2]", "body[3]" (a flexible body)
  int line = 0;
  std::string mass;  ///< e.g. "the mass of body[1] 'ball' (line 14)"
};

ModeOrigin mode_origin(const scene::Scene& scene, const core::PenaltyMode& m) {
  const scene::SceneSpec& spec = scene.spec;
  ModeOrigin origin;
  const auto body_mass = [&](int b) {
    const auto ub = static_cast<std::size_t>(b);
    return "body[" + std::to_string(b + 1) + "] '" + scene.model->body(b).name() + "' (line " +
           std::to_string(spec.bodies[ub].source.line) + ")";
  };
  if (m.kind == "flexible body") {
    const int b = scene.model->body_index(m.label);
    origin.path = "body[" + std::to_string(b + 1) + "]";
    if (b >= 0) origin.line = spec.bodies[static_cast<std::size_t>(b)].source.line;
    return origin;
  }
  // The element's table (scene::element_sources lists them in the model's order).
  const std::vector<scene::SpecSource> sources = scene::element_sources(spec);
  if (m.element >= 0 && static_cast<std::size_t>(m.element) < sources.size()) {
    const scene::SpecSource& source = sources[static_cast<std::size_t>(m.element)];
    origin.path = source.path;
    origin.line = source.line;
  }
  if (const int c = table_index(origin.path, "contact[");
      c >= 0 && static_cast<std::size_t>(c) < spec.contacts.size()) {
    const scene::ContactSpec& contact = spec.contacts[static_cast<std::size_t>(c)];
    if (contact.effective_mass == 0.0) {
      // scene::build_contact's default: the pairs' body (reduced with the other body's).
      if (contact.gap) {
        origin.mass = "the mass of " + body_mass(contact.gap->body);
      } else if (!contact.pairs.empty()) {
        const contact::ContactPair& p = contact.pairs.front();
        origin.mass = p.body_a >= 0 ? "the reduced mass of " + body_mass(p.body_a) + " and " +
                                          body_mass(p.body_b)
                                    : "the mass of " + body_mass(p.body_b);
      }
    }
  }
  return origin;
}

}  // namespace

void check_scene_extremes(const scene::Scene& scene, double end_time) {
  const core::Model& model = *scene.model;
  const double h_min = core::smallest_resolved_step(end_time);
  const auto refuse = [&](const std::string& key, const std::string& why, int line = 0) {
    throw core::InputError(scene.file, line, key, why);
  };
  // Every motion must be slower than what double precision resolves over [0, end_time]: a
  // period below h_min cannot be followed by any integrator, fixed-step or adaptive.
  const auto resolvable = [&](double omega) { return 2.0 / omega >= h_min; };
  for (const core::PenaltyMode& m : core::stiff_modes(model)) {
    const ModeOrigin origin = mode_origin(scene, m);
    // The table's path is the key; a mode without one (a model built in code) is named by its
    // label.
    const std::string key = origin.path.empty() ? m.label : origin.path;
    // A friction mode is a damper (stiffness 0, rate c/m: contact/gap_support.cpp); every
    // other mode is a spring and needs a positive stiffness.
    const bool damper = m.label.ends_with(" friction");
    // The inertia the mode sees, and where it comes from when the scene takes it from a body.
    const std::string inertia = text(m.inertia) + (origin.mass.empty() ? "" : ", " + origin.mass);
    if (!(m.frequency > 0.0) || !std::isfinite(m.frequency) || !std::isfinite(m.stiffness) ||
        !(damper ? m.stiffness >= 0.0 : m.stiffness > 0.0)) {
      refuse(key,
             "its stiffness " + text(m.stiffness) + " and inertia " + inertia +
                 " give the frequency " + text(m.frequency) +
                 " rad/s: a value of the scene under- or overflows double precision",
             origin.line);
    }
    if (!resolvable(m.frequency)) {
      refuse(key,
             "omega = " + text(m.frequency) + " rad/s (stiffness " + text(m.stiffness) +
                 ", inertia " + inertia +
                 ") gives the step limit 2/omega = " + text(2.0 / m.frequency) + " s, below the " +
                 text(h_min) + " s that double precision resolves at t = " + text(end_time) +
                 " s: no integrator can follow it; lower the stiffness" +
                 (origin.mass.empty() ? "" : ", raise that mass") + " or shorten the end time",
             origin.line);
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
    // At the part that holds it (a body, a potential, the gravity), with its table's line.
    const scene::EnergyPart part = scene::largest_initial_energy(scene.spec, *scene.model);
    const std::string why = "the initial energy (kinetic " + text(kinetic) + " J, potential " +
                            text(potential) + " J) is beyond 1e100 J, " + text(part.energy) +
                            " J of it the " + part.what +
                            " of this part: the scene's values overflow double precision in the "
                            "equations of motion";
    const std::string key =
        part.source.path.empty() ? "" : part.source.path + (part.key.empty() ? "" : "." + part.key);
    throw core::InputError(part.source.file.empty() ? scene.file : part.source.file,
                           part.source.line, key, why);
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
