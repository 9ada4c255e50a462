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
/// simulating less dynamics).
///
/// As D → 0 the scheme converges to the averaged dynamics, not to the coupled one: a window on
/// a frozen geometry wears at the rate of that geometry's settled motion, while the coupled
/// motion lags its changing geometry (and its contacts see the surfaces recede). That limit's
/// distance to the reference, the averaging error, is the same for every integrator and jump;
/// the slow-time integrators' error is the distance to it. So the observed slow-time order of
/// each integrator is measured from the distances between the final profiles of its successive
/// levels (studies/observed_order.hpp, distance_order), in which that limit cancels; the error
/// against the reference and its least-squares slope are reported beside it, and the limit
/// itself (Richardson's extrapolation of the two finest levels at the observed order) is named
/// with its distance to the reference. A level enters the orders when its run is `ok`: no
/// change of the contact regime inside a jump (`regime-change`, CycleJumpResult::
/// regime_changes: extrapolation across it is outside the integrators' asymptotic range) and no
/// slow-time instability (`unstable`, CycleJumpResult::slow_instability); both are named, the
/// breakdown map. A distance enters when it is at least 10× the reference's estimated error (the
/// windows solve with the reference's solver and tolerance: below that it measures their
/// solves), an error against the reference likewise (`unresolved` below). No order is fitted
/// from fewer than three distances (or three levels against the reference).
///
/// The reference's error is estimated by a second solve at rtol/estimate_factor (the difference
/// of the final profiles, in the error's units).
#include <string>
#include <vector>

#include "studies/observed_order.hpp"
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
  /// "ok", "unresolved" (error below 10× the reference's estimate), "regime-change" or
  /// "unstable" (named in the notes; out of the fits), "failed: …".
  std::string status = "ok";
  int window_count = 0;
  double fast_time = 0.0;
  Eigen::VectorXd depth;  ///< h(T)
};

struct WearJumpFit {
  std::string slow;
  int claimed = 0;
  double window = 0.0;
  /// The slow-time order from the distances between successive `ok` levels (NaN from fewer
  /// than three resolved distances), and the levels they join.
  double observed = 0.0;
  int levels = 0;
  std::vector<LevelDistance> distances;  ///< every distance between successive `ok` levels
  std::vector<bool> distance_used;       ///< resolved: at least 10× the reference's estimate
  /// The least-squares slope of the error against the reference over the `ok` levels (NaN
  /// from fewer than three), and their count.
  double observed_reference = 0.0;
  int reference_levels = 0;
  /// The limit D → 0 by Richardson's extrapolation of the two finest levels of the distances
  /// used, at the observed order, and its error against the reference (NaN without an order).
  double limit_error = 0.0;
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
/// The distances between successive levels and the limits: one row per distance,
/// slow,window,coarse,fine,distance,used (1 when it entered the order), and the integrator's
/// limit_error (its averaging error estimate, empty without an order) on every row.
std::string wear_jump_distances_csv(const WearJumpResult& result);
/// The table, the notes, and last one line per slow-time integrator,
/// "  NAME claimed P, observed X over N levels".
std::string format_wear_jump(const WearJumpResult& result);

}  // namespace flexref::studies
