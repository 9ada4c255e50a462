#include "io/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <system_error>

namespace flexref::io {

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
