#include "studies/study_output.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>

#include "io/atomic_file.hpp"

namespace {

namespace fs = std::filesystem;
using flexref::studies::StudyOutput;
using flexref::studies::StudyRecord;

/// A fresh temporary folder, removed at the end of the test.
struct TempDir {
  TempDir() {
    std::mt19937 rng(20261123u);
    path = fs::temp_directory_path() /
           ("flexref_study_output_" + std::to_string(::getpid()) + "_" + std::to_string(rng()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path path;
};

std::string read(const fs::path& p) {
  std::ifstream in(p);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Entries of a folder other than the named ones (staging or previous folders left behind).
int leftovers(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    n += e.path().filename().string().starts_with(".") ? 1 : 0;
  }
  return n;
}

TEST_CASE("a committed study replaces the previous one as a whole", "[study_output]") {
  TempDir tmp;
  const fs::path dir = tmp.path / "out" / "converge";
  {
    StudyOutput out(dir);
    out.write("a.csv", "old\n");
    out.write("old_only.txt", "stale\n");
    CHECK(!fs::exists(dir));  // nothing is visible before commit
    out.commit(StudyRecord{});
  }
  CHECK(read(dir / "a.csv") == "old\n");
  {
    StudyOutput out(dir);
    out.write("a.csv", "new\n");
    out.commit(StudyRecord{});
  }
  CHECK(read(dir / "a.csv") == "new\n");
  CHECK(!fs::exists(dir / "old_only.txt"));  // no old file beside the new ones
  CHECK(read(dir / "study.toml").find("written = [\"a.csv\", \"study.toml\"]") !=
        std::string::npos);
  CHECK(leftovers(dir.parent_path()) == 0);
}

TEST_CASE("an interrupted study leaves the previous folder untouched", "[study_output]") {
  TempDir tmp;
  const fs::path dir = tmp.path / "converge";
  {
    StudyOutput out(dir);
    out.write("convergence.csv", "old\n");
    out.commit(StudyRecord{});
  }
  try {
    StudyOutput out(dir);
    out.write("convergence.csv", "new\n");
    throw std::runtime_error("interrupted");
  } catch (const std::runtime_error&) {
  }
  CHECK(read(dir / "convergence.csv") == "old\n");
  CHECK(leftovers(tmp.path) == 0);
}

TEST_CASE("output folders are validated before any work", "[study_output]") {
  TempDir tmp;
  using flexref::io::OutputError;
  std::ofstream(tmp.path / "file.toml") << "x = 1\n";
  // A path below a file.
  CHECK_THROWS_AS(StudyOutput(tmp.path / "file.toml" / "sub"), OutputError);
  // A file where the folder should be.
  CHECK_THROWS_AS(StudyOutput(tmp.path / "file.toml"), OutputError);
  // A folder that is not a study's: never swept away.
  fs::create_directories(tmp.path / "src" / "nested");
  std::ofstream(tmp.path / "src" / "main.cpp") << "int main() {}\n";
  CHECK_THROWS_AS(StudyOutput(tmp.path / "src"), OutputError);
  CHECK(fs::exists(tmp.path / "src" / "main.cpp"));
  // A non-empty folder without study.toml.
  fs::create_directories(tmp.path / "data");
  std::ofstream(tmp.path / "data" / "x.csv") << "t\n0\n";
  CHECK_THROWS_AS(StudyOutput(tmp.path / "data"), OutputError);
  // A read-only parent (root may write anyway: check only when the mode is enforced).
  fs::create_directories(tmp.path / "ro");
  ::chmod((tmp.path / "ro").c_str(), 0500);
  if (::access((tmp.path / "ro").c_str(), W_OK) != 0) {
    CHECK_THROWS_AS(StudyOutput(tmp.path / "ro" / "out"), OutputError);
  }
  ::chmod((tmp.path / "ro").c_str(), 0700);
  // An empty folder is fine.
  fs::create_directories(tmp.path / "empty");
  CHECK_NOTHROW(StudyOutput(tmp.path / "empty"));
}

}  // namespace
