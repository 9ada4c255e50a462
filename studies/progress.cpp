#include "studies/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <exception>
#include <utility>

namespace flexref::studies {

Progress::Progress(std::string label, long total, std::string unit, bool enabled,
                   ProgressSettings settings)
    : label_(std::move(label)),
      total_(total),
      unit_(std::move(unit)),
      settings_(settings),
      uncaught_(std::uncaught_exceptions()),
      start_(std::chrono::steady_clock::now()) {
  if (settings_.from_environment) {
    if (const char* env = std::getenv("FLEXREF_PROGRESS")) {
      double delay = 0.0;
      double interval = 0.0;
      if (std::string(env) == "off") {
        enabled = false;
      } else if (std::sscanf(env, "%lf,%lf", &delay, &interval) == 2 && delay >= 0.0 &&
                 interval > 0.0) {
        settings_.delay = std::chrono::duration<double>(delay);
        settings_.interval = std::chrono::duration<double>(interval);
        settings_.redraw = std::chrono::duration<double>(interval);
      }
    }
  }
  if (!enabled || settings_.stream == nullptr) return;
  terminal_ =
      settings_.terminal < 0 ? isatty(fileno(settings_.stream)) != 0 : settings_.terminal > 0;
  printer_ = std::thread([this] { run(); });
}

Progress::~Progress() { finish(); }

void Progress::finish() {
  if (!printer_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  printer_.join();
  if (printed_) print(true);
}

void Progress::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  if (wake_.wait_for(lock, settings_.delay, [this] { return stop_; })) return;
  const auto period = terminal_ ? settings_.redraw : settings_.interval;
  do {
    print(false);
  } while (!wake_.wait_for(lock, period, [this] { return stop_; }));
}

void Progress::print(bool final_line) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const long done = done_.load(std::memory_order_relaxed);
  const long total = total_.load(std::memory_order_relaxed);
  std::string line = label_ + ": ";
  if (total > 0) {
    line += std::to_string(done) + "/" + std::to_string(total) + " " + unit_ + ", ";
  } else if (done > 0) {
    line += std::to_string(done) + " " + unit_ + ", ";
  }
  line += std::to_string(std::lround(elapsed)) + " s";
  if (final_line) line += std::uncaught_exceptions() > uncaught_ ? ", stopped" : ", done";
  if (terminal_) {
    // Clear to the end of the line: a shorter line must not leave old characters behind.
    std::fprintf(settings_.stream, "\r%s\033[K%s", line.c_str(), final_line ? "\n" : "");
  } else {
    std::fprintf(settings_.stream, "%s\n", line.c_str());
  }
  std::fflush(settings_.stream);
  printed_ = true;
}

}  // namespace flexref::studies
