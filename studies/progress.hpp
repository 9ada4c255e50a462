#pragma once
/// \file progress.hpp
/// The progress line of long work on standard error, one mechanism for every
/// command and study: nothing while the work is shorter than `delay` (2 s); then, on a
/// terminal, one line redrawn in place ("\r") every `redraw` (0.5 s), and without a terminal (a
/// log file, CI) a new line every `interval` (5 s), so that a log shows the work advancing
/// without filling up. Workers count with an atomic increment (no lock, no output from worker
/// threads); a background thread prints.
///
/// The environment variable FLEXREF_PROGRESS overrides the defaults: "off" prints nothing,
/// "D,I" waits D seconds and then prints every I seconds (terminal or not), e.g. "0,1" in a
/// CI log that should show every second; with D = 0 the first line is printed at once, so the
/// line and its final "done" appear even for work shorter than I.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "reference/solve_progress.hpp"

namespace flexref::studies {

/// The clock of a progress line. Tests inject one and move it by hand: a Progress on an
/// injected clock starts no printer thread, and prints only from tick(), in the caller's
/// thread, what is due at the clock's time; what it prints then depends on the times the test
/// sets, not on the machine's load.
using ProgressClock = std::function<std::chrono::steady_clock::time_point()>;

struct ProgressSettings {
  std::chrono::duration<double> delay{2.0};     ///< print nothing for work shorter than this
  std::chrono::duration<double> redraw{0.5};    ///< terminal: redraw period
  std::chrono::duration<double> interval{5.0};  ///< not a terminal: one line per interval
  std::FILE* stream = stderr;
  /// -1: ask isatty() of the stream; 0: lines; 1: a redrawn line.
  int terminal = -1;
  bool from_environment = true;  ///< apply FLEXREF_PROGRESS (see above)
  ProgressClock clock;           ///< empty: std::chrono::steady_clock::now and a printer thread
};

/// What a progress line says (see Progress::line):
///   "converge: 12/36 runs, 7 s, ~14 s left" (a count of units of work);
///   "reference: cvode and its error estimate: solve 2 of 3, t = 4.1 of 10 s, 7 s, ~9 s left"
///   (reference solves followed through reference::SolveProgress);
///   "plot x.png: 7 s" (nothing else known).
/// The time left is the elapsed time scaled by the share of the work still to do, counting
/// every unit, and every solve, as equally long: a guide ("~"), not a promise.
class Progress {
 public:
  /// `label` starts the line; `total` the count of `unit`s to do (0: unknown).
  /// Disabled (enabled = false) it prints nothing and starts no thread.
  Progress(std::string label, long total, std::string unit, bool enabled = true,
           ProgressSettings settings = {});
  /// Stops the printer; when a line was printed, finishes it with the final count and "done"
  /// (or "stopped" when an exception unwinds the work).
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// One more unit done (any thread).
  void advance() noexcept { done_.fetch_add(1, std::memory_order_relaxed); }
  /// The counter itself, for a loop that stores its own count (lie::run_scheme's steps).
  std::atomic<long>& counter() noexcept { return done_; }
  /// The count to do, when it is known only once the work runs (a distributed study).
  void set_total(long total) noexcept { total_.store(total, std::memory_order_relaxed); }
  /// Stops the printer now; when a line was printed, finishes it (the destructor does this too).
  void finish();
  /// Shows the solve count, the simulated time reached and the time left of reference solves
  /// that report to `solves` (reference::SolverOptions::progress), which must outlive this.
  void follow(const reference::SolveProgress* solves) noexcept {
    solves_.store(solves, std::memory_order_relaxed);
  }
  /// Prints a line when one is due at the clock's time: the first once `delay` has passed,
  /// then one per period (`redraw` on a terminal, `interval` otherwise). The printer thread
  /// calls it; with an injected clock (ProgressSettings::clock) the caller does.
  void tick();
  /// The line as it would be printed now (without "\r" or "\n"); `final_line` adds "done" or
  /// "stopped".
  std::string line(bool final_line = false) const;

 private:
  void run();
  void print(bool final_line);

  std::string label_;
  std::atomic<long> total_;
  std::string unit_;
  ProgressSettings settings_;
  bool terminal_ = false;
  bool printed_ = false;
  bool active_ = false;  ///< enabled with a stream, not yet finished
  int uncaught_ = 0;     ///< std::uncaught_exceptions() at construction
  std::atomic<long> done_{0};
  std::atomic<const reference::SolveProgress*> solves_{nullptr};
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point next_;  ///< when the next line is due
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread printer_;
};

}  // namespace flexref::studies
