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

ReferenceMethod parse_reference_method(std::string_view name) {
  if (name == "auto") return ReferenceMethod::kAuto;
  if (name == "adams") return ReferenceMethod::kAdams;
  if (name == "bdf") return ReferenceMethod::kBdf;
  if (name == "bdf2") return ReferenceMethod::kBdf2;
  if (name == "erk") return ReferenceMethod::kErk;
  if (name == "esdirk") return ReferenceMethod::kEsdirk;
  throw std::invalid_argument("reference method '" + std::string(name) +
                              "': expected auto, adams, bdf, bdf2, erk or esdirk");
}

const char* to_string(ReferenceMethod method) {
  switch (method) {
    case ReferenceMethod::kAuto:
      return "auto";
    case ReferenceMethod::kAdams:
      return "adams";
    case ReferenceMethod::kBdf:
      return "bdf";
    case ReferenceMethod::kBdf2:
      return "bdf2";
    case ReferenceMethod::kErk:
      return "erk";
    case ReferenceMethod::kEsdirk:
      return "esdirk";
  }
  return "auto";
}

}  // namespace flexref::studies
