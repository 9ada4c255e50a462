#include "app/import_modes_command.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/output_files.hpp"
#include "core/error.hpp"
#include "io/output_file.hpp"
#include "scene/calculix_frd.hpp"
#include "scene/calculix_import.hpp"
#include "scene/calculix_import_report.hpp"
#include "scene/calculix_input_deck.hpp"
#include "scene/calculix_matrices.hpp"
#include "scene/index_ranges.hpp"
#include "scene/modal_data_reader.hpp"

namespace flexref::app {
namespace {

/// JOB for JOB.frd (the path without the extension).
std::string job_of(const std::string& frd) {
  std::filesystem::path p(frd);
  if (p.extension() == ".frd") p.replace_extension();
  return p.string();
}

std::string commented(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  for (std::string line; std::getline(in, line);) out += "# " + line + "\n";
  return out;
}

}  // namespace

int import_modes_command(const ImportModesOptions& options) {
  check_output_file(options.output, false);
  std::ostream& summary = summary_stream(options.output);
  const std::string job = job_of(options.frd);
  const scene::CalculixModes frd = scene::read_calculix_frd(options.frd);
  const scene::CalculixMatrices matrices =
      scene::read_calculix_matrices(options.matrices.empty() ? job : options.matrices);
  std::string dat_file = options.dat;
  if (dat_file.empty() && std::filesystem::is_regular_file(job + ".dat")) dat_file = job + ".dat";
  std::vector<scene::CalculixEigenvalueTable> dat;
  if (!dat_file.empty()) dat = scene::read_calculix_dat_eigenvalues(dat_file);

  scene::CalculixImportOptions import;
  import.frequency_step = options.step;
  if (!options.modes.empty()) import.modes = scene::parse_index_list(options.modes, "--modes");
  if (!options.nodes.empty()) import.nodes = scene::parse_ranges(options.nodes, "--nodes");
  // The deck: where shell and beam nodes lie and what their *BOUNDARY holds (ccx expands them
  // into solid nodes), and the node sets.
  const std::string inp = options.inp.empty() ? job + ".inp" : options.inp;
  std::optional<scene::CalculixDeck> deck;
  if (!options.inp.empty() || !options.node_set.empty() || std::filesystem::is_regular_file(inp)) {
    deck = scene::read_calculix_deck(inp);
  }
  if (!options.node_set.empty()) {
    for (const int id : scene::read_calculix_node_set(inp, options.node_set)) {
      import.nodes.emplace_back(id, id);
    }
  }
  if (options.tolerance > 0.0) import.frequency_tolerance = options.tolerance;
  const scene::CalculixImport result = scene::import_calculix_modes(
      frd, matrices, dat_file.empty() ? nullptr : &dat, import, deck ? &*deck : nullptr);

  std::ostringstream sources;
  sources << "import-modes: " << options.frd << " (modes), " << matrices.mass_file << ", "
          << matrices.stiffness_file << ", " << matrices.dof_file << " (matrices)"
          << (dat_file.empty() ? std::string(", no .dat checked") : ", " + dat_file + " (checked)")
          << (deck ? ", " + inp + " (deck)" : std::string()) << "\n";
  std::string report = sources.str() + scene::format_calculix_import_report(result);
  summary << report;
  if (!result.self_check_passed) {
    std::ostringstream difference;
    difference.precision(3);
    difference << result.max_difference;
    if (!options.accept) {
      throw core::InputError(
          options.frd, 0, "",
          "frequency self-check failed: the body's frequencies differ from CalculiX's by up to " +
              difference.str() + " (> " + number_text(result.frequency_tolerance) +
              "); refine the mesh, keep more nodes, or pass --accept; nothing written");
    }
    report += "self-check failure ACCEPTED (--accept)\n";
    summary << "self-check failure accepted (--accept)\n";
  }
  const std::string description = options.description.empty()
                                      ? "CalculiX modes of " +
                                            std::filesystem::path(options.frd).filename().string() +
                                            " (step " + std::to_string(result.frequency_step) + ")"
                                      : options.description;
  const std::string text = commented(report) + scene::format_modal_data(result.data, description);
  io::write_output_file(options.output, text);
  summary << "wrote " << options.output << " (" << result.data.node_count() << " nodes, "
          << result.data.mode_count() << " modes)\n";
  return kExitOk;
}

RegisteredCommand register_import_modes_command(CLI::App& app) {
  auto options = std::make_shared<ImportModesOptions>();
  CLI::App* cmd = app.add_subcommand(
      "import-modes", "modal-data file of a flexible body from a CalculiX frequency step");
  cmd->add_option("frd", options->frd, "CalculiX result file JOB.frd (ASCII)")->required();
  cmd->add_option("-o,--output", options->output,
                  "modal-data file to write (TOML; - for standard output; a link's target is "
                  "written, docs/output.md)")
      ->required();
  cmd->add_option("--matrices", options->matrices,
                  "base name of the .mas/.sti/.dof of the free solid (default: JOB)");
  cmd->add_option("--dat", options->dat,
                  "ccx .dat whose eigenvalue tables are checked (default: JOB.dat if present)");
  cmd->add_option("--step", options->step, "frequency step of the .frd (1: the first)")
      ->check(positive_number())
      ->capture_default_str();
  cmd->add_option("--modes", options->modes,
                  "elastic modes to keep, 1-based after rigid-body modes: e.g. 1-4,7 "
                  "(default: all)");
  auto* nodes = cmd->add_option("--nodes", options->nodes,
                                "ccx node numbers to keep, e.g. 1-20,31 (default: all)");
  cmd->add_option("--node-set", options->node_set, "a *NSET of the deck: the nodes to keep")
      ->excludes(nodes);
  cmd->add_option("--inp", options->inp,
                  "input deck: shell and beam nodes, --node-set (default: JOB.inp if present)");
  cmd->add_option("--tolerance", options->tolerance,
                  "frequency self-check, relative (default: " +
                      number_text(scene::kDefaultFrequencyTolerance) + ")")
      ->check(positive_number());
  cmd->add_flag("--accept", options->accept,
                "write the file even when the frequency self-check fails");
  cmd->add_option("--description", options->description, "description in the modal-data file");
  return {cmd, [options] { return import_modes_command(*options); }};
}

}  // namespace flexref::app
