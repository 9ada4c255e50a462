#pragma once
/// \file wear_jump.hpp
/// The `wear-jump` study (docs/wear.md, "What is measured"): the multi-scale scheme
/// (studies/wear_cycle_jump.hpp) against the fully coupled reference, whose worn depths are
/// states integrated with the dynamics over the whole slow time under the error test, with the
/// same acceleration factor.
///
/// For every slow-time integrator and every jump D = T/n of a ladder (and every window of a
/// list), the scheme's final worn profile h(T) is compared with the reference's:
///   error = max_j |h_j − h_ref,j| / max_j h_ref,j
/// (the largest depth difference relative to the reference's largest depth), with its cost
/// (CPU of its windows, model builds included) and its speed-up, the reference's CPU over it
/// (the same solver and tolerance for both, so the speed-up is what the scheme saves by
/// simulating less dynamics). The observed slow-time order of each integrator is the
/// least-squares slope of log error against log D over its levels (studies/observed_order.hpp)
/// whose error is at least 10× the reference's estimated error (an `unresolved` level measures
/// the reference, not the scheme) and whose runs saw no change of the contact regime inside a
/// jump (a `regime-change` level: extrapolation across the change is outside the integrators'
/// asymptotic range, which their order describes). Levels whose runs saw
/// the contact regime change inside a jump (CycleJumpResult::regime_changes) are named: the
/// breakdown map.
///
/// The reference's error is estimated by a second solve at rtol/estimate_factor (the difference
/// of the final profiles, in the error's units).
#include <string>
#include <vector>

#include "studies/wear_cycle_jump.hpp"

namespace flexref::studies {

struct WearJumpOptions {
  std::vector<SlowIntegrator> slow = {SlowIntegrator::kEuler, SlowIntegrator::kHeun,
                                      SlowIntegrator::kAb2};
  std::vector<int> jump_counts = {2, 4, 8, 16, 32};  ///< jumps over [0, T]: D = T/n
  std::vector<double> windows;                       ///< T_w values (empty: base.window)
  CycleJumpOptions base;  ///< transient, slow time, solver, tolerance, formulation
  double estimate_factor = 10.0;
  int jobs = 1;
  bool progress = false;  ///< a progress line on stderr
};

struct WearJumpRow {
  std::string slow;
  int jumps = 0;
  double jump = 0.0;    ///< D, s
  double window = 0.0;  ///< T_w, s
  double error = 0.0;
  double cpu = 0.0;  ///< s
  double speedup = 0.0;
  /// "ok", "unresolved" (error below 10× the reference's estimate), "regime-change" (named in
  /// the notes; both out of the fit), "failed: …".
  std::string status = "ok";
  int window_count = 0;
  double fast_time = 0.0;
  Eigen::VectorXd depth;  ///< h(T)
};

struct WearJumpFit {
  std::string slow;
  int claimed = 0;
  double observed = 0.0;  ///< NaN when fewer than three levels are usable
  int levels = 0;
  double window = 0.0;
};

struct WearJumpResult {
  WearJumpOptions options;
  CycleJumpResult layout;  ///< channels and depth layout (its path is the reference's)
  Eigen::VectorXd reference_depth;
  double reference_cpu = 0.0;
  long reference_steps = 0;
  double reference_estimate = 0.0;  ///< relative, in the error's units
  std::vector<double> reference_times;
  std::vector<double> reference_max_depth;
  std::vector<WearJumpRow> rows;
  std::vector<WearJumpFit> fits;
  std::vector<std::string> notes;
};

/// Runs the study (the runs in parallel over `jobs` threads; their numbers do not depend on
/// it, their CPU times are each its own thread's). Throws std::invalid_argument on bad options
/// or a scene without a wear law, core::SolverError when the reference fails (a failed scheme
/// run is a row with its status).
WearJumpResult run_wear_jump(const scene::SceneSpec& spec, const WearJumpOptions& options);

/// The profile error of a final profile against the reference's.
double profile_error(const Eigen::VectorXd& depth, const Eigen::VectorXd& reference);

/// CSV columns: slow,jump,window,error,cpu,speedup,status.
std::string wear_jump_csv(const WearJumpResult& result);
/// The table, the notes, and last one line per slow-time integrator,
/// "  NAME claimed P, observed X over N levels".
std::string format_wear_jump(const WearJumpResult& result);

}  // namespace flexref::studies
