#pragma once
/// \file lte_map.hpp
/// The `lte-map` study (docs/design/studies.md, "LTE breakdown"; docs/design/model.md, "The LTE
/// model"): where the linear theory of elastodynamics stops describing a spinning flexible body. On
/// a scene with one free flexible body, a grid of
///   - spin ratio x = Ω0/ω1: the initial spin rate over the first clamped elastic frequency
///     (Body::natural_frequencies()(0), the frame held fixed), and
///   - inertia ratio y = I_flex/I_rigid about the spin axis through the undeformed centre of
///     mass Br: I_flex of the flexible part (the nodes), I_rigid of the hub (its inertia about
///     its own centre plus the parallel-axis term m_hub d², d the distance of the hub's centre
///     from the axis),
/// is integrated three times per point by the same reference solver at the same tight tolerance
/// (docs/lte_map.md): with the LTE model, with the classical coupled model (the linear floating
/// frame, no geometric stiffening) and with the coupled model with geometric stiffening
/// (docs/geometric_stiffening.md), the **truth**: the classical coupled model softens in the
/// plane of rotation (ω² − Ω²) where a real beam stiffens, so at Ω/ω1 ≈ 0.3 its own error
/// exceeds the LTE model's. Both simplifications are measured against the truth (modelling
/// errors, not discretization errors). `--truth coupled` reproduces the two-level map of
/// earlier versions (LTE against the classical coupled model). How a grid point is built:
/// studies/lte_map_grid.hpp; the CSV and the table: studies/lte_map_report.hpp.
///
/// **Metrics** of a simplified model m against the truth t, per point, over the output times of
/// the stated horizon [0, end_time] (δ the elastic deflection of the tracked point in the body
/// frame, δ = p_BrP_B(P, q_f) − p_BrP_B(P, 0) = Φ_P q_f; all relative, so they do not depend on
/// the excitation's amplitude while the response is linear):
///   - tip error (L∞): max_t |δ_m(t) − δ_t(t)| / max_t |δ_t(t)| — mixes amplitude and phase, and
///     grows with the horizon as the phase drifts;
///   - envelope error: max_t |δ_m| / max_t |δ_t| − 1 (peak deflection: amplitude only);
///   - frequency shift: f_m / f_t − 1, f the dominant (first-mode) frequency of the deflection
///     component that varies most in the truth, from its zero crossings about its mean over the
///     second half of the horizon (after the spin-up transients; phase rate only);
///   - attitude error (LTE): max_t of the geodesic angle between the LTE and truth attitudes.
/// **Reference accuracy** (the 100× rule of docs/design/studies.md): each reference is rerun at
/// rtol/estimate_factor (tighter, accuracy_check_rtol, as the modes study and a certified
/// reference's checks); the difference of the deflections (same normalization) estimates the
/// run's own error. A model's tip error is `resolved` when it is ≥ 100 × the larger of its and
/// the truth's estimates.
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "studies/lte_map_grid.hpp"

namespace flexref::studies {

struct LteMapOptions {
  std::vector<double> spin_ratios;     ///< x = Ω0/ω1, > 0
  std::vector<double> inertia_ratios;  ///< y = I_flex/I_rigid about the spin axis, > 0
  double end_time = 10.0;              ///< s
  double output_step = 0.01;           ///< s
  std::string solver = "cvode";        ///< reference solver of both models
  double rtol = 1e-10;
  double estimate_factor = 10.0;  ///< the accuracy check reruns at rtol/estimate_factor
  bool scale_loads = true;
  /// The truth: the coupled model with geometric stiffening (true) or the classical coupled
  /// model (false: the two-level map, no classical-model metrics).
  bool stiffened_truth = true;
  int body = -1;      ///< the flexible body (−1: the first free flexible body)
  std::string point;  ///< the tracked node point (empty: the node point farthest from Br)
  int jobs = 1;
  bool progress = false;  ///< "lte-map: k/n grid points" on stderr (studies/progress.hpp)
};

struct LteMapPoint {
  double spin_ratio = 0.0;     ///< x
  double inertia_ratio = 0.0;  ///< y
  double spin = 0.0;           ///< Ω0 = x·ω1, rad/s
  double omega1 = 0.0;         ///< rad/s
  double hub_scale = 0.0;
  double load_scale = 0.0;
  // LTE against the truth.
  double tip_error = 0.0;        ///< L∞ tip error (relative): the map's primary metric
  double envelope_error = 0.0;   ///< peak deflection ratio − 1
  double frequency_shift = 0.0;  ///< dominant frequency ratio − 1 (NaN: too few crossings)
  double attitude_error = 0.0;   ///< rad
  // The classical coupled model against the truth (NaN when the truth is the classical model).
  double classical_tip_error = 0.0;
  double classical_envelope_error = 0.0;
  double classical_frequency_shift = 0.0;
  double max_deflection = 0.0;      ///< max_t |δ_truth|, m
  double truth_frequency = 0.0;     ///< dominant frequency of the truth, rad/s
  double truth_estimate = 0.0;      ///< estimated error of the truth (tip metric units)
  double lte_estimate = 0.0;        ///< same for the LTE reference
  double classical_estimate = 0.0;  ///< same for the classical reference
  bool resolved = false;            ///< tip_error ≥ 100 × max(truth, LTE estimates)
  bool classical_resolved = false;  ///< classical_tip_error ≥ 100 × max(truth, classical)
  /// "ok"; "no frequency shift: …" when a deflection crosses its mean fewer than three times
  /// over the second half (the other metrics are measured, the frequency cells are empty); or
  /// "failed: …".
  std::string status = "ok";
};

struct LteMapResult {
  LteMapOptions options;
  LteMapBase base;
  std::vector<LteMapPoint> points;  ///< inertia ratio major, spin ratio minor (option order)
  std::vector<std::string> notes;
};

/// lte_map_base (studies/lte_map_grid.hpp) of options.body and options.point.
LteMapBase lte_map_base(const core::Model& model, const LteMapOptions& options);

/// Runs the grid (parallel over points; the numbers do not depend on jobs).
LteMapResult run_lte_map(const LteModelFactory& factory, const LteMapOptions& options);

}  // namespace flexref::studies
