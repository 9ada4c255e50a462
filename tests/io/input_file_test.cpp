#include "io/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/temp_dir.hpp"

namespace flexref::io {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

/// This test's own folder (tests/support/temp_dir.hpp).
using InputFileTempDir = testing::TempDir;

TEST_CASE("regular files and links to them are read whole and line by line", "[io]") {
  InputFileTempDir tmp;
  // More than one 64 KiB block, so the reader refills its buffer.
  std::string text;
  for (int i = 0; i < 20000; ++i) text += "line " + std::to_string(i) + "\n";
  std::ofstream(tmp.path() / "a.csv", std::ios::binary) << text;
  fs::create_symlink("a.csv", tmp.path() / "link.csv");

  InputFile whole((tmp.path() / "link.csv").string(), "a CSV file");
  REQUIRE(whole.is_open());
  CHECK(whole.error().empty());
  CHECK(whole.read_all() == text);

  InputFile lines((tmp.path() / "a.csv").string(), "a CSV file");
  std::string line;
  int count = 0;
  std::string last;
  while (std::getline(lines, line)) {
    ++count;
    last = line;
  }
  CHECK(count == 20000);
  CHECK(last == "line 19999");
}

TEST_CASE("what is not a regular file is refused before it is opened", "[io]") {
  InputFileTempDir tmp;
  const auto refused = [](const fs::path& path) {
    InputFile in(path.string(), "the scene file");
    CHECK_FALSE(in.is_open());
    CHECK_FALSE(static_cast<bool>(in));
    std::string line;
    CHECK_FALSE(std::getline(in, line));
    return in.error();
  };
  CHECK_THAT(refused(tmp.path() / "missing.toml"),
             Contains("cannot open the scene file") && Contains("No such file"));
  CHECK_THAT(refused(tmp.path()), Contains("is a directory; expected the scene file"));
  // A FIFO without a writer: an open for reading would wait for ever; refused at once.
  const fs::path fifo = tmp.path() / "fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THAT(refused(fifo), Contains("is a FIFO"));
  // A link to it as well.
  fs::create_symlink("fifo", tmp.path() / "scene.toml");
  CHECK_THAT(refused(tmp.path() / "scene.toml"), Contains("is a FIFO"));
}

}  // namespace
}  // namespace flexref::io
