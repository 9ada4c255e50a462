/// \file main.cpp
/// The `flexref` command line (CLI11): assembles the subcommands (each registered by its own
/// file, app/command_registry.hpp), parses, runs the one given and maps its errors to exit codes
/// (one table: app/exit_codes.hpp, docs/decisions.md "Command line", the --help epilogue): 0
/// success, 1 bad input, 2 usage, 3 solver failure, 4 a study refused to report, 5 an output
/// cannot be written.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/help_text.hpp"
#include "core/error.hpp"
#include "io/interrupt_cleanup.hpp"
#include "io/output_file.hpp"
#include "studies/mpi/distribution.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/study_refused.hpp"

namespace {

int run_command_line(int argc, char** argv) {
  using namespace flexref::app;
  CLI::App app{
      "flexref: trusted reference solutions for rigid and flexible bodies in large rotation "
      "(with contact and joints), and the verification of time integrators against them"};
  app.require_subcommand(1);
  app.footer(kExitCodeTable);
  app.set_version_flag("--version", "flexref 0.1.0");
  // In the order of `flexref --help`.
  const std::vector<RegisteredCommand> commands = {
      register_check_command(app),
      register_run_command(app),
      register_reference_command(app),
      register_compare_command(app),
      register_converge_command(app),
      register_work_precision_command(app),
      register_stability_command(app),
      register_figure_command(app),
      register_lte_map_command(app),
      register_import_modes_command(app),
      register_modal_truncation_command(app),
      register_wear_command(app),
      register_wear_jump_command(app),
  };

  // An unknown command is a usage error that names it (CLI11 would say "A subcommand is
  // required").
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    std::string names;
    for (const CLI::App* sub : app.get_subcommands({})) {
      known = known || sub->get_name() == argv[1];
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::fprintf(stderr, "flexref: unknown command '%s'; the commands are %s (flexref --help)\n",
                   argv[1], names.c_str());
      return kExitUsage;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every parse error is a usage error (CLI11's own codes,
    // 105, 106 …, are not part of the table).
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }

  try {
    for (const RegisteredCommand& command : commands) {
      if (*command.command) return command.run();
    }
  } catch (const flexref::core::InputError& e) {
    std::fprintf(stderr, "flexref: error: %s\n", e.what());
    return kExitInputError;
  } catch (const flexref::core::SolverError& e) {
    std::fprintf(stderr, "flexref: solver error: %s\n", e.what());
    return kExitSolverError;
  } catch (const flexref::trajectory::StudyRefused& e) {
    std::fprintf(stderr, "flexref: refused: %s\n", e.what());
    return kExitRefused;
  } catch (const flexref::io::OutputError& e) {
    std::fprintf(stderr, "flexref: output error: %s\n", e.what());
    return kExitOutputError;
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "flexref: output error: %s\n", e.what());
    return kExitOutputError;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "flexref: error: %s\n", e.what());
    return kExitInputError;
  } catch (const std::exception& e) {
    // Anything else happened while computing (no input or output error type reached here).
    std::fprintf(stderr, "flexref: failure: %s\n", e.what());
    return kExitSolverError;
  }
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  // First, before any thread exists: SIGINT, SIGTERM and SIGHUP remove the unfinished outputs
  // (io/interrupt_cleanup.hpp).
  flexref::io::install_interrupt_cleanup();
  // One process, or a rank of an MPI job (studies/mpi/distribution.hpp, docs/mpi.md).
  flexref::studies::ProcessSession session(argc, argv);
  return session.finish(run_command_line(argc, argv));
}
