#include "studies/progress.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <thread>

namespace flexref::studies {
namespace {

/// What a Progress printed into a temporary file while `work` ran.
template <class Work>
std::string printed(ProgressSettings settings, long total, Work&& work) {
  std::FILE* file = std::tmpfile();
  REQUIRE(file != nullptr);
  settings.stream = file;
  settings.from_environment = false;
  {
    Progress progress("study", total, "runs", true, settings);
    work(progress);
  }
  std::rewind(file);
  std::string text;
  for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file)) text += static_cast<char>(c);
  std::fclose(file);
  return text;
}

ProgressSettings fast(int terminal) {
  ProgressSettings s;
  s.delay = std::chrono::milliseconds(20);
  s.interval = std::chrono::milliseconds(20);
  s.redraw = std::chrono::milliseconds(20);
  s.terminal = terminal;
  return s;
}

// The timings below only bound how many lines appear: a line every 20 ms over 300 ms of work
// gives several whatever the scheduler does; nothing is asserted about speed.
TEST_CASE("Progress writes new lines when standard error is not a terminal", "[studies]") {
  const std::string text = printed(fast(0), 4, [](Progress& p) {
    for (int i = 0; i < 4; ++i) {
      p.advance();
      std::this_thread::sleep_for(std::chrono::milliseconds(75));
    }
  });
  INFO(text);
  CHECK(text.find('\r') == std::string::npos);
  CHECK(text.find("study: ") == 0);
  CHECK(text.find("/4 runs") != std::string::npos);
  CHECK(text.find("study: 4/4 runs") != std::string::npos);  // the final line
  CHECK(text.find("done\n") != std::string::npos);
  CHECK(std::count(text.begin(), text.end(), '\n') >= 3);
}

TEST_CASE("Progress redraws one line on a terminal", "[studies]") {
  const std::string text = printed(
      fast(1), 0, [](Progress&) { std::this_thread::sleep_for(std::chrono::milliseconds(200)); });
  INFO(text);
  CHECK(text.find('\r') != std::string::npos);
  CHECK(std::count(text.begin(), text.end(), '\n') == 1);  // only the finished line
}

TEST_CASE("Progress prints nothing for short work or when disabled", "[studies]") {
  ProgressSettings slow = fast(0);
  slow.delay = std::chrono::seconds(30);
  CHECK(printed(slow, 3, [](Progress& p) { p.advance(); }).empty());
  std::FILE* file = std::tmpfile();
  {
    ProgressSettings s = fast(0);
    s.stream = file;
    Progress disabled("study", 1, "runs", false, s);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  CHECK(std::ftell(file) == 0);
  std::fclose(file);
}

TEST_CASE("Progress says 'stopped' when an exception ends the work", "[studies]") {
  std::FILE* file = std::tmpfile();
  REQUIRE(file != nullptr);
  ProgressSettings settings = fast(0);
  settings.stream = file;
  settings.from_environment = false;
  try {
    Progress progress("study", 5, "runs", true, settings);
    progress.advance();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    throw std::runtime_error("failure");
  } catch (const std::runtime_error&) {
  }
  std::rewind(file);
  std::string text;
  for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file)) text += static_cast<char>(c);
  std::fclose(file);
  INFO(text);
  CHECK(text.find("study: 1/5 runs") != std::string::npos);
  CHECK(text.find("stopped\n") != std::string::npos);
  CHECK(text.find("done") == std::string::npos);
}

}  // namespace
}  // namespace flexref::studies

namespace flexref::studies {
namespace {

/// A clock the test moves by hand: no assertion depends on the wall clock.
struct ManualClock {
  std::chrono::steady_clock::time_point now{};
  ProgressClock clock() {
    return [this] { return now; };
  }
  void advance(double seconds) {
    now += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(seconds));
  }
};

ProgressSettings manual(ManualClock& clock) {
  ProgressSettings s;
  s.clock = clock.clock();
  s.from_environment = false;
  return s;
}

TEST_CASE("Progress shows the count done and the time left", "[studies]") {
  ManualClock clock;
  // Disabled: no printer thread; line() says what would be printed.
  Progress progress("converge", 36, "runs", false, manual(clock));
  CHECK(progress.line() == "converge: 0/36 runs, 0 s");  // nothing done: no estimate yet
  for (int i = 0; i < 12; ++i) progress.advance();
  clock.advance(7.0);
  // 12 of 36 in 7 s: the 24 left take 14 s at the same rate.
  CHECK(progress.line() == "converge: 12/36 runs, 7 s, ~14 s left");
  for (int i = 0; i < 24; ++i) progress.advance();
  clock.advance(14.0);
  CHECK(progress.line(true) == "converge: 36/36 runs, 21 s, done");
}

TEST_CASE("Progress follows reference solves: solve k of n, t of T, time left", "[studies]") {
  ManualClock clock;
  Progress progress("reference: cvode and its error estimate", 0, "", false, manual(clock));
  reference::SolveProgress solves(3);
  progress.follow(&solves);
  CHECK(progress.line() == "reference: cvode and its error estimate: 0 s");  // not started
  solves.start_solve(0.0, 10.0);
  solves.reached(5.0);
  clock.advance(3.0);
  // Half of the first of three solves: 1/6 of the work in 3 s, 15 s left.
  CHECK(progress.line() ==
        "reference: cvode and its error estimate: solve 1 of 3, t = 5 of 10 s, 3 s, ~15 s left");
  solves.start_solve(0.0, 10.0);
  solves.reached(10.0);
  solves.start_solve(0.0, 10.0);
  solves.reached(2.5);
  clock.advance(6.0);
  // 2.25 of 3 solves in 9 s: 3 s left.
  CHECK(progress.line() ==
        "reference: cvode and its error estimate: solve 3 of 3, t = 2.5 of 10 s, 9 s, ~3 s left");
  // Long work: minutes and hours.
  clock.advance(9000.0);
  CHECK(progress.line().find(", 2.5 h, ~50 min left") != std::string::npos);
}

TEST_CASE("SolveProgress counts a solve beyond the expected number", "[studies]") {
  // The high-precision check repeats itself with shorter steps when its steps equal the run's.
  reference::SolveProgress solves(2);
  for (int k = 0; k < 3; ++k) solves.start_solve(0.0, 4.0);
  solves.reached(4.0);
  const reference::SolveProgress::Snapshot s = solves.snapshot();
  CHECK(s.solve == 3);
  CHECK(s.solves == 3);
  CHECK(s.fraction() == 1.0);
}

}  // namespace
}  // namespace flexref::studies
