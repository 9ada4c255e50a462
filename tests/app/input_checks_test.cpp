#include "app/input_checks.hpp"

#include <catch2/catch.hpp>
#include <fstream>
#include <regex>
#include <stdexcept>
#include <string>

#include "app/cli_validators.hpp"
#include "core/error.hpp"
#include "core/output_times.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::app {
namespace {

/// A copy of a bundled scene with one line replaced (the first that matches `pattern`).
std::string edited_scene(const std::string& scene, const std::string& pattern,
                         const std::string& replacement) {
  std::ifstream in("scenes/" + scene + ".toml");
  REQUIRE(in);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string edited = std::regex_replace(text, std::regex(pattern), replacement,
                                                std::regex_constants::format_first_only);
  REQUIRE(edited != text);
  static const testing::TempDir dir("input-checks");  // this program's, removed at exit
  const std::string path = (dir / (scene + ".toml")).string();
  std::ofstream(path) << edited;
  return path;
}

std::string refusal(const std::string& path) {
  try {
    load_scene(path);
  } catch (const core::InputError& e) {
    CHECK(e.file() == path);
    return e.what();
  }
  return "";
}

TEST_CASE("scenes whose physics double precision cannot carry are refused up front",
          "[app][input_checks]") {
  // Each is refused before any output: accepted, it would write inf or NaN (or nonsense) with exit
  // 0. A spin of 1e150 rad/s turns by 2 rad in 2e-150 s, far below the 2.2e-8 s double precision
  // resolves at t = 100 s (free_spin's end time).
  std::string m = refusal(
      edited_scene("free_spin", "angular_velocity = .*", "angular_velocity = [1e150, 1.0, 0.0]"));
  CHECK(m.find("body[1].angular_velocity") != std::string::npos);
  CHECK(m.find("resolves") != std::string::npos);
  // stiffness = 1e300 N/m^1.5: ω ~ 1e120 rad/s.
  m = refusal(edited_scene("bouncing_ball", "\nstiffness = [^#]*", "\nstiffness = 1e300 "));
  CHECK(m.find("contact[1]") != std::string::npos);
  CHECK(m.find("no integrator can follow it") != std::string::npos);
  // reference_speed = 1e-300 m/s: the impact stiffness underflows to 0.
  m = refusal(
      edited_scene("bouncing_ball", "reference_speed = [^#]*", "reference_speed = 1e-300 "));
  CHECK(m.find("contact[1]") != std::string::npos);
  CHECK(m.find("under- or overflows") != std::string::npos);
  // The bundled scenes pass.
  for (const char* scene : {"free_spin", "book_toss", "bouncing_ball", "flexible_spinner",
                            "spin_up_beam_6", "double_pendulum_impacts", "tippe_top"}) {
    INFO(scene);
    CHECK_NOTHROW(load_scene(std::string("scenes/") + scene + ".toml"));
  }
}

TEST_CASE("work limits refuse huge runs and files before any work", "[app][input_checks]") {
  WorkLimits limits;
  // end_time 1e6 s at output_step 0.01 s: 1e8 rows (the vector itself would be 0.8 GB).
  try {
    limited_output_times(1e6, 0.01, limits);
    FAIL("no exception");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("--max-rows") != std::string::npos);
  }
  CHECK(limited_output_times(10.0, 0.01, limits).size() == 1001);
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(100.0, 0.1);
  // 1e-4 s over 100 s is 1e6 steps: allowed; 1e-6 s is 1e8: refused unless raised.
  CHECK(check_scheme_run(model, 1e-4, times, limits, "--dt") == 1'000'000);
  try {
    check_scheme_run(model, 1e-6, times, limits, "--dt");
    FAIL("no exception");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("--max-steps") != std::string::npos);
    CHECK(std::string(e.what()).find("--dt 1e-06") == 0);
  }
  limits.max_steps = 1e9;
  CHECK(check_scheme_run(model, 1e-6, times, limits, "--dt") == 100'000'000);
  // Below the resolution no limit helps: 1e-19 s at t = 100 s.
  CHECK_THROWS_WITH(check_scheme_run(model, 1e-19, times, limits, "--dt"),
                    Catch::Matchers::Contains("double precision"));
}

std::string check(const CLI::Validator& v, std::string value) { return v(value); }

TEST_CASE("option validators give plain messages", "[app][input_checks]") {
  // CLI11's PositiveNumber printed its range with 300 digits and called a word "not in range".
  CHECK(check(positive_number(), "0") == "must be a positive number, got 0");
  CHECK(check(positive_number(), "abc") == "'abc' is not a number");
  CHECK(check(positive_number(), "nan").find("not a finite number") != std::string::npos);
  CHECK(check(positive_number(), "1e-400").find("not a finite number") != std::string::npos);
  CHECK(check(positive_number(), "1e-3").empty());
  CHECK(check(number_in(1e-14, 1e-4), "0.1") == "must lie in [1e-14, 0.0001], got 0.1");
  CHECK(check(integer_in(3, 16), "2") == "must be an integer in [3, 16], got 2");
  CHECK(check(integer_in(3, 16), "2.5") == "must be an integer, got 2.5");
  CHECK(check(integer_in(3, 16), "4").empty());
  CHECK(check(non_negative_number(), "-1") == "must be zero or positive, got -1");
}

}  // namespace
}  // namespace flexref::app
