#pragma once
/// \file exit_codes.hpp
/// The exit codes of `flexref`: the one table of docs/cli.md ("Exit codes", the reasons in
/// docs/decisions.md, "Command line"), printed by `flexref --help` (app/help_text.hpp,
/// kExitCodeTable). app/main.cpp maps the errors a command throws to them.

namespace flexref::app {

inline constexpr int kExitOk = 0;
inline constexpr int kExitInputError = 1;   ///< bad scene, CSV, study file or option value
inline constexpr int kExitUsage = 2;        ///< command-line syntax (CLI11 parse errors)
inline constexpr int kExitSolverError = 3;  ///< an integrator failed (time, step, why)
inline constexpr int kExitRefused = 4;      ///< a study refused to report (uncertified, < 3 levels)
inline constexpr int kExitOutputError = 5;  ///< an output file or folder cannot be written

}  // namespace flexref::app
