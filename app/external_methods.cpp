/// \file external_methods.cpp
/// `--external` and `--runs` of the studies (docs/external.md).
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>

#include "app/commands.hpp"
#include "studies/external_program.hpp"

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
    method.run = [command, kept = method.kept_file](double h, int level) {
      return studies::run_external_level(command, h, kept(level));
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
      if (!files->emplace(h, pair.substr(eq + 1)).second) {
        throw std::invalid_argument("--runs: the step " + dt_text + " is given twice");
      }
      method.steps.push_back(h);
    }
    method.run = [files](double h, int) {
      studies::ExternalLevel level;
      level.run = studies::read_run_csv(files->at(h));
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
