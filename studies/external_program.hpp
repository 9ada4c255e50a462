#pragma once
/// \file external_program.hpp
/// Runs another code's integrator as a program, once per level of a study (docs/external.md):
/// a command template with `{scene}`, `{dt}` and `{output}` substituted, run by /bin/sh in its
/// own process group, its CPU time measured by wait4 (user + system time of the program and of
/// every child it waited for), killed after a timeout, its output read through a pipe while
/// it runs and only its last 64 KiB kept (a program may print its own progress, millions of
/// lines). A program that fails, times out or writes no file or a bad one is an error with its
/// exit status and the tail of its output — the study records that level as failed and goes
/// on. A program may report the CPU time of its integration alone (`# cpu_seconds = X` in its
/// file): the level's CPU time is then that report, refused when above what the process used.
#include <string>

#include "studies/convergence.hpp"

namespace flexref::studies {

struct ExternalCommand {
  std::string command;         ///< template, e.g. "python3 my_euler.py {scene} {dt} {output}"
  std::string scene;           ///< substituted for {scene}
  double timeout_seconds = 0;  ///< 0: no limit
};

/// The template with {scene}, {dt} (17 significant digits, "%.17g") and {output} replaced.
/// Paths with characters outside [A-Za-z0-9_./+:=@%,-] are single-quoted for the shell. Throws
/// std::invalid_argument when the template lacks {dt} or {output}, or has an unknown {name}.
std::string substitute_command(const std::string& command, const std::string& scene, double dt,
                               const std::string& output);

struct ProgramOutcome {
  int exit_status = -1;  ///< the exit status, −1 when killed by a signal
  int signal = 0;        ///< the signal that ended it, 0 when it exited
  bool timed_out = false;
  double cpu_seconds = 0.0;  ///< user + system CPU time (wait4), children included
  /// Last lines of its stdout and stderr (≤ 2000 characters), each line as a terminal leaves it:
  /// what follows its last carriage return (a progress line rewritten in place).
  std::string output_tail;
};

/// Runs `/bin/sh -c command_line` with stdin from /dev/null and stdout and stderr captured,
/// waits for it (killing its process group after `timeout_seconds` when > 0). Throws
/// std::runtime_error only when the program cannot be started.
ProgramOutcome run_program(const std::string& command_line, double timeout_seconds);

/// One level: substitutes, runs, and reads `output` under the contract. Its CPU time is the
/// program's `# cpu_seconds` report when the file has one (cpu_reported), else the whole
/// process's. Throws std::runtime_error describing a failure (exit status, signal or timeout,
/// output tail) or a missing file, and core::InputError for a file that breaks the contract or
/// a CPU report above the CPU time the process used (beyond 1 % + 10 ms of clock granularity).
ExternalLevel run_external_level(const ExternalCommand& command, double dt,
                                 const std::string& output);

}  // namespace flexref::studies
