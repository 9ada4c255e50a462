#pragma once
/// \file solve_progress.hpp
/// Where a sequence of reference solves stands, for a progress line drawn by another thread
/// (studies/progress.hpp): solve_reference counts the solves, and each solver stores the
/// simulated time it has reached at every output time. Plain atomics: the solver writes, the
/// printer reads, neither waits.
#include <algorithm>
#include <atomic>

namespace flexref::reference {

class SolveProgress {
 public:
  /// `solves`: how many solves the work is expected to take (a reference and its checks).
  explicit SolveProgress(int solves = 1) : solves_(std::max(solves, 1)) {}

  /// A new solve over [t0, t_end] starts (solve_reference calls it).
  void start_solve(double t0, double t_end) noexcept {
    t0_.store(t0, std::memory_order_relaxed);
    t_end_.store(t_end, std::memory_order_relaxed);
    t_.store(t0, std::memory_order_relaxed);
    solve_.fetch_add(1, std::memory_order_relaxed);
  }
  /// The current solve has reached simulated time t (the solvers call it at each output time).
  void reached(double t) noexcept { t_.store(t, std::memory_order_relaxed); }

  struct Snapshot {
    int solve = 0;  ///< 1-based; 0 before the first solve starts
    int solves = 1;
    double t = 0.0;
    double t0 = 0.0;
    double t_end = 0.0;
    /// The share of the whole work done, counting every solve as equally long:
    /// (solve − 1 + (t − t0)/(t_end − t0)) / solves, in [0, 1].
    double fraction() const {
      if (solve <= 0) return 0.0;
      const double within = t_end > t0 ? std::clamp((t - t0) / (t_end - t0), 0.0, 1.0) : 0.0;
      return std::clamp((solve - 1 + within) / solves, 0.0, 1.0);
    }
  };
  Snapshot snapshot() const noexcept {
    Snapshot s;
    s.solve = solve_.load(std::memory_order_relaxed);
    s.solves = std::max(solves_, s.solve);
    s.t = t_.load(std::memory_order_relaxed);
    s.t0 = t0_.load(std::memory_order_relaxed);
    s.t_end = t_end_.load(std::memory_order_relaxed);
    return s;
  }

 private:
  int solves_;
  std::atomic<int> solve_{0};
  std::atomic<double> t_{0.0};
  std::atomic<double> t0_{0.0};
  std::atomic<double> t_end_{0.0};
};

}  // namespace flexref::reference
