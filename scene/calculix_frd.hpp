#pragma once
/// \file calculix_frd.hpp
/// Reads the eigenmodes of a CalculiX `*FREQUENCY` step from its result file `JOB.frd` (ASCII,
/// as ccx writes it by default) and the eigenvalue tables of its printed output `JOB.dat`
/// (docs/calculix.md, "Files").
///
/// The .frd holds the nodes (`2C` block: id and coordinates) and, per mode, a parameter header
/// (`1PSTEP` with the step number, `1PGK` the eigenvalue ω², `1PMODE` the mode number) and a
/// `100C` result block whose value is the frequency in Hz (10 significant digits) and whose
/// `DISP` records are the mode shape at every node. Numbers in `-1` records have the fixed
/// format E12.5: **coordinates and displacements carry 6 significant digits**, the eigenvalue
/// 7, the frequency 10. Every problem is a core::InputError naming the file and the line:
/// a truncated file (no `9999` end marker, or a block that ends early), a missing, repeated or
/// unknown node in a mode, a mode number out of sequence, a binary or malformed record.
#include <Eigen/Core>
#include <istream>
#include <string>
#include <vector>

namespace flexref::scene {

/// One eigenmode of a CalculiX frequency step.
struct CalculixMode {
  int number = 0;             ///< ccx's mode number in its step (1, 2, …)
  double eigenvalue = 0.0;    ///< λ = ω² (1PGK), rad²/s²; slightly negative for rigid modes
  double frequency_hz = 0.0;  ///< the 100C value: √λ/2π, Hz (0 when λ < 0)
  /// Displacement of every node (columns in the order of CalculixModes::node_ids), ccx's
  /// normalization (unit modal mass with the consistent mass matrix).
  Eigen::Matrix3Xd shape;
  int line = 0;  ///< line of the mode's 100C record
};

/// The modes of one `*FREQUENCY` step (steps are told apart by the step number of `1PSTEP`).
struct CalculixFrequencyStep {
  int step = 0;  ///< ccx's step number
  std::vector<CalculixMode> modes;
};

struct CalculixModes {
  std::string file;
  std::vector<int> node_ids;                 ///< ccx node numbers, in file order
  Eigen::Matrix3Xd positions;                ///< node coordinates (the model's units; flexref: SI)
  std::vector<CalculixFrequencyStep> steps;  ///< frequency steps, in file order
};

/// Reads `path`. Throws core::InputError (file, line, what is wrong).
CalculixModes read_calculix_frd(const std::string& path);
/// Same, from a stream; `file_name` is used in messages.
CalculixModes parse_calculix_frd(std::istream& in, const std::string& file_name);

/// The eigenvalue table of one frequency step in a .dat file ("E I G E N V A L U E   O U T P U T").
struct CalculixEigenvalueTable {
  std::vector<double> eigenvalues;  ///< λ per mode, in order (7 significant digits)
  int line = 0;                     ///< line of the table's title
};

/// Reads every eigenvalue table of `path` (a ccx .dat file), in file order. Throws
/// core::InputError for an unreadable file or a malformed table row.
std::vector<CalculixEigenvalueTable> read_calculix_dat_eigenvalues(const std::string& path);
std::vector<CalculixEigenvalueTable> parse_calculix_dat_eigenvalues(std::istream& in,
                                                                    const std::string& file_name);

}  // namespace flexref::scene
