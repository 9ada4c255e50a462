#include "studies/reference_solver_name.hpp"

#include <stdexcept>
#include <string>

namespace flexref::studies {

ReferenceSolver parse_reference_solver(std::string_view name) {
  if (name == "auto") return ReferenceSolver::kAuto;
  if (name == "ida") return ReferenceSolver::kIda;
  if (name == "cvode") return ReferenceSolver::kCvode;
  if (name == "arkode") return ReferenceSolver::kArkode;
  if (name == "odeint") return ReferenceSolver::kOdeint;
  if (name == "exact") return ReferenceSolver::kExact;
  throw std::invalid_argument("reference solver '" + std::string(name) +
                              "': expected auto, ida, cvode, arkode, odeint or exact");
}

const char* to_string(ReferenceSolver solver) {
  switch (solver) {
    case ReferenceSolver::kAuto:
      return "auto";
    case ReferenceSolver::kIda:
      return "ida";
    case ReferenceSolver::kCvode:
      return "cvode";
    case ReferenceSolver::kArkode:
      return "arkode";
    case ReferenceSolver::kOdeint:
      return "odeint";
    case ReferenceSolver::kExact:
      return "exact";
  }
  return "auto";
}

}  // namespace flexref::studies
