#pragma once
/// \file wear_cycle_jump.hpp
/// The multi-scale (cycle-jump) scheme of wear (docs/wear.md, "Multi-scale scheme"), as
/// industry uses it to reach years of wear from seconds of vibration:
///
///   1. integrate the dynamics over a window on a frozen geometry (core::WearLaw::
///      geometry_frozen: the contacts see the depths h_k, the states only record the window's
///      wear), discarding a transient T_tr at its start;
///   2. average the wear rate of every point or sector over the window T_w that follows:
///      r(h_k) = (h(T_tr + T_w) − h(T_tr)) / T_w;
///   3. advance the geometry over a jump D of slow time by a slow-time integrator:
///        euler  h_{k+1} = h_k + D r(h_k)                                   (order 1)
///        heun   h̃ = h_k + D r(h_k),  h_{k+1} = h_k + ½ D (r(h_k) + r(h̃))   (order 2, two windows)
///        ab2    h_{k+1} = h_k + D ((1 + ω/2) r(h_k) − (ω/2) r(h_{k−1})),  ω = D_k/D_{k−1}
///               (second-order Adams–Bashforth with variable steps; its first jump by Heun);
///   4. restart the dynamics on the new geometry from the bodies' state at the end of the last
///      window (the state adapted to the geometry by the next transient), until the slow time T.
///
/// Every window restarts the scene's clock at t = 0 (the reference solvers start there): its
/// loads restart with it, so the window T_tr + T_w should be a whole number of the loads'
/// periods for the carried state to meet the loads' phase it left (the scenes' headers give
/// them). The first window starts from the scene's initial state, after its own transient.
///
/// Its errors (docs/wear.md): the averaging over the window, the slow-time integration (order p
/// in D) and a change of the contact regime inside a jump, which extrapolation cannot follow.
/// The regime of a window is its impact count and the set of points or sectors that wear; a
/// jump whose end differs from its start — the impacts by more than 20 % of the larger count
/// and more than 2, a point or sector changing between worn (above 20 % of the largest rate)
/// and unworn (below 5 %), wear starting or stopping — is named in
/// CycleJumpResult::regime_changes.
///
/// A slow-time integrator outside its stability interval (the slow system's own decay rate λ
/// times D beyond −2 for Euler and Heun, −1 for AB2) makes the geometry overshoot at every jump:
/// the averaged rates of successive jumps oscillate and do not decay. That is named in
/// CycleJumpResult::slow_instability (Mukras et al. 2009 report it as the instability of the
/// geometry-update interval): over three successive jumps the change of the start windows'
/// rates Δr_k = r_k − r_{k−1} reverses its direction each time (Δr_k · Δr_{k−1} < 0) and its
/// size after the full oscillation has not decreased (|Δr_k| ≥ |Δr_{k−2}|), with |Δr_k| above
/// the windows' noise: max(1e-3, 100 rtol) of the largest rate.
#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "core/flexible_formulation.hpp"
#include "core/model.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::studies {

enum class SlowIntegrator { kEuler, kHeun, kAb2 };

/// "euler", "heun", "ab2"; and back (std::invalid_argument for another name).
const char* to_string(SlowIntegrator slow);
SlowIntegrator parse_slow_integrator(const std::string& name);
/// The order its authors claim: 1 (Euler), 2 (Heun, AB2).
int claimed_order(SlowIntegrator slow);

struct CycleJumpOptions {
  double window = 0.05;           ///< T_w, s of dynamics averaged per window
  double transient = 0.05;        ///< T_tr, s discarded at the start of every window
  double first_transient = -1.0;  ///< the first window's (< 0: transient), s
  double jump = 10.0;             ///< D, s of slow time per jump
  double until = 100.0;           ///< T, s of slow time
  SlowIntegrator slow = SlowIntegrator::kEuler;
  std::string solver = "cvode";  ///< the reference solver of the windows
  double rtol = 1e-8;
  core::FlexibleFormulation formulation = core::FlexibleFormulation::kLte;
  double output_step = 1e-3;  ///< the windows' output grid (it steers no solver step), s
  /// Called after every window with the slow time reached (for a progress line); may be empty.
  std::function<void(double slow_time)> on_window;
};

/// One window of dynamics.
struct WearWindow {
  int jump = 0;            ///< the jump it belongs to (from 0)
  std::string role;        ///< "start" (at h_k) or "predictor" (Heun's h̃)
  double slow_time = 0.0;  ///< τ_k of the jump, s
  Eigen::VectorXd depth;   ///< the geometry it ran on, m
  Eigen::VectorXd rate;    ///< averaged ḣ, m/s
  double impacts_per_second = 0.0;
  double cpu_seconds = 0.0;  ///< model build and solve, this thread
  long steps = 0;
};

struct WearPathPoint {
  double slow_time = 0.0;
  Eigen::VectorXd depth;
};

struct CycleJumpResult {
  CycleJumpOptions options;
  std::vector<std::string> channels;  ///< the worn contacts
  std::vector<int> channel_first;     ///< each channel's first depth
  std::vector<int> channel_count;     ///< and their count
  std::vector<int> channel_sectors;   ///< sectors (gap support), 0 for points
  std::vector<double> depth_areas;    ///< the scar area of each depth, m²
  std::vector<WearPathPoint> path;    ///< the depths at every jump's end, from τ = 0
  std::vector<WearWindow> windows;
  int jumps = 0;
  double fast_time = 0.0;                   ///< s of dynamics simulated
  double cpu_seconds = 0.0;                 ///< every window's
  std::vector<std::string> regime_changes;  ///< "jump 3 (t = 30 → 40 s): …"
  std::vector<int> regime_change_jumps;     ///< their jump indices
  /// The first non-decaying oscillation of the slow path (empty: none), "jumps 1-4 (t = 10 ->
  /// 40 s): …".
  std::string slow_instability;
};

/// The slow-time instability test above on the averaged rates of successive jumps (their start
/// windows, jump order), for the jumps' slow times; empty when the path does not oscillate.
std::string slow_instability(const std::vector<Eigen::VectorXd>& rates,
                             const std::vector<double>& slow_times, double rtol);

/// The scene on a worn geometry: each contact with a wear law starts from its slice of `depth`
/// (the model's depth layout: contacts in file order), with `frozen` geometry or not.
scene::SceneSpec with_wear_geometry(const scene::SceneSpec& spec, const Eigen::VectorXd& depth,
                                    bool frozen);
/// The scene starting from `state` of a model built from it (each body's pose, velocities and
/// modal coordinates; the worn depths are with_wear_geometry's).
scene::SceneSpec with_initial_state(const scene::SceneSpec& spec, const core::Model& model,
                                    const core::State& state);

/// Runs the scheme. Throws std::invalid_argument on options out of range or a scene without a
/// wear law, core::SolverError when a window's solve fails.
CycleJumpResult run_cycle_jump(const scene::SceneSpec& spec, const CycleJumpOptions& options);

}  // namespace flexref::studies
