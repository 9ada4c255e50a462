#include "studies/study_output.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>

#include "io/output_file.hpp"
#include "tests/support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using flexref::studies::StudyOutput;
using flexref::studies::StudyRecord;

using flexref::testing::TempDir;  // this test's own folder (tests/support/temp_dir.hpp)

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
  const fs::path dir = tmp.path() / "out" / "converge";
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
  const fs::path dir = tmp.path() / "converge";
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
  CHECK(leftovers(tmp.path()) == 0);
}

TEST_CASE("output folders are validated before any work", "[study_output]") {
  TempDir tmp;
  using flexref::io::OutputError;
  std::ofstream(tmp.path() / "file.toml") << "x = 1\n";
  // A path below a file.
  CHECK_THROWS_AS(StudyOutput(tmp.path() / "file.toml" / "sub"), OutputError);
  // A file where the folder should be.
  CHECK_THROWS_AS(StudyOutput(tmp.path() / "file.toml"), OutputError);
  // A folder that is not a study's: never swept away.
  fs::create_directories(tmp.path() / "src" / "nested");
  std::ofstream(tmp.path() / "src" / "main.cpp") << "int main() {}\n";
  CHECK_THROWS_AS(StudyOutput(tmp.path() / "src"), OutputError);
  CHECK(fs::exists(tmp.path() / "src" / "main.cpp"));
  // A non-empty folder without study.toml.
  fs::create_directories(tmp.path() / "data");
  std::ofstream(tmp.path() / "data" / "x.csv") << "t\n0\n";
  CHECK_THROWS_AS(StudyOutput(tmp.path() / "data"), OutputError);
  // A read-only parent, and a read-only previous study: refused, root included (the permission
  // bits decide, docs/decisions.md "Outputs").
  fs::create_directories(tmp.path() / "ro");
  ::chmod((tmp.path() / "ro").c_str(), 0555);
  CHECK_THROWS_AS(StudyOutput(tmp.path() / "ro" / "out"), OutputError);
  ::chmod((tmp.path() / "ro").c_str(), 0700);
  fs::create_directories(tmp.path() / "ro_study");
  std::ofstream(tmp.path() / "ro_study" / "study.toml") << "[files]\n";
  ::chmod((tmp.path() / "ro_study").c_str(), 0555);
  CHECK_THROWS_AS(StudyOutput(tmp.path() / "ro_study"), OutputError);
  ::chmod((tmp.path() / "ro_study").c_str(), 0700);
  CHECK(leftovers(tmp.path()) == 0);
  // A FIFO, and a link to a file, where the folder should be.
  REQUIRE(::mkfifo((tmp.path() / "fifo").c_str(), 0600) == 0);
  CHECK_THROWS_AS(StudyOutput(tmp.path() / "fifo"), OutputError);
  fs::create_symlink("file.toml", tmp.path() / "to_file");
  CHECK_THROWS_AS(StudyOutput(tmp.path() / "to_file"), OutputError);
  CHECK(fs::is_symlink(tmp.path() / "to_file"));
  // An empty folder is fine.
  fs::create_directories(tmp.path() / "empty");
  CHECK_NOTHROW(StudyOutput(tmp.path() / "empty"));
}

TEST_CASE("a link to a study folder stays a link and the folder it points to is replaced",
          "[study_output]") {
  TempDir tmp;
  fs::create_directories(tmp.path() / "results" / "real");
  fs::create_symlink("results/real", tmp.path() / "latest");
  for (const std::string text : {"first\n", "second\n"}) {
    StudyOutput out(tmp.path() / "latest");
    out.write("a.csv", text);
    out.commit(StudyRecord{});
  }
  CHECK(fs::is_symlink(tmp.path() / "latest"));
  CHECK(read(tmp.path() / "results" / "real" / "a.csv") == "second\n");
  CHECK(leftovers(tmp.path()) == 0);
  CHECK(leftovers(tmp.path() / "results") == 0);
  // A dangling link: the folder it names is created, the link stays.
  fs::create_symlink("results/new", tmp.path() / "next");
  {
    StudyOutput out(tmp.path() / "next");
    out.write("a.csv", "new\n");
    out.commit(StudyRecord{});
  }
  CHECK(fs::is_symlink(tmp.path() / "next"));
  CHECK(read(tmp.path() / "results" / "new" / "a.csv") == "new\n");
}

TEST_CASE("messages name the final paths, not the staging folder", "[study_output]") {
  TempDir tmp;
  StudyOutput out(tmp.path() / "converge");
  const std::string staged = out.staged("run_euler_0.csv");
  CHECK(staged.find(".staging-") != std::string::npos);
  const std::string message = "`euler 0.01 " + staged + "` exited with status 1";
  CHECK(out.with_final_paths(message) ==
        "`euler 0.01 " + (tmp.path() / "converge" / "run_euler_0.csv").string() +
            "` exited with status 1");
  // A write that fails names the final path too (a folder in the way of the file).
  fs::create_directories(out.staged("convergence.csv"));
  try {
    out.write("convergence.csv", "x\n");
    FAIL("wrote over a folder");
  } catch (const flexref::io::OutputError& e) {
    const std::string what = e.what();
    CHECK(what.find((tmp.path() / "converge" / "convergence.csv").string()) != std::string::npos);
    CHECK(what.find(".staging-") == std::string::npos);
  }
}

}  // namespace
