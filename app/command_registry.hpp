#pragma once
/// \file command_registry.hpp
/// The `flexref` subcommands: each command's file adds its subcommand and options to the app
/// and returns how to run it (register_<command>_command); app/main.cpp calls them in the
/// help's order, parses, and runs the one given.
#include <CLI/CLI.hpp>
#include <functional>

namespace flexref::app {

struct RegisteredCommand {
  CLI::App* command = nullptr;  ///< the subcommand; `*command` is true when it was given
  /// Runs the command with the parsed options; returns the exit code and throws the errors
  /// main.cpp maps to exit codes.
  std::function<int()> run;
};

RegisteredCommand register_check_command(CLI::App& app);
RegisteredCommand register_run_command(CLI::App& app);
RegisteredCommand register_reference_command(CLI::App& app);
RegisteredCommand register_compare_command(CLI::App& app);
RegisteredCommand register_converge_command(CLI::App& app);
RegisteredCommand register_work_precision_command(CLI::App& app);
RegisteredCommand register_stability_command(CLI::App& app);
RegisteredCommand register_figure_command(CLI::App& app);
RegisteredCommand register_lte_map_command(CLI::App& app);
RegisteredCommand register_import_modes_command(CLI::App& app);
RegisteredCommand register_modal_truncation_command(CLI::App& app);
RegisteredCommand register_wear_command(CLI::App& app);
RegisteredCommand register_wear_jump_command(CLI::App& app);

}  // namespace flexref::app
