#pragma once
/// \file check_command.hpp
/// `flexref check SCENE`: validates a scene and prints its model, the explicit schemes' step
/// limits and genalpha's step advice.
#include <string>

#include "app/default_model.hpp"
#include "core/flexible_formulation.hpp"

namespace flexref::app {

struct CheckOptions {
  std::string scene;
  /// The model the scene is built with: a scene with joints at a flexible body's nodes loads
  /// only under the coupled model.
  core::FlexibleFormulation model = kDefaultFormulation;
};
int check_command(const CheckOptions& options);

}  // namespace flexref::app
