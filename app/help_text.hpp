#pragma once
/// \file help_text.hpp
/// Help text that several `flexref` commands print, written once: the exit-code table of the
/// --help epilogue and the output rule in the help of every option that takes an output path.

namespace flexref::app {

/// The exit codes (app/exit_codes.hpp, docs/cli.md "Exit codes") as `--help` prints them.
inline constexpr const char* kExitCodeTable =
    "Exit codes: 0 success, 1 bad input (scene, CSV, study file, option value), 2 usage "
    "(command-line syntax), 3 solver failure, 4 a study refused to report (e.g. an uncertified "
    "reference, fewer than three valid levels), 5 an output file or folder cannot be written. "
    "Interrupted by SIGINT, SIGTERM or SIGHUP, flexref removes its unfinished outputs and ends "
    "by the signal (shell status 128+N: 130, 143, 129).";

/// The output rule (io/output_file.hpp, docs/output.md "Where outputs go") in the help of an
/// output file option (-o) and of an output folder option (--out).
inline constexpr const char* kOutputFileHelp =
    "file to write; - for standard output; a symbolic link's target is written, a FIFO or "
    "device directly (no .meta.toml sidecar then); docs/output.md";
inline constexpr const char* kOutputFolderHelp =
    "output directory, replaced as a whole when the study completes (a link to a folder stays "
    "a link; docs/output.md)";

}  // namespace flexref::app
