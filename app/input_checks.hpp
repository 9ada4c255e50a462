#pragma once
/// \file input_checks.hpp
/// What a command refuses before any work (docs/decisions.md, "Command line"): a scene whose
/// physics double precision cannot carry (loaded through load_scene), and a run or a file
/// beyond the work limits (app/work_limits.hpp). Each refusal names the file and key, or the
/// option, and how to proceed.
#include <string>
#include <vector>

#include "app/default_model.hpp"
#include "app/work_limits.hpp"
#include "core/flexible_formulation.hpp"
#include "core/model.hpp"
#include "scene/scene.hpp"

namespace flexref::app {

/// Refuses (core::InputError naming the scene file and the key) a scene whose physics double
/// precision cannot carry over [0, end_time]: a stiff mode (flexible body, contact, joint) or
/// an initial spin whose period is below core::smallest_resolved_step(end_time), a stiffness
/// or frequency that under- or overflows, an initial energy beyond 1e100 J.
void check_scene_extremes(const scene::Scene& scene, double end_time);
/// scene::read_scene followed by check_scene_extremes(scene, scene.end_time).
scene::Scene load_scene(const std::string& path,
                        core::FlexibleFormulation formulation = kDefaultFormulation);
/// core::output_times, refused (std::invalid_argument) beyond limits.max_rows rows before the
/// grid is built.
std::vector<double> limited_output_times(double end_time, double output_step,
                                         const WorkLimits& limits);
/// lie::validate_step_grid plus the step-count limit; `what` names the option ("--dt") in the
/// message. Returns the number of steps.
long check_scheme_run(const core::Model& model, double dt, const std::vector<double>& times,
                      const WorkLimits& limits, const std::string& what);

}  // namespace flexref::app
