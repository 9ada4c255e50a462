/// \file cli_options.cpp
/// Options that several `flexref` commands share, one definition each.
#include "app/cli_options.hpp"

#include <algorithm>
#include <stdexcept>

#include "app/cli_validators.hpp"
#include "lie/stepper.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::app {

void add_genalpha_options(CLI::App* command, lie::MethodOptions& options,
                          std::function<std::vector<std::string>()> schemes,
                          const std::string& scheme_option) {
  command
      ->add_option("--rho-inf", options.rho_inf,
                   "genalpha's spectral radius at infinity, in [0, 1] (1: no numerical damping); "
                   "only with genalpha among the schemes")
      ->check(number_in(0.0, 1.0))
      ->capture_default_str();
  command->add_flag("--perturbed-start", options.perturbed_start,
                    "genalpha: start from a_0 = dv/dt(t0 + (alpha_m - alpha_f) h) (Arnold's "
                    "perturbed starting value) instead of a_0 = dv/dt(t0); only with genalpha "
                    "among the schemes");
  // After every option is read (the final callback runs inside CLI::App::parse, so the error
  // is a parse error: exit 2, nothing run). Accepted silently, the option would change nothing
  // and the user would believe it did.
  command->final_callback([command, schemes = std::move(schemes), scheme_option] {
    const std::vector<std::string> chosen = schemes();
    if (std::find(chosen.begin(), chosen.end(), "genalpha") != chosen.end()) return;
    for (const char* option : {"--rho-inf", "--perturbed-start"}) {
      if (command->count(option) == 0) continue;
      std::string list;
      for (const std::string& s : chosen) list += (list.empty() ? "" : ",") + s;
      throw CLI::ValidationError(
          option, std::string("applies only to genalpha, and ") + scheme_option + " is " +
                      (list.empty() ? std::string("empty") : list) +
                      (command->count(scheme_option) == 0 ? " (the default)" : "") + ": " +
                      (scheme_option == "--schemes" ? "add genalpha to --schemes"
                                                    : "give --scheme genalpha") +
                      " or leave " + option + " out");
    }
  });
}

void add_reference_budget(CLI::App* command, double& budget) {
  command
      ->add_option("--reference-budget", budget,
                   "seconds of wall time auto may spend on a quad reference; over it (projected "
                   "early), the study keeps the double one (0: no bound; docs/precision.md)")
      ->check(non_negative_number())
      ->capture_default_str();
}

void add_model_option(CLI::App* command, core::FlexibleFormulation& model) {
  add_enum_option(command, "--model", model,
                  "flexible bodies' equations: coupled | lte (lte by default: the model the "
                  "schemes integrate)",
                  {"coupled", "lte"}, parse_formulation,
                  [](core::FlexibleFormulation f) { return core::to_string(f); });
}

core::FlexibleFormulation parse_formulation(const std::string& model) {
  if (model == "coupled") return core::FlexibleFormulation::kCoupled;
  if (model == "lte") return core::FlexibleFormulation::kLte;
  throw std::invalid_argument("unknown --model \"" + model + "\"; expected coupled or lte");
}

studies::ReferenceSolver reference_solver_for(const core::Model& model,
                                              studies::ReferenceSolver solver,
                                              const std::string& option) {
  if (!model.has_flexible_bodies()) return solver;
  if (solver == studies::ReferenceSolver::kExact) {
    throw std::invalid_argument(option +
                                " exact: the scene has flexible bodies, which have no analytic "
                                "solution; use cvode, ida or odeint");
  }
  return solver;
}

void add_limits(CLI::App* command, WorkLimits& limits, bool steps) {
  if (steps) {
    command
        ->add_option("--max-steps", limits.max_steps,
                     "refuse a scheme run of more steps (raise it to allow longer runs)")
        ->check(positive_integer())
        ->capture_default_str();
  }
  command
      ->add_option("--max-rows", limits.max_rows,
                   "refuse a trajectory of more output rows (raise it to allow larger files)")
      ->check(positive_integer())
      ->capture_default_str();
}

void add_allow_scene_mismatch(CLI::App* command, bool& allow) {
  command->add_flag("--allow-scene-mismatch", allow,
                    "compare results whose sidecars (FILE.meta.toml) name different scenes or "
                    "another version of the scene (refused otherwise)");
}

void add_scheme_ladder(CLI::App* command, std::string& scene, std::vector<std::string>& schemes,
                       double& dt) {
  command->add_option("scene", scene, "scene file (TOML)")->required();
  command->add_option("--schemes", schemes, "comma-separated list")
      ->delimiter(',')
      ->check(CLI::IsMember(lie::scheme_names()))
      ->capture_default_str();
  command
      ->add_option("--dt", dt,
                   "coarsest step [s]; by default 0.01 or the scene's output interval, the shorter")
      ->check(positive_number())
      ->capture_default_str();
}

double coarsest_step(double dt, bool dt_given, double output_step) {
  return dt_given ? dt : std::min(dt, output_step);
}

void add_estimate_factor(CLI::App* command, double& factor) {
  command
      ->add_option("--estimate-factor", factor,
                   "accuracy check: every reference run is repeated at rtol divided by this "
                   "factor (tighter); their distance estimates the run's error")
      ->check(number_in(2.0, 1e6))
      ->capture_default_str();
}

std::string metric_help(const std::string& what) {
  std::string list;
  for (const std::string& m : trajectory::metric_names()) list += (list.empty() ? "" : " | ") + m;
  return what + ": " + list;
}

}  // namespace flexref::app
