#include "app/figure_command.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <toml.hpp>
#include <vector>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/help_text.hpp"
#include "app/input_checks.hpp"
#include "app/scene_metadata.hpp"
#include "core/error.hpp"
#include "core/output_times.hpp"
#include "io/input_file.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/stepper.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "scene/scene_toml.hpp"
#include "studies/high_precision_references.hpp"
#include "studies/parallel.hpp"
#include "studies/plot.hpp"
#include "studies/reference_policy.hpp"
#include "studies/reference_solver_name.hpp"
#include "studies/study_output.hpp"
#include "studies/trajectory_figure.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {

namespace {

std::string read_text(const std::string& path) {
  io::InputFile in(path, "the study file (TOML)");
  if (!in.is_open()) throw core::InputError(path, 0, "", in.error());
  try {
    return in.read_all();
  } catch (const std::runtime_error& e) {
    throw core::InputError(path, 0, "", e.what());
  }
}

/// An array of strings or numbers under `key` of table t (file:line:key errors).
std::vector<std::string> string_array(const scene::scene_toml::Table& t, std::string_view key) {
  std::vector<std::string> out;
  const toml::value* v = t.find(key);
  if (v == nullptr) return out;
  if (!v->is_array() || v->as_array().empty()) t.fail(key, "expected a non-empty array of names");
  for (const toml::value& e : v->as_array()) {
    if (!e.is_string()) t.fail_at(e, key, "expected a name (string)");
    out.push_back(e.as_string().str);
  }
  return out;
}

std::vector<double> number_array(const scene::scene_toml::Table& t, std::string_view key) {
  std::vector<double> out;
  const toml::value* v = t.find(key);
  if (v == nullptr || !v->is_array() || v->as_array().empty()) {
    t.fail(key, "expected a non-empty array of steps [s]");
  }
  for (const toml::value& e : v->as_array()) {
    out.push_back(t.to_number(e, key, scene::scene_toml::Sign::kPositive, "a positive step [s]"));
  }
  return out;
}

}  // namespace

int figure_command(const FigureCommandOptions& options) {
  const std::string text = read_text(options.study);
  const toml::value document = scene::scene_toml::parse(text, options.study);
  const scene::scene_toml::Table root(document, options.study, "");
  root.check_keys({"figure"});
  const std::optional<scene::scene_toml::Table> figure = root.table("figure", "a [figure] table");
  if (!figure) root.fail("figure", "expected a [figure] table");
  const scene::scene_toml::Table& f = *figure;
  f.check_keys({"title", "scene", "schemes", "steps", "body", "point", "solver", "rtol", "end_time",
                "rho_inf", "perturbed_start"});
  const std::string title = f.optional_string("title", "a title").value_or("");
  // The scene path is relative to the study file.
  const std::filesystem::path scene_path =
      std::filesystem::path(options.study).parent_path() / f.string("scene", "a scene file");
  const scene::Scene scene = load_scene(scene_path.string());
  const core::Model& model = *scene.model;

  studies::FigureSettings settings;
  if (f.has("schemes")) settings.schemes = string_array(f, "schemes");
  const std::vector<std::string> known = lie::scheme_names();
  for (const std::string& s : settings.schemes) {
    if (std::find(known.begin(), known.end(), s) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      f.fail("schemes", "unknown scheme \"" + s + "\"; expected " + list);
    }
  }
  // genalpha's options (docs/cli.md, "Schemes and models"), refused unless genalpha is among the
  // schemes, as the command line refuses --rho-inf: accepted silently, they would change nothing.
  const bool genalpha = std::find(settings.schemes.begin(), settings.schemes.end(), "genalpha") !=
                        settings.schemes.end();
  for (const char* key : {"rho_inf", "perturbed_start"}) {
    if (f.has(key) && !genalpha)
      f.fail(key,
             "applies only to genalpha: add it to schemes or leave " + std::string(key) + " out");
  }
  settings.method_options.rho_inf =
      f.number_or("rho_inf", lie::kDefaultRhoInfinity, scene::scene_toml::Sign::kNonNegative,
                  "genalpha's spectral radius at infinity in [0, 1]");
  if (settings.method_options.rho_inf > 1.0) f.fail("rho_inf", "must lie in [0, 1]");
  settings.method_options.perturbed_start =
      f.boolean_or("perturbed_start", false, "true or false (genalpha's perturbed start)");
  settings.steps = number_array(f, "steps");
  if (const auto body = f.optional_string("body", "a body name")) {
    settings.body = model.body_index(*body);
    if (settings.body < 0) f.fail("body", "no body \"" + *body + "\" in " + scene_path.string());
  }
  const auto& points = model.body(settings.body).description().points;
  if (points.empty()) f.fail("point", "the body has no tracked point to draw");
  if (const auto point = f.optional_string("point", "a tracked point name")) {
    settings.point = -1;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (points[i].name == *point) settings.point = static_cast<int>(i);
    }
    if (settings.point < 0) f.fail("point", "no tracked point \"" + *point + "\" on the body");
  }
  std::optional<studies::ReferenceSolver> solver;
  try {
    solver = studies::parse_reference_solver(
        f.optional_string("solver", "a reference solver").value_or("cvode"));
  } catch (const std::invalid_argument&) {
    // An unknown name: refused below with the study file's line and key.
  }
  if (!solver || *solver == studies::ReferenceSolver::kAuto ||
      *solver == studies::ReferenceSolver::kArkode) {
    f.fail("solver", "expected cvode, ida, odeint or exact");
  }
  settings.solver = studies::to_string(*solver);
  settings.rtol = f.number_or("rtol", 1e-10, scene::scene_toml::Sign::kPositive, "a tolerance");
  const double end_time = f.number_or("end_time", scene.end_time,
                                      scene::scene_toml::Sign::kPositive, "an end time [s]");
  if (end_time > scene.end_time) f.fail("end_time", "exceeds the scene's end time");
  for (double h : settings.steps) {
    if (!core::is_multiple_of(end_time, h)) {
      f.fail("steps", "a step must divide the end time");
    }
    try {
      check_scheme_run(model, h, {0.0, end_time}, options.limits, "step");
    } catch (const std::invalid_argument& e) {
      f.fail("steps", e.what());
    }
  }
  const std::vector<double> times =
      limited_output_times(end_time, scene.output_step, options.limits);
  settings.jobs = options.jobs > 0 ? options.jobs : studies::default_jobs();
  settings.progress = true;

  studies::StudyOutput out(options.out_dir);
  std::cerr << "figure: reference (" << settings.solver << ") and "
            << settings.schemes.size() * settings.steps.size() << " scheme runs on "
            << studies::workers_text(settings.jobs) << " ...\n";
  // --reference-precision (docs/precision.md), as in converge: a given precision replaces the
  // reference; "auto" repeats the figure against a quad reference when the double one leaves a
  // curve uncertified and the scene allows it.
  // The schemes against the model before a high-precision reference (quad: minutes).
  for (const std::string& s : settings.schemes) {
    (void)lie::make_stepper(s, model, settings.method_options);
  }
  // The study file's solver and rtol are the double reference's.
  const studies::StudyReferences references(scene, times, "points", studies::ReferenceSolver::kAuto,
                                            "figure");
  studies::PolicyStudy<studies::FigureResult> policy_study;
  policy_study.run = [&](std::shared_ptr<const trajectory::CertifiedReference> reference,
                         studies::ReferencePrecision precision) {
    settings.given_reference = std::move(reference);
    if (settings.given_reference) settings.given_precision = precision;
    return studies::run_trajectory_figure(model, times, settings);
  };
  policy_study.uncertified = [](const studies::FigureResult& r) {
    if (!studies::figure_has_uncertified(r)) return std::string();
    std::ostringstream why;
    why << "the double reference (estimated error " << r.reference_estimate
        << " m) could not certify every curve";
    return why.str();
  };
  policy_study.repeated = "the figure was repeated against a quad-precision reference";
  studies::PolicyOutcome<studies::FigureResult> outcome = studies::run_with_reference_policy(
      options.reference_precision, options.reference_budget, references, policy_study);
  const studies::FigureResult& result = outcome.result;
  const std::string& note = outcome.note;
  const std::string& refused = outcome.refused;

  const std::string table =
      studies::figure_table(result) + (note.empty() ? "" : "note: " + note + "\n");
  studies::StudyRecord record = scene_record(scene_path.string(), scene);
  record.table("study")
      .set("kind", "figure")
      .set("file", options.study)
      .set("title", title)
      .set("schemes", settings.schemes)
      .set("steps", settings.steps)
      .set("point", points[static_cast<std::size_t>(settings.point)].name)
      .set("end_time", end_time);
  auto&& reference_table = record.table("reference");
  reference_table.set("solver", settings.given_reference ? std::string("odeint") : settings.solver)
      .set("precision", studies::to_string(result.reference_precision))
      .set("estimate", result.reference_estimate)
      .set("estimate_method", result.reference_estimate_method);
  if (!settings.given_reference) reference_table.set("rtol", settings.rtol);
  record.table("study").set("reference_budget", options.reference_budget);
  if (!refused.empty()) record.table("study").set("reference_refused", refused);
  studies::add_versions(record);
  out.write("figure.csv", studies::figure_csv(result));
  out.write("figure.txt", table);
  const studies::PlotOutcome plot = out.plot(
      "plot_trajectory_figure.py", "figure.png",
      {out.staged("figure.csv"), out.staged("figure.png"), title.empty() ? scene.name : title});
  out.commit(std::move(record));

  std::cout << (title.empty() ? scene.name : title) << "\n"
            << table << "wrote figure.csv, figure.txt, study.toml" << (plot.ok ? ", " : "\n")
            << plot.message << "\n";
  return kExitOk;
}

RegisteredCommand register_figure_command(CLI::App& app) {
  auto options = std::make_shared<FigureCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "figure", "trajectory of a tracked point by each scheme and step, with the reference");
  cmd->add_option("study", options->study, "study file (TOML), e.g. studies/paper/*.toml")
      ->required();
  cmd->add_option("--jobs", options->jobs, "parallel runs (0: all cores)")
      ->check(integer_in(0, 1024));
  add_enum_option(cmd, "--reference-precision", options->reference_precision,
                  "auto (quad when the double reference cannot certify a curve and the scene "
                  "allows it) | double | extended | quad (docs/precision.md)",
                  {"auto", "double", "extended", "quad"}, studies::parse_reference_precision,
                  [](studies::ReferencePrecision p) { return studies::to_string(p); });
  add_reference_budget(cmd, options->reference_budget);
  cmd->add_option("--out", options->out_dir, kOutputFolderHelp)->capture_default_str();
  add_limits(cmd, options->limits, true);

  return {cmd, [options] { return figure_command(*options); }};
}

}  // namespace flexref::app
