/// \file external_methods.cpp
/// `--external` and `--runs` of the studies (docs/external.md).
#include "app/external_methods.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>

#include "app/scene_metadata.hpp"
#include "core/error.hpp"
#include "io/input_file.hpp"
#include "studies/external_program.hpp"
#include "trajectory/reference_sidecar.hpp"

namespace flexref::app {

std::vector<studies::ExternalMethod> external_methods(const ExternalOptions& options,
                                                      const studies::StudyOutput& out) {
  std::vector<studies::ExternalMethod> methods;
  if (!options.external.empty() && !options.runs.empty()) {
    throw std::invalid_argument("give --external or --runs, not both");
  }
  if (options.external.empty() && options.runs.empty()) return methods;
  studies::ExternalMethod method;
  method.label =
      options.label.empty() ? (options.runs.empty() ? "external" : "runs") : options.label;
  for (char c : method.label) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) {
      throw std::invalid_argument("--label '" + method.label +
                                  "': use letters, digits, '_' and '-'");
    }
  }
  method.claimed_order = options.claimed_order;
  if (!options.external.empty()) {
    studies::ExternalCommand command;
    command.command = options.external;
    command.scene = std::filesystem::absolute(options.scene).string();
    command.timeout_seconds = options.timeout;
    // Checks the template once, before any work.
    (void)studies::substitute_command(command.command, command.scene, 1.0, "x.csv");
    const std::string label = method.label;
    method.kept_file = [label, &out](int level) {
      return out.staged("run_" + label + "_" + std::to_string(level) + ".csv");
    };
    // The program writes into the staging folder, which is gone when the user reads why a level
    // failed: the message names the file's final place.
    method.run = [command, kept = method.kept_file, &out, options](double h, int level) {
      studies::ExternalLevel run;
      try {
        run = studies::run_external_level(command, h, kept(level));
      } catch (const std::exception& e) {
        throw std::runtime_error(out.with_final_paths(e.what()));
      }
      // A program that writes a sidecar (flexref run, another code's own) says which scene it
      // integrated: refuse the level when that is not the studied one.
      check_same_scene(trajectory::read_reference_sidecar(kept(level)).scene,
                       "the run of level " + std::to_string(level) + " (its sidecar)",
                       options.scene_identity, "the study", options.allow_scene_mismatch);
      return run;
    };
  } else {
    auto files = std::make_shared<std::map<double, std::string>>();
    for (const std::string& pair : options.runs) {
      const auto eq = pair.find('=');
      const std::string dt_text = pair.substr(0, eq == std::string::npos ? 0 : eq);
      char* end = nullptr;
      errno = 0;
      const double h = std::strtod(dt_text.c_str(), &end);
      if (eq == std::string::npos || dt_text.empty() || *end != '\0' || !(h > 0.0) ||
          !std::isfinite(h) || eq + 1 == pair.size()) {
        throw std::invalid_argument("--runs '" + pair + "': expected DT=FILE with DT > 0");
      }
      const std::string file = pair.substr(eq + 1);
      // Refused before any work when it cannot be read (missing, a folder, a FIFO, a device).
      if (const io::InputFile in(file, "a trajectory CSV file (--runs)"); !in.is_open()) {
        throw core::InputError(file, 0, "", in.error());
      }
      if (!files->emplace(h, file).second) {
        throw std::invalid_argument("--runs: the step " + dt_text + " is given twice");
      }
      check_same_scene(trajectory::read_reference_sidecar(file).scene, "--runs " + file,
                       options.scene_identity, "the study", options.allow_scene_mismatch);
      method.steps.push_back(h);
    }
    method.run = [files](double h, int) {
      studies::ExternalLevel level;
      level.run = trajectory::read_run_csv(files->at(h));
      // Only the program's own report is known of a run made earlier.
      level.cpu_reported = std::isfinite(level.run.reported_cpu_seconds);
      level.cpu_seconds = level.cpu_reported ? level.run.reported_cpu_seconds : std::nan("");
      return level;
    };
  }
  methods.push_back(std::move(method));
  return methods;
}

}  // namespace flexref::app
