#include "studies/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <exception>
#include <utility>

namespace flexref::studies {

namespace {

/// A duration as a progress line says it: "7 s", "12 min", "2.5 h".
std::string duration_text(double seconds) {
  char buffer[32];
  if (seconds < 99.5) {
    std::snprintf(buffer, sizeof buffer, "%.0f s", seconds);
  } else if (seconds < 5970.0) {
    std::snprintf(buffer, sizeof buffer, "%.0f min", seconds / 60.0);
  } else {
    std::snprintf(buffer, sizeof buffer, "%.1f h", seconds / 3600.0);
  }
  return buffer;
}

}  // namespace

namespace {

std::chrono::steady_clock::duration as_clock_duration(std::chrono::duration<double> d) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(d);
}

}  // namespace

Progress::Progress(std::string label, long total, std::string unit, bool enabled,
                   ProgressSettings settings)
    : label_(std::move(label)),
      total_(total),
      unit_(std::move(unit)),
      settings_(std::move(settings)),
      uncaught_(std::uncaught_exceptions()) {
  const bool injected_clock = static_cast<bool>(settings_.clock);
  if (!injected_clock) settings_.clock = [] { return std::chrono::steady_clock::now(); };
  start_ = settings_.clock();
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
  active_ = true;
  next_ = start_ + as_clock_duration(settings_.delay);
  // Without a delay the first line is printed here, before the work: the line (and its final
  // "done") then appears however short the work is (FLEXREF_PROGRESS=0,I in logs and tests).
  if (settings_.delay <= std::chrono::duration<double>::zero()) tick();
  if (!injected_clock) printer_ = std::thread([this] { run(); });
}

Progress::~Progress() { finish(); }

void Progress::finish() {
  if (!active_) return;
  if (printer_.joinable()) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    printer_.join();
  }
  active_ = false;
  if (printed_) print(true);
}

void Progress::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  // The steady clock here (an injected clock starts no thread): wait until the next line is
  // due, or the work has finished.
  while (!wake_.wait_until(lock, next_, [this] { return stop_; })) tick();
}

void Progress::tick() {
  if (!active_) return;
  const auto now = settings_.clock();
  if (now < next_) return;
  print(false);
  next_ = now + as_clock_duration(terminal_ ? settings_.redraw : settings_.interval);
}

std::string Progress::line(bool final_line) const {
  const double elapsed = std::chrono::duration<double>(settings_.clock() - start_).count();
  const long done = done_.load(std::memory_order_relaxed);
  const long total = total_.load(std::memory_order_relaxed);
  std::string text = label_ + ": ";
  double fraction = -1.0;  // share of the work done, when known
  if (const reference::SolveProgress* solves = solves_.load(std::memory_order_relaxed)) {
    const reference::SolveProgress::Snapshot s = solves->snapshot();
    if (s.solve > 0) {
      char buffer[96];
      std::snprintf(buffer, sizeof buffer, "solve %d of %d, t = %.3g of %.3g s, ", s.solve,
                    s.solves, s.t, s.t_end);
      text += buffer;
      fraction = s.fraction();
    }
  } else if (total > 0) {
    text += std::to_string(done) + "/" + std::to_string(total) + " " + unit_ + ", ";
    fraction = static_cast<double>(done) / static_cast<double>(total);
  } else if (done > 0) {
    text += std::to_string(done) + " " + unit_ + ", ";
  }
  text += duration_text(elapsed);
  if (final_line) {
    text += std::uncaught_exceptions() > uncaught_ ? ", stopped" : ", done";
  } else if (fraction > 0.0 && fraction < 1.0) {
    text += ", ~" + duration_text(elapsed * (1.0 - fraction) / fraction) + " left";
  }
  return text;
}

void Progress::print(bool final_line) {
  const std::string text = line(final_line);
  if (terminal_) {
    // Clear to the end of the line: a shorter line must not leave old characters behind.
    std::fprintf(settings_.stream, "\r%s\033[K%s", text.c_str(), final_line ? "\n" : "");
  } else {
    std::fprintf(settings_.stream, "%s\n", text.c_str());
  }
  std::fflush(settings_.stream);
  printed_ = true;
}

}  // namespace flexref::studies
