/// \file output_files.cpp
/// The output file of `run`, `reference` and `import-modes`, its sidecar, and where the
/// command's summary goes, under the output rule (io/output_file.hpp, docs/output.md).
#include "app/output_files.hpp"

#include <cstdio>
#include <iostream>
#include <optional>

#include "io/output_file.hpp"

namespace flexref::app {

void check_output_file(const std::string& output, bool with_sidecar) {
  io::check_writable_file(output);
  if (!with_sidecar) return;
  if (const std::optional<std::string> sidecar = io::sidecar_path(output)) {
    io::check_writable_file(*sidecar);
  }
}

void write_sidecar(const studies::StudyRecord& record, const std::string& output) {
  const io::OutputTarget target = io::resolve_output(output);
  if (const std::optional<std::string> sidecar = io::sidecar_path(output)) {
    record.write(*sidecar);
    return;
  }
  std::fprintf(stderr,
               "flexref: note: %s is %s: its metadata sidecar (.meta.toml) is not written; give "
               "a file name to keep it\n",
               output.c_str(), target.description.c_str());
}

std::ostream& summary_stream(const std::string& output) {
  try {
    if (io::resolve_output(output).is_standard_output()) return std::cerr;
  } catch (const io::OutputError&) {
    // Reported by the write itself.
  }
  return std::cout;
}

}  // namespace flexref::app
