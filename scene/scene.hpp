#pragma once
/// \file scene.hpp
/// A scene as read from its file (docs/design/scenes.md, scenes/README.md): the model every
/// integrator sees plus the run settings that are not part of the physics.
#include <memory>
#include <string>
#include <vector>

#include "core/model.hpp"

namespace flexref::scene {

struct Scene {
  std::string name;                    ///< [scene] name
  std::string file;                    ///< path or name as given to the reader
  std::string description;             ///< optional free text, empty when absent
  double end_time = 0.0;               ///< s, > 0
  double output_step = 0.0;            ///< s, in (0, end_time]
  std::unique_ptr<core::Model> model;  ///< never null after reading
};

}  // namespace flexref::scene
