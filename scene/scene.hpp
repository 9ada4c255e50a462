#pragma once
/// \file scene.hpp
/// A scene as read from its file (docs/design/scenes.md, scenes/README.md): its description
/// (SceneSpec, plain data that studies may vary and rebuild with build_model), the model every
/// integrator sees, and the run settings that are not part of the physics.
#include <memory>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::scene {

struct Scene {
  std::string name;          ///< [scene] name
  std::string file;          ///< path or name as given to the reader
  std::string description;   ///< optional free text, empty when absent
  double end_time = 0.0;     ///< s, > 0
  double output_step = 0.0;  ///< s, in (0, end_time]
  /// The identity of the scene's physics (scene/scene_identity.hpp): "fnv1a64:…" for a scene
  /// read from a file, empty for one built in code.
  std::string hash;
  SceneSpec spec;                      ///< what the file says
  std::unique_ptr<core::Model> model;  ///< build_model(spec); never null after reading
};

}  // namespace flexref::scene
