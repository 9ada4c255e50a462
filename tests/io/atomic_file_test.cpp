#include "io/atomic_file.hpp"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

namespace flexref::io {
namespace {

namespace fs = std::filesystem;

std::string message_of(const std::string& path) {
  try {
    check_writable_file(path);
  } catch (const OutputError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("check_writable_file refuses paths that cannot be written, before any work", "[io]") {
  const fs::path dir =
      fs::temp_directory_path() / ("flexref_io_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "file.toml") << "x";

  CHECK(message_of("").find("empty") != std::string::npos);
  CHECK(message_of(dir.string()).find("is a directory") != std::string::npos);
  CHECK(message_of((dir / "missing" / "x.csv").string()).find("does not exist") !=
        std::string::npos);
  // `--out base.toml/sub`: the parent is a file.
  CHECK(message_of((dir / "file.toml" / "x.csv").string()).find("is not a directory") !=
        std::string::npos);
  CHECK(message_of((dir / "x.csv").string()).empty());
  CHECK_FALSE(fs::exists(dir / "x.csv"));  // a check writes nothing
  fs::remove_all(dir);
}

}  // namespace
}  // namespace flexref::io
