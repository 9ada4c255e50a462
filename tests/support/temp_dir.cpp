#include "tests/support/temp_dir.hpp"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace flexref::testing {

namespace fs = std::filesystem;

TempDir::TempDir(std::string_view label) {
  const fs::path pattern =
      fs::temp_directory_path() / ("flexref-" + std::string(label) + "-XXXXXX");
  std::string buffer = pattern.string();
  if (::mkdtemp(buffer.data()) == nullptr) {
    throw std::runtime_error("TempDir: cannot make a folder like " + pattern.string() + ": " +
                             std::generic_category().message(errno));
  }
  path_ = buffer;
}

TempDir::~TempDir() {
  // Only what the constructor made: a "flexref-…" folder directly in the temporary folder.
  if (path_.empty() || !path_.filename().string().starts_with("flexref-")) return;
  // Owner read, write and search permission on every folder below (each before the iteration
  // enters it; links are not followed), so that removal works for a user other than root after
  // a test made a folder read-only.
  std::error_code ignored;
  fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ignored);
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(path_, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (it->is_directory(ignored) && !it->is_symlink(ignored)) {
      fs::permissions(it->path(), fs::perms::owner_all, fs::perm_options::add, ignored);
    }
  }
  fs::remove_all(path_, ignored);
}

fs::path TempDir::write(const fs::path& name, std::string_view text) const {
  const fs::path file = path_ / name;
  fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("TempDir: cannot write " + file.string());
  return file;
}

}  // namespace flexref::testing
