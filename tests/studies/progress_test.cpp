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
