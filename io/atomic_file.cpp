#include "io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <system_error>

namespace flexref::io {

void check_writable_file(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) throw OutputError("cannot write an output file: the path is empty");
  const fs::path target(path);
  std::error_code ec;
  if (fs::is_directory(target, ec)) {
    throw OutputError("cannot write " + path + ": it is a directory; give a file name");
  }
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const fs::file_status status = fs::status(dir, ec);
  if (!fs::exists(status)) {
    throw OutputError("cannot write " + path + ": directory " + dir.string() + " does not exist");
  }
  if (!fs::is_directory(status)) {
    throw OutputError("cannot write " + path + ": " + dir.string() + " is not a directory");
  }
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    throw OutputError("cannot write " + path + ": directory " + dir.string() +
                      " is not writable (" + std::strerror(errno) + ")");
  }
}

void write_file_atomically(const std::string& path, const std::string& text) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  if (target.has_parent_path() && !fs::exists(target.parent_path())) {
    throw OutputError("cannot write " + path + ": directory " + target.parent_path().string() +
                      " does not exist");
  }
  std::random_device rd;
  const fs::path temp = target.string() + ".tmp" + std::to_string(rd() % 1000000u);
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out) throw OutputError("cannot write " + temp.string() + ": " + std::strerror(errno));
    out << text;
    out.flush();
    if (!out) {
      std::error_code ignore;
      fs::remove(temp, ignore);
      throw OutputError("write to " + temp.string() + " failed");
    }
  }
  std::error_code ec;
  fs::rename(temp, target, ec);
  if (ec) {
    std::error_code ignore;
    fs::remove(temp, ignore);
    throw OutputError("cannot rename " + temp.string() + " to " + path + ": " + ec.message());
  }
}

}  // namespace flexref::io
