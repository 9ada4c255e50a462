#include "studies/progress.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace flexref::studies {
namespace {

/// A clock the test moves by hand: no assertion depends on the wall clock or the machine's
/// load. A Progress on it starts no printer thread; tick() prints what is due.
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

/// Everything written to `file` so far.
std::string progress_file_text(std::FILE* file) {
  std::fflush(file);
  const long end = std::ftell(file);
  std::rewind(file);
  std::string text;
  for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file)) text += static_cast<char>(c);
  std::fseek(file, end, SEEK_SET);
  return text;
}

/// The default periods (delay 2 s, redraw 0.5 s, interval 5 s) on `clock`, into `file`.
ProgressSettings on_manual_clock(ManualClock& clock, std::FILE* file, int terminal) {
  ProgressSettings s;
  s.clock = clock.clock();
  s.stream = file;
  s.terminal = terminal;
  s.from_environment = false;
  return s;
}

TEST_CASE("Progress writes new lines when standard error is not a terminal", "[studies]") {
  ManualClock clock;
  std::FILE* file = std::tmpfile();
  REQUIRE(file != nullptr);
  {
    Progress p("study", 4, "runs", true, on_manual_clock(clock, file, 0));
    p.advance();
    clock.advance(1.0);
    p.tick();
    CHECK(progress_file_text(file).empty());  // before the 2 s delay
    clock.advance(1.0);
    p.tick();
    CHECK(progress_file_text(file) == "study: 1/4 runs, 2 s, ~6 s left\n");
    p.advance();
    clock.advance(4.5);
    p.tick();  // the next line is due at 7 s
    CHECK(progress_file_text(file) == "study: 1/4 runs, 2 s, ~6 s left\n");
    clock.advance(0.5);
    p.tick();
    CHECK(progress_file_text(file) ==
          "study: 1/4 runs, 2 s, ~6 s left\nstudy: 2/4 runs, 7 s, ~7 s left\n");
    p.advance();
    p.advance();
    clock.advance(1.0);
  }
  const std::string text = progress_file_text(file);
  std::fclose(file);
  CHECK(text.find('\r') == std::string::npos);
  CHECK(text ==
        "study: 1/4 runs, 2 s, ~6 s left\nstudy: 2/4 runs, 7 s, ~7 s left\n"
        "study: 4/4 runs, 8 s, done\n");
}

TEST_CASE("Progress redraws one line on a terminal", "[studies]") {
  ManualClock clock;
  std::FILE* file = std::tmpfile();
  REQUIRE(file != nullptr);
  {
    Progress p("study", 0, "runs", true, on_manual_clock(clock, file, 1));
    for (int i = 0; i < 6; ++i) {  // 0.5 ... 3 s: lines due at 2, 2.5 and 3 s
      clock.advance(0.5);
      p.tick();
    }
  }
  const std::string text = progress_file_text(file);
  std::fclose(file);
  // Each line cleared to its end; only the finished one ends the line.
  CHECK(text == "\rstudy: 2 s\033[K\rstudy: 2 s\033[K\rstudy: 3 s\033[K\rstudy: 3 s, done\033[K\n");
  CHECK(std::count(text.begin(), text.end(), '\n') == 1);
}

TEST_CASE("Progress prints nothing for short work or when disabled", "[studies]") {
  ManualClock clock;
  std::FILE* file = std::tmpfile();
  REQUIRE(file != nullptr);
  {
    Progress p("study", 3, "runs", true, on_manual_clock(clock, file, 0));
    p.advance();
    clock.advance(1.9);  // the work ends before the 2 s delay
    p.tick();
  }
  CHECK(progress_file_text(file).empty());
  {
    Progress disabled("study", 1, "runs", false, on_manual_clock(clock, file, 0));
    clock.advance(60.0);
    disabled.tick();
  }
  CHECK(progress_file_text(file).empty());
  std::fclose(file);
}

TEST_CASE("Progress says 'stopped' when an exception ends the work", "[studies]") {
  ManualClock clock;
  std::FILE* file = std::tmpfile();
  REQUIRE(file != nullptr);
  try {
    Progress progress("study", 5, "runs", true, on_manual_clock(clock, file, 0));
    progress.advance();
    clock.advance(3.0);
    progress.tick();
    throw std::runtime_error("failure");
  } catch (const std::runtime_error&) {
  }
  const std::string text = progress_file_text(file);
  std::fclose(file);
  CHECK(text == "study: 1/5 runs, 3 s, ~12 s left\nstudy: 1/5 runs, 3 s, stopped\n");
}

TEST_CASE("Progress on the steady clock prints at once without a delay and finishes its line",
          "[studies]") {
  // No time is asserted: with no delay the first line is printed before the work starts, and
  // the printer thread's next line is due only after an hour, so exactly that line and the
  // final one appear whatever the load.
  std::FILE* file = std::tmpfile();
  REQUIRE(file != nullptr);
  ProgressSettings s;
  s.stream = file;
  s.terminal = 0;
  s.from_environment = false;
  s.delay = std::chrono::duration<double>(0.0);
  s.interval = std::chrono::hours(1);
  {
    Progress p("study", 2, "runs", true, s);
    p.advance();
    p.advance();
  }
  const std::string text = progress_file_text(file);
  std::fclose(file);
  INFO(text);
  CHECK(text.rfind("study: 0/2 runs, 0 s\n", 0) == 0);
  CHECK(text.find("study: 2/2 runs, ") != std::string::npos);
  CHECK(text.ends_with(", done\n"));
  CHECK(std::count(text.begin(), text.end(), '\n') == 2);
}

}  // namespace
}  // namespace flexref::studies

namespace flexref::studies {
namespace {

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
