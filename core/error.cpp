#include "core/error.hpp"

#include <sstream>
#include <utility>

namespace flexref::core {
namespace {

std::string input_message(const std::string& file, int line, const std::string& key,
                          const std::string& what) {
  std::ostringstream out;
  out << file;
  if (line > 0) out << ':' << line;
  out << ": ";
  if (!key.empty()) out << "key '" << key << "': ";
  out << what;
  return out.str();
}

std::string solver_message(const std::string& solver, double time, long step,
                           const std::string& why) {
  std::ostringstream out;
  out.precision(17);
  out << solver << " failed at t = " << time;
  if (step >= 0) out << " (step " << step << ")";
  out << ": " << why;
  return out.str();
}

}  // namespace

InputError::InputError(std::string file, int line, std::string key, const std::string& what)
    : std::runtime_error(input_message(file, line, key, what)),
      file_(std::move(file)),
      line_(line),
      key_(std::move(key)) {}

SolverError::SolverError(std::string solver, double time, long step, const std::string& why)
    : std::runtime_error(solver_message(solver, time, step, why)),
      solver_(std::move(solver)),
      time_(time),
      step_(step),
      why_(why) {}

}  // namespace flexref::core
