#pragma once
/// \file error.hpp
/// Exceptions that carry where a failure happened, so the command line can report it.
#include <stdexcept>
#include <string>

namespace flexref::core {

/// Bad user input: a scene, modal-data or result file. Names the file, line and key.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, std::string key, const std::string& what);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
};

/// An integrator that cannot continue: says at which time and step, and why (a negative step:
/// the step is not known, e.g. a failure found in a solver's output).
class SolverError : public std::runtime_error {
 public:
  SolverError(std::string solver, double time, long step, const std::string& why);
  const std::string& solver() const { return solver_; }
  double time() const { return time_; }
  long step() const { return step_; }
  /// The reason alone, without the solver, time and step.
  const std::string& why() const { return why_; }

 private:
  std::string solver_;
  double time_;
  long step_;
  std::string why_;
};

}  // namespace flexref::core
