#include "studies/plot.hpp"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "studies/external_program.hpp"

namespace flexref::studies {
namespace {

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

/// The last non-empty line of a program's output, for a one-line message.
std::string last_line(const std::string& text) {
  const auto end = text.find_last_not_of(" \n\r");
  if (end == std::string::npos) return "";
  const auto start = text.find_last_of('\n', end);
  return text.substr(start == std::string::npos ? 0 : start + 1,
                     end + 1 - (start == std::string::npos ? 0 : start + 1));
}

// The scripts run through run_program (studies/external_program.hpp), not std::system: that
// blocks SIGCHLD and ignores SIGINT in flexref while the script runs and hands the script
// flexref's blocked signals, so an interrupt would be lost (io/interrupt_cleanup.hpp). Their
// output is captured; a failure's last line goes into the message.
bool imports_matplotlib(const std::string& python) {
  try {
    return run_program(shell_quote(python) + " -c 'import matplotlib'", 0.0).exit_status == 0;
  } catch (const std::runtime_error&) {
    return false;
  }
}

std::string script_path(const std::string& script) {
  if (const char* dir = std::getenv("FLEXREF_PLOT_SCRIPT_DIR")) {
    return (std::filesystem::path(dir) / script).string();
  }
  return (std::filesystem::path(FLEXREF_PLOT_SCRIPT_DIR) / script).string();
}

}  // namespace

std::string find_python_with_matplotlib() {
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("FLEXREF_PYTHON")) candidates.emplace_back(env);
  candidates.emplace_back("/usr/bin/python3");
  candidates.emplace_back("python3");
  for (const auto& c : candidates) {
    if (imports_matplotlib(c)) return c;
  }
  return {};
}

PlotOutcome run_plot_script(const std::string& script, std::vector<std::string> arguments,
                            const std::string& png_path) {
  const std::string python = find_python_with_matplotlib();
  if (python.empty()) {
    return {false,
            "no plot: no Python with matplotlib found (tried $FLEXREF_PYTHON, /usr/bin/python3, "
            "python3; on Debian: apt-get install python3-matplotlib)"};
  }
  const std::string path = script_path(script);
  if (!std::filesystem::exists(path)) return {false, "no plot: script " + path + " not found"};
  const std::string temp = png_path + ".tmp.png";
  std::string cmd = shell_quote(python) + " " + shell_quote(path);
  for (std::size_t i = 0; i < arguments.size(); ++i) {
    cmd += " " + shell_quote(arguments[i] == png_path ? temp : arguments[i]);
  }
  ProgramOutcome outcome;
  try {
    outcome = run_program(cmd, 0.0);
  } catch (const std::runtime_error& e) {
    return {false, std::string("no plot: ") + e.what()};
  }
  if (outcome.exit_status != 0) {
    std::error_code ignore;
    std::filesystem::remove(temp, ignore);
    const std::string why = last_line(outcome.output_tail);
    return {false, "no plot: " + script + " failed (" + python + ")" +
                       (why.empty() ? std::string() : ": " + why)};
  }
  std::error_code ec;
  std::filesystem::rename(temp, png_path, ec);
  if (ec) return {false, "no plot: cannot rename " + temp + ": " + ec.message()};
  return {true, png_path};
}

}  // namespace flexref::studies
