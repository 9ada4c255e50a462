#pragma once
/// \file step_limit.hpp
/// The explicit step limit of a model: explicit central differences (the translation and
/// modal parts of the hybrid step, docs/design/schemes.md "The hybrid step") are stable for
/// h ω ≤ 2 on an undamped linear mode, so every elastic mode of a flexible body and every
/// penalty element (contact, joint) bounds the step. One function, used by check, run,
/// converge and stability, for a model read from a scene or built in code.
#include <limits>
#include <string>
#include <vector>

#include "core/force_element.hpp"
#include "core/model.hpp"

namespace flexref::core {

/// The penalty modes of the model's elements in element order, each with its element's index,
/// labelled by the element's label (ForceElement::label: "spring 'S1'", "joint[2]" as the scene
/// names it) or, for an element built in code without one, "<kind>[<n>]" with n counting the
/// elements of that kind that have modes, from 1.
std::vector<PenaltyMode> penalty_modes(const Model& model);

/// Every mode that bounds an explicit step: each flexible body's highest natural frequency
/// (frame held fixed; kind "flexible body", label the body's name, stiffness the modal
/// stiffness, inertia the modal mass) followed by penalty_modes(model).
std::vector<PenaltyMode> stiff_modes(const Model& model);

/// The smallest explicit step limit of a model and what sets it.
struct StepLimit {
  double h = std::numeric_limits<double>::infinity();  ///< s; +∞ when nothing bounds it
  double frequency = 0.0;                              ///< rad/s of the limiting mode
  std::string what;  ///< "flexible body <name>" or a penalty mode's label
  bool bounded() const { return h < std::numeric_limits<double>::infinity(); }
};

/// The smallest step_limit of stiff_modes(model).
StepLimit explicit_step_limit(const Model& model);

}  // namespace flexref::core
