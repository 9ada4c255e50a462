#pragma once
/// \file atomic_file.hpp
/// Writing result files so that an interrupted run never leaves a half-written one: the text
/// goes to a temporary file in the same directory, which is then renamed onto the target
/// (rename is atomic within a file system, POSIX rename(2)).
#include <stdexcept>
#include <string>

namespace flexref::io {

/// A result file or folder that cannot be written (missing or read-only directory, full disk,
/// a path that names a file where a folder is needed). Says which path and why.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Checks, before any work, that write_file_atomically(path, …) can succeed as far as the file
/// system can tell: the path is not empty, does not name a directory, and its directory exists
/// and is writable. Throws OutputError naming the path and the reason.
void check_writable_file(const std::string& path);

/// Writes text to path atomically (temporary file + rename); throws OutputError naming the
/// path when the directory is missing or the write fails.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace flexref::io
