#pragma once
/// \file method_options.hpp
/// The options a method's factory receives (lie/method_registry.hpp), a value passed from the
/// command line, a study's options or the Python module down to where each stepper is made.
/// Nothing is process-wide: two studies in one process with different options build their
/// steppers each with its own (docs/decisions.md, "Verifying other integrators").
#include <functional>
#include <map>
#include <string>
#include <string_view>

#include "lie/genalpha_parameters.hpp"

namespace flexref::lie {

struct MethodOptions {
  /// genalpha's spectral radius at infinity ρ∞ (lie/genalpha_parameters.hpp); its factory
  /// refuses a value outside [0, 1] (std::invalid_argument naming rho_inf).
  double rho_inf = kDefaultRhoInfinity;
  /// genalpha starts from Arnold's perturbed a_0 = v̇(t_0 + (α_m − α_f) h) instead of v̇_0.
  bool perturbed_start = false;
  /// A registered method's own options by name (the names its MethodInfo::option_names
  /// declares); the built-in methods read none. check_method_options refuses a name that no
  /// method of a study reads: accepted silently, it would change nothing and the user would
  /// believe it did.
  std::map<std::string, double, std::less<>> values;

  /// values[name], or `fallback` when the name is not given.
  double value(std::string_view name, double fallback) const;
};

}  // namespace flexref::lie
