#pragma once
/// \file import_modes_command.hpp
/// `flexref import-modes JOB.frd -o BODY.modal.toml`: the modes of a CalculiX frequency step as
/// a modal-data file (scene/calculix_import.hpp, docs/calculix.md). Prints the import report
/// (mass properties, removed rigid-body modes, frequency self-check) and records it as comments
/// at the top of the file; writes nothing when a check fails (the self-check unless --accept).
#include <string>

namespace flexref::app {

struct ImportModesOptions {
  std::string frd;         ///< JOB.frd
  std::string output;      ///< the modal-data file to write
  std::string matrices;    ///< base of .mas/.sti/.dof (default: JOB)
  std::string dat;         ///< eigenvalue tables to check (default: JOB.dat when it exists)
  std::string inp;         ///< deck for --node-set (default: JOB.inp)
  int step = 1;            ///< frequency step (1: the first)
  std::string modes;       ///< "1-4,7": elastic modes (default: all)
  std::string nodes;       ///< "1-20,31": ccx node numbers to keep (default: all)
  std::string node_set;    ///< a *NSET of the deck: the nodes to keep
  double tolerance = 0.0;  ///< frequency self-check (0: the default)
  bool accept = false;
  std::string description;
};

int import_modes_command(const ImportModesOptions& options);

}  // namespace flexref::app
