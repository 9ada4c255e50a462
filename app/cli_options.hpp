#pragma once
/// \file cli_options.hpp
/// Options that several `flexref` commands share, one definition each: the output rule in the
/// help of output paths, genalpha's parameters, --model, the work limits, --reference-budget,
/// --allow-scene-mismatch, --estimate-factor and the metric list.
#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/work_limits.hpp"
#include "core/flexible_formulation.hpp"
#include "lie/method_options.hpp"

namespace flexref::app {

/// The output rule (io/output_file.hpp, docs/output.md "Where outputs go"), in the help of every
/// option that takes an output path.
extern const char* const kOutputFileHelp;
extern const char* const kOutputFolderHelp;

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

/// --max-steps (when `steps`) and --max-rows (app::WorkLimits): counts, whole numbers.
void add_limits(CLI::App* command, WorkLimits& limits, bool steps);

/// --allow-scene-mismatch: compare files whose sidecars name different scenes
/// (docs/decisions.md, "Scene identity").
void add_allow_scene_mismatch(CLI::App* command, bool& allow);

/// The scene, --schemes and --dt (the coarsest step) of the studies that step schemes down a
/// ladder of steps (converge, work-precision).
void add_scheme_ladder(CLI::App* command, std::string& scene, std::vector<std::string>& schemes,
                       double& dt);

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
