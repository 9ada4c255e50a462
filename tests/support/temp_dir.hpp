#pragma once
/// \file temp_dir.hpp
/// The one place where tests get a folder to write into. Every test that writes a file writes
/// it inside a TempDir of its own: a new folder with a unique name (mkdtemp), removed with
/// everything in it when the TempDir goes out of scope. Fixed names in the shared temporary
/// folder collide when two builds' suites run at once (Release and sanitizers in CI) and leave
/// files behind that change the next run's verdict.
#include <filesystem>
#include <string>
#include <string_view>

namespace flexref::testing {

class TempDir {
 public:
  /// Makes "flexref-<label>-XXXXXX" (mode 0700) in the system's temporary folder ($TMPDIR, else
  /// /tmp) with mkdtemp. Throws std::runtime_error when it cannot.
  explicit TempDir(std::string_view label = "test");
  /// Removes the folder and everything in it: symbolic links inside are removed, never
  /// followed; folders a test made read-only are made writable first.
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// path() / name.
  std::filesystem::path operator/(const std::filesystem::path& name) const { return path_ / name; }
  /// Writes `text` to path() / name (parent folders made as needed) and returns that path.
  std::filesystem::path write(const std::filesystem::path& name, std::string_view text) const;

 private:
  std::filesystem::path path_;
};

}  // namespace flexref::testing
