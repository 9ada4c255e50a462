#pragma once
/// \file reference_budget.hpp
/// The wall-time budget of an extended/quad reference (docs/precision.md, "Cost guard"): a run
/// projects its own wall time over the simulated time left at its recent rate and stops once
/// the projection of the whole reference is over its budget.
#include <stdexcept>
#include <string>

#include "precision/precision.hpp"
#include "reference/solve_progress.hpp"

namespace flexref::precision {

/// Thrown when the projected wall time of a reference with its estimate exceeds its budget:
/// raised at the first check that projects over, so a refused reference costs a small part of
/// the budget.
class BudgetExceeded : public std::runtime_error {
 public:
  BudgetExceeded(const std::string& what, double projected_seconds, double budget_seconds,
                 double reached_time)
      : std::runtime_error(what),
        projected_seconds_(projected_seconds),
        budget_seconds_(budget_seconds),
        reached_time_(reached_time) {}
  /// The projected wall time of the whole reference with its estimate, s.
  double projected_seconds() const { return projected_seconds_; }
  double budget_seconds() const { return budget_seconds_; }
  /// The simulated time the run had reached when it was stopped, s.
  double reached_time() const { return reached_time_; }

 private:
  double projected_seconds_;
  double budget_seconds_;
  double reached_time_;
};

/// The bound of one run inside a reference: the reference's projected total is
/// spent + factor × this run's projected time, where factor is what the reference costs per
/// second of this run (3 for a run followed by its check at rtol/100, which costs about twice
/// the run; 1 for the check itself).
struct Budget {
  double seconds = 0.0;  ///< the whole reference's bound (0: none)
  double spent = 0.0;    ///< wall time of the reference's earlier runs
  double factor = 1.0;
  /// Where a progress line follows the run (reference/solve_progress.hpp; not owned, may be
  /// null): the run starts a solve in it and stores the simulated time it reaches.
  reference::SolveProgress* progress = nullptr;
};

/// The recent cost of a run: wall seconds per simulated second over a window that covers at
/// least the last half of its elapsed time (samples kept as the elapsed time doubles). A run
/// whose first stretch is cheap (a many-mode body before its load excites the top modes) is
/// projected from what it costs now, not from its average so far.
class RateWindow {
 public:
  explicit RateWindow(double t0) : t0_(t0), mark_{0.0, t0}, pending_{0.0, t0} {}
  /// Records the sample (elapsed, t) and returns the run's projected wall time to t_end,
  /// elapsed + (t_end − t) × rate: the rate since the window's mark, or since t0 when no
  /// simulated time has passed since the mark. Never below `elapsed`; requires t > t0.
  double projected_run(double elapsed, double t, double t_end);
  /// The run's start in simulated time.
  double t0() const { return t0_; }

 private:
  struct Sample {
    double elapsed;
    double t;
  };
  double t0_;
  Sample mark_;     ///< at or before half the elapsed time
  Sample pending_;  ///< becomes the mark once the elapsed time has doubled since it
};

/// The projection at simulated time t of a run that started at window.t0(), ends at t_end and
/// has taken `elapsed` seconds: spent + factor × window.projected_run(elapsed, t, t_end) (with a
/// fresh window, the average rate: spent + factor × elapsed × (t_end − t0)/(t − t0)). Throws
/// BudgetExceeded when it is over budget.seconds. Nothing is projected without a budget, at
/// t ≤ t0, or before 1 % of the budget has elapsed (start-up dominates the first rows).
void check_budget(const Budget& budget, RateWindow& window, double elapsed, double t, double t_end,
                  Precision precision);

}  // namespace flexref::precision
