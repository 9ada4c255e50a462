#pragma once
/// \file reference_solver_name.hpp
/// The reference solver a user names (--solver, --reference-solver, a study file's `solver`,
/// Python's solver=) and its method (--method): parsed once where they enter, passed on by name
/// to reference/ (reference::solve_reference and trajectory::certified_reference take the name).
#include <string_view>

namespace flexref::studies {

enum class ReferenceSolver {
  kAuto,    ///< chosen from the model (reference::choose_reference_solver)
  kIda,     ///< SUNDIALS IDA (implicit DAE)
  kCvode,   ///< SUNDIALS CVODE (Adams or BDF)
  kArkode,  ///< SUNDIALS ARKODE (ERK or ESDIRK)
  kOdeint,  ///< Boost.Odeint (RKF7(8); Bulirsch-Stoer beyond double)
  kExact,   ///< the closed-form solution of the scene
};

/// "auto", "ida", "cvode", "arkode", "odeint" or "exact"; throws std::invalid_argument naming
/// the accepted values.
ReferenceSolver parse_reference_solver(std::string_view name);
const char* to_string(ReferenceSolver solver);

/// The method a user names for the reference solver (reference's --method): CVODE's Adams or
/// BDF, IDA's BDF order cap, ARKODE's explicit or implicit method, or auto (from the scene).
enum class ReferenceMethod { kAuto, kAdams, kBdf, kBdf2, kErk, kEsdirk };

/// "auto", "adams", "bdf", "bdf2", "erk" or "esdirk"; throws std::invalid_argument naming the
/// accepted values.
ReferenceMethod parse_reference_method(std::string_view name);
const char* to_string(ReferenceMethod method);

}  // namespace flexref::studies
