#pragma once
/// \file cli_options.hpp
/// Options that several `flexref` commands share, one definition each: genalpha's parameters,
/// --model, the reference solver's rule, the work limits, --reference-budget,
/// --allow-scene-mismatch, the scheme ladder and its coarsest step, --estimate-factor and the
/// metric list. Their shared help text: app/help_text.hpp.
#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/work_limits.hpp"
#include "core/flexible_formulation.hpp"
#include "core/model.hpp"
#include "lie/method_options.hpp"
#include "studies/reference_solver_name.hpp"

namespace flexref::app {

/// genalpha's options (lie/genalpha_parameters.hpp, docs/schemes.md "Lie-group generalized-α"),
/// stored in the command's lie::MethodOptions, which the command passes down to where its
/// steppers are made: --rho-inf (MethodOptions::rho_inf), the spectral radius at infinity, a
/// usage error outside [0, 1], and --perturbed-start (MethodOptions::perturbed_start), Arnold's
/// starting value a_0 = v̇(t_0 + (α_m − α_f) h). When either is given and `schemes` — the
/// schemes the command runs, read once parsing is complete — does not include "genalpha", the
/// parse fails with a CLI::ValidationError (exit 2) naming the option, `scheme_option`
/// ("--scheme", "--schemes") and its value.
void add_genalpha_options(CLI::App* command, lie::MethodOptions& options,
                          std::function<std::vector<std::string>()> schemes,
                          const std::string& scheme_option);

/// A study's --reference-budget (docs/precision.md, "Cost guard").
void add_reference_budget(CLI::App* command, double& budget);

/// --model of every command that takes it, with the one default (app/default_model.hpp).
void add_model_option(CLI::App* command, core::FlexibleFormulation& model);
/// `--model coupled|lte`: the formulation of flexible bodies' equations (rigid bodies are the
/// same in both), a command-line choice so that scenes stay model-agnostic. Returns the
/// core::FlexibleFormulation of the value; throws std::invalid_argument for any other.
core::FlexibleFormulation parse_formulation(const std::string& model);

/// The reference solver to use for a scene (--solver, --reference-solver): `solver` itself,
/// except that a model with flexible bodies has no analytic solution — "exact" is refused
/// (std::invalid_argument naming `option`). "auto" stays "auto"
/// (trajectory::resolve_reference_solver resolves it: never exact for a flexible model).
studies::ReferenceSolver reference_solver_for(const core::Model& model,
                                              studies::ReferenceSolver solver,
                                              const std::string& option);

/// --max-steps (when `steps`) and --max-rows (app::WorkLimits): counts, whole numbers.
void add_limits(CLI::App* command, WorkLimits& limits, bool steps);

/// --allow-scene-mismatch: compare files whose sidecars name different scenes
/// (docs/decisions.md, "Scene identity").
void add_allow_scene_mismatch(CLI::App* command, bool& allow);

/// The scene, --schemes and --dt (the coarsest step) of the studies that step schemes down a
/// ladder of steps (converge, work-precision).
void add_scheme_ladder(CLI::App* command, std::string& scene, std::vector<std::string>& schemes,
                       double& dt);
/// The coarsest step of such a study: --dt when given, else the default dt or the scene's
/// output interval, the shorter (a step must divide the output interval: Andrews' squeezer
/// writes every 1e-4 s, so the default 1e-2 s could not run it).
double coarsest_step(double dt, bool dt_given, double output_step);

/// --estimate-factor of lte-map and modes: one meaning (trajectory/accuracy_check.hpp).
void add_estimate_factor(CLI::App* command, double& factor);

/// "what: relative | rotation+points | ...": the help of a --metric option.
std::string metric_help(const std::string& what);

/// An option whose value is one of `names`, stored in the enum `value` as CLI11 reads it
/// (`parse`: name -> enum; `print`: enum -> name, for the default in the help). CLI11 binds it
/// as text, so the help lists it as it does a text option ("TEXT:{a,b} [a]"), and refuses any
/// other name (a usage error) before `parse` sees it.
template <class Enum, class Parse, class Print>
CLI::Option* add_enum_option(CLI::App* command, const std::string& name, Enum& value,
                             const std::string& help, const std::vector<std::string>& names,
                             Parse parse, Print print) {
  auto text = std::make_shared<std::string>(print(value));
  return command->add_option(name, *text, help)
      ->check(CLI::IsMember(names))
      ->capture_default_str()
      ->each([text, &value, parse](const std::string& given) { value = parse(given); });
}

}  // namespace flexref::app
