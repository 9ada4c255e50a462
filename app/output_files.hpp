#pragma once
/// \file output_files.hpp
/// The output file of `run`, `reference` and `import-modes`, its metadata sidecar
/// (FILE.meta.toml, io::sidecar_path), and where a command's summary goes, under the output
/// rule (io/output_file.hpp, docs/output.md).
#include <ostream>
#include <string>

#include "studies/study_record.hpp"

namespace flexref::app {

/// The output file and, when it gets one, its sidecar, checked before any work
/// (io::OutputError).
void check_output_file(const std::string& output, bool with_sidecar);
/// Writes `record` as the sidecar of `output` (io::sidecar_path) or, when the output is
/// standard output, another descriptor, a device or a FIFO, says on stderr that none is written.
void write_sidecar(const studies::StudyRecord& record, const std::string& output);
/// Where a command's summary goes: standard error when its output file is standard output (so
/// that standard output carries the data alone), standard output otherwise.
std::ostream& summary_stream(const std::string& output);

}  // namespace flexref::app
