#pragma once
/// \file method_registry.hpp
/// The methods the studies can run, by name (after SUNDIALS' ARKODE Butcher-table registry and
/// Drake's integrator factory): each entry has a name, the order its authors claim and a
/// factory that builds a lie::Stepper for a model and the options the caller passes
/// (lie::MethodOptions: genalpha's ρ∞ and perturbed start, a user method's named values). C1,
/// C2, NMB and genalpha are registered at start-up; a user registers their own stepper once and
/// then runs it through every study (studies::run_convergence, run_work_precision, the
/// stability and figure studies), which build their steppers with make_stepper and the
/// MethodOptions of the study's options.
///
///     flexref::lie::register_method({"lie_euler", 1, "explicit Lie-Euler",
///         [](const flexref::core::Model& m, const flexref::lie::MethodOptions&) {
///           return std::make_unique<LieEuler>(m);
///         }});
///
/// Registration is thread-safe; register before a study starts.
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/model.hpp"
#include "lie/method_options.hpp"
#include "lie/stepper.hpp"

namespace flexref::lie {

/// Builds a stepper for a model (which outlives it) with the caller's options; throws
/// std::invalid_argument for an option value the method refuses, naming the option.
using StepperFactory =
    std::function<std::unique_ptr<Stepper>(const core::Model&, const MethodOptions&)>;

struct MethodInfo {
  std::string name;         ///< letters, digits, '_' and '-'; unique
  int claimed_order = 0;    ///< the order the authors claim (≥ 1), checked by `converge`
  std::string description;  ///< one line for listings
  StepperFactory factory;   ///< builds a stepper for a model and options
  /// Whether studies run it when no scheme list is given (default_scheme_names). The comparison
  /// method `genalpha` is registered with false: it runs only when named (--schemes).
  bool in_default_studies = true;
  /// The names of MethodOptions::values the factory reads (its own options; none for the
  /// built-in methods, whose options are MethodOptions' named fields).
  std::vector<std::string> option_names = {};
};

/// Adds a method. Throws std::invalid_argument when the name is empty, has other characters
/// than letters, digits, '_' and '-', is already registered, the claimed order is < 1 or the
/// factory is empty.
void register_method(MethodInfo method);

/// The registered method of that name, or nullptr.
const MethodInfo* find_method(std::string_view name);

/// All registered methods, in registration order (c1, c2, nmb, genalpha first).
std::vector<MethodInfo> registered_methods();

/// Refuses (std::invalid_argument naming the option) a name of options.values that none of
/// `schemes` declares in its MethodInfo::option_names. Studies call it before any run; a name
/// of `schemes` that is not registered is left to make_stepper.
void check_method_options(const MethodOptions& options, const std::vector<std::string>& schemes);

}  // namespace flexref::lie
