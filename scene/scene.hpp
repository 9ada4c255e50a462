#pragma once
/// \file scene.hpp
/// A scene as read from its file (docs/design/scenes.md, scenes/README.md): the model every
/// integrator sees plus the run settings that are not part of the physics.
#include <memory>
#include <string>
#include <vector>

#include "core/model.hpp"

namespace flexref::scene {

/// The stiffest mode of one penalty element ([[contact]] or [[joint]]) as `check` prints it
/// and `run` warns about: ω = √(k/m_eff) (contacts: the effective stiffness of
/// ContactElement::effective_stiffness), and the explicit central-difference step limit it
/// implies (2/ω; a damped joint's lower (2/ω)(√(1 + ζ²) − ζ)).
struct PenaltyMode {
  std::string label;        ///< "contact[1]", "joint[2] translational", "joint[2] angular"
  std::string kind;         ///< "contact", "joint"
  double stiffness = 0.0;   ///< effective k (N/m) or k_θ (N·m/rad)
  double inertia = 0.0;     ///< effective mass (kg) or inertia (kg·m²) the mode sees
  double frequency = 0.0;   ///< rad/s
  double step_limit = 0.0;  ///< s
};

struct Scene {
  std::string name;                    ///< [scene] name
  std::string file;                    ///< path or name as given to the reader
  std::string description;             ///< optional free text, empty when absent
  double end_time = 0.0;               ///< s, > 0
  double output_step = 0.0;            ///< s, in (0, end_time]
  std::unique_ptr<core::Model> model;  ///< never null after reading
  /// One entry per contact table and two (translational, angular) per revolute joint, one per
  /// spherical joint, in file order.
  std::vector<PenaltyMode> penalty_modes;
};

}  // namespace flexref::scene
