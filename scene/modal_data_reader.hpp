#pragma once
/// \file modal_data_reader.hpp
/// Reads and writes modal-data files: the modes of a flexible body from the user's own
/// finite-element code, or exported from the built-in beam model. The format is TOML, like
/// scene files, and is documented key by key in docs/modal_data.md.
///
/// Every problem is reported as a core::InputError that names the file, the line and the key
/// (`nodes[3].mass`, `mode[2].shape[17]`: tables and rows count from 1 like in the file) and
/// says what is expected; nothing else escapes, whatever the file contains. The reader lives
/// in scene/ because flexible/ and core/ know no file format (docs/design/README.md); it
/// builds a flexible::ModalData.
#include <string>

#include "flexible/modal_data.hpp"

namespace flexref::scene {

/// Value of the required top-level key `format`.
inline constexpr const char* kModalDataFormat = "flexref-modal-data";
/// Default of `modal_mass_tolerance`: the relative difference allowed between a mode's
/// `modal_mass` and the nodal sum Σ m_k |Φ_k|².
inline constexpr double kDefaultModalMassTolerance = 1e-3;

/// Reads and validates the modal-data file at `path`. Throws core::InputError.
flexible::ModalData read_modal_data(const std::string& path);

/// Same, from text in memory; `file_name` is only used in messages.
flexible::ModalData parse_modal_data(const std::string& text, const std::string& file_name);

/// The data as a modal-data file: every number in the shortest form that reads back as the
/// same double (so write → read is exact), the stiffness given as `stiffness`, the nodal-sum
/// modal mass as `modal_mass`, and the frequency as a comment. Validates the data first;
/// throws std::invalid_argument when it is invalid or a node or mode name is not writable
/// (names: ASCII letters, digits, '_' and '-').
std::string format_modal_data(const flexible::ModalData& data, const std::string& description = "");

/// format_modal_data written to `path` under the output rule (io/output_file.hpp: atomically
/// for a file, through links, directly to a FIFO or device). Throws std::invalid_argument (bad
/// data) or io::OutputError (I/O).
void write_modal_data(const flexible::ModalData& data, const std::string& path,
                      const std::string& description = "");

}  // namespace flexref::scene
