#pragma once
/// \file output_file.hpp
/// How every file flexref writes reaches the path the user named (docs/decisions.md,
/// "Outputs"), without ever replacing what that path points to:
///
/// - symbolic links are followed and their target is written (a link stays a link; a dangling
///   link creates its target);
/// - a regular file, or a path that does not exist yet, is written atomically: a temporary file
///   beside the target, renamed onto it when complete (POSIX rename(2)), so an interrupted run
///   never leaves a half-written file; the file keeps its permission bits;
/// - a character device (/dev/null, a terminal) or a FIFO is written directly: no temporary, no
///   rename, no sidecar beside it;
/// - `-` is standard output, and a path that names one of the program's own open descriptors
///   (/dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N) is that descriptor, written as it
///   is (a shell's `>>` still appends), never the file behind it;
/// - a directory, a block device (a disk) or a socket, a read-only file or a file in a read-only
///   directory is refused with OutputError (exit 5), before anything is touched. Read-only means
///   what the permission bits say, for root as well: a file or folder whose mode grants nobody
///   write permission is not written even where root could.
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

namespace flexref::io {

/// A result file or folder that cannot be written (missing or read-only directory, full disk,
/// a path that names a file where a folder is needed). Says which path and why.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What an output path names, once its symbolic links are followed.
struct OutputTarget {
  enum class Kind {
    kDescriptor,  ///< `-` (descriptor 1), /dev/stdout, /dev/fd/N …: written to the descriptor
    kFile,        ///< a regular file, or nothing yet: written atomically
    kSpecial,     ///< a character device or a FIFO: written directly
  };
  std::string named;             ///< the path as given
  std::filesystem::path target;  ///< the file written: `named` with every link followed
  Kind kind = Kind::kFile;
  int descriptor = -1;  ///< for kDescriptor
  /// "a new file", "a file", "a FIFO", "a character device", "standard output", "descriptor 3"
  std::string description;

  bool is_standard_output() const { return kind == Kind::kDescriptor && descriptor == 1; }
};

/// Resolves `path` under the rule above and checks, before any work, that it can be written as
/// far as the file system can tell (the target is not a directory, its directory exists and is
/// writable, the target is not read-only). Opens, creates and changes nothing (opening a FIFO
/// would wake its reader). Throws OutputError naming the path and the reason.
OutputTarget resolve_output(const std::string& path);

/// resolve_output, for its checks alone.
void check_writable_file(const std::string& path);

/// Writes `text` to `path` under the rule above. Throws OutputError naming the path and the
/// reason; a failed write leaves the target as it was (for a regular file) and no temporary.
void write_output_file(const std::string& path, const std::string& text);

/// Where the metadata sidecar of an output goes: `TARGET.meta.toml` beside the file actually
/// written (links followed), or nothing when the output is a descriptor (standard output), a
/// device or a FIFO (a sidecar beside a device would be a stray file in /dev). Throws
/// OutputError as resolve_output.
std::optional<std::string> sidecar_path(const std::string& output);

/// Refuses (OutputError naming `what` and the reason) a directory that files cannot be created
/// in: missing, not a directory, not writable, or read-only by its permission bits.
void check_writable_directory(const std::filesystem::path& directory, const std::string& what);

/// `path` with the symbolic links of its last component followed one by one (those of the
/// folders above are the kernel's to follow), up to a path that is not a link or does not exist
/// (a dangling link resolves to where it points). Throws OutputError on a loop of links.
std::filesystem::path follow_links(const std::filesystem::path& path);

}  // namespace flexref::io
