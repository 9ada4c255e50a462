#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "app/run_command.hpp"
#include "core/error.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/temp_dir.hpp"

namespace flexref::app {
namespace {

namespace fs = std::filesystem;

using testing::TempDir;  // this test's own folder (tests/support/temp_dir.hpp)

/// Captures what a command prints (its summary line, warnings, progress) for the test to read.
struct Captured {
  Captured() : out_(std::cout.rdbuf(out.rdbuf())), err_(std::cerr.rdbuf(err.rdbuf())) {}
  ~Captured() {
    std::cout.rdbuf(out_);
    std::cerr.rdbuf(err_);
  }
  std::ostringstream out, err;

 private:
  std::streambuf* out_;
  std::streambuf* err_;
};

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  REQUIRE(in);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A bundled scene with regex replacements, written into `dir`.
fs::path edited_scene(const fs::path& dir, const std::string& scene,
                      const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string text = read_text("scenes/" + scene + ".toml");
  for (const auto& [pattern, replacement] : edits) {
    const std::string edited = std::regex_replace(text, std::regex(pattern), replacement,
                                                  std::regex_constants::format_first_only);
    REQUIRE(edited != text);
    text = edited;
  }
  const fs::path path = dir / (scene + ".toml");
  std::ofstream(path) << text;
  return path;
}

/// run_command's refusal message, or "" when it succeeded.
std::string run_refusal(const RunOptions& options) {
  try {
    Captured quiet;
    run_command(options);
  } catch (const core::SolverError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE(
    "run refuses a run that breaks the scene's invariants and names the step and writes nothing",
    "[app][run]") {
  // Each must be refused with a message and no file: C2 far past its rotational limit
  // h|W| = 0.582 raises the energy of free_spin from 1.02e7 J to 1.56e7 J, doubles book_toss's.
  TempDir tmp;
  RunOptions options;
  options.scheme = "c2";
  options.dt = 0.01;
  options.output = (tmp.path() / "run.csv").string();
  SECTION("free_spin at W0 = (200, 300, 2000) rad/s: h|W| = 20") {
    options.scene =
        edited_scene(tmp.path(), "free_spin",
                     {{"angular_velocity = .*", "angular_velocity = [200.0, 300.0, 2000.0]"}})
            .string();
  }
  SECTION("book_toss at |W| = 1e6 rad/s") {
    options.scene = edited_scene(tmp.path(), "book_toss",
                                 {{"angular_velocity = .*", "angular_velocity = [0.0, 1e6, 0.0]"}})
                        .string();
  }
  const std::string message = run_refusal(options);
  INFO(message);
  CHECK(message.find("unstable") != std::string::npos);
  CHECK(message.find("energy balance") != std::string::npos);
  CHECK(std::regex_search(message, std::regex("use --dt [0-9.e-]+")));
  CHECK_FALSE(fs::exists(options.output));
  CHECK_FALSE(fs::exists(options.output + ".meta.toml"));
}

TEST_CASE("every bundled scene runs with its defaults or the refusal names a step that runs",
          "[app][run]") {
  // A scene refused at the default --dt 1e-3 (tube_support_impact among them) must name a step
  // to use. Each scene is run briefly (its first 0.2 s: each refusal found at the default step
  // comes before that) with every option at its default.
  TempDir tmp;
  for (const auto& entry : fs::directory_iterator("scenes")) {
    if (entry.path().extension() != ".toml") continue;
    const std::string name = entry.path().stem().string();
    INFO(name);
    RunOptions options;
    options.scene =
        edited_scene(tmp.path(), name, {{"\nend_time = [^#\n]*", "\nend_time = 0.2 "}}).string();
    options.output = (tmp.path() / (name + ".csv")).string();
    // A scene with ideal joints is the references' (C1, C2 and NMB refuse it before any work,
    // naming the joint and what to use instead: lie/scheme_support.cpp), at a step on its grid.
    // Under the coupled model: joints at a flexible body's nodes are refused under LTE
    // (slider_crank_flexible), and rigid bodies are the same in both models.
    if (scene::read_scene(options.scene).spec.ideal_joints.size() > 0) {
      options.dt = 1e-5;
      options.model = core::FlexibleFormulation::kCoupled;
      CHECK_THROWS_WITH(run_command(options), Catch::Matchers::Contains("ideal joint") &&
                                                  Catch::Matchers::Contains("--scheme genalpha") &&
                                                  Catch::Matchers::Contains("flexref reference"));
      CHECK_FALSE(fs::exists(options.output));
      continue;
    }
    const std::string refusal = run_refusal(options);
    if (refusal.empty()) continue;
    std::smatch step;
    REQUIRE(std::regex_search(refusal, step, std::regex("use --dt ([0-9.e-]+)")));
    CHECK_FALSE(fs::exists(options.output));
    options.dt = std::stod(step[1].str());
    CHECK(run_refusal(options).empty());
    CHECK(fs::exists(options.output));
  }
}

}  // namespace
}  // namespace flexref::app
