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
/// earlier versions (LTE against the classical coupled model).
///
/// **How a grid point is built** (LteMapScaling, applied by the caller's factory): the initial
/// angular velocity is scaled so that |ω0| = x·ω1 (direction kept); the hub is scaled as a whole
/// by s, its mass and its inertia about its own centre (its centre, the beam and the modal data
/// unchanged), with s found by bisection so that I_flex/I_rigid = y about the axis through the
/// new Br. Scaling the mass with the inertia matters: a free hub's translation couples with the
/// beam's bending as much as its rotation does (m_beam/m_total), so a heavier-inertia hub of the
/// same mass would not approach the LTE limit. When scale_loads is set, every applied load is
/// scaled by (|ω0|/|ω0,scene|)·(I_axis/I_axis,scene), I_axis the total undeformed inertia about
/// the spin axis, so that the spin history Ω(t)/Ω0 of the rigid motion is the scene's at every
/// grid point (the load drives the same relative spin-up).
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
#include "scene/scene_spec.hpp"

namespace flexref::studies {

/// What a grid point changes in the scene's flexible body (see the file comment).
struct LteMapScaling {
  double hub_scale = 1.0;  ///< s: hub mass ← s·mass, I_hub,Bcm ← s·I_hub,Bcm
  Eigen::Vector3d w0_WB_B = Eigen::Vector3d::Zero();  ///< initial angular velocity, body frame
  double load_scale = 1.0;  ///< every applied load's value ← load_scale·value
};

/// The three model levels of the map.
enum class LteMapLevel {
  kLte,        ///< linear theory of elastodynamics (inertia of the undeformed body)
  kClassical,  ///< coupled floating frame, no geometric stiffening
  kStiffened,  ///< coupled floating frame with geometric stiffening (the truth)
};

/// Builds the scene's model at a level with a grid point's changes applied (std::nullopt: the
/// scene unchanged but for the level); called concurrently from several threads (must not share
/// mutable state).
using LteModelFactory =
    std::function<core::Model(LteMapLevel, const std::optional<LteMapScaling>&)>;

/// The factory of a scene: copies the spec, sets the flexible body's geometric stiffening for the
/// level (a [body.beam] is regenerated with or without it; a modal file's [geometric_stiffness]
/// is dropped below the stiffened level), applies the scaling to body `body` (hub mass and
/// inertia, initial angular velocity) and to every [[load]] value, and builds the model. The
/// stiffened level throws std::invalid_argument when the body has no geometric-stiffness data
/// (a modal file without the section, a beam that is not clamped-free).
LteModelFactory lte_map_factory(scene::SceneSpec spec, int body);

/// Whether body `body` of the scene can be stiffened (a clamped-free [body.beam], or modal data
/// with geometric stiffness).
bool lte_map_can_stiffen(const scene::SceneSpec& spec, int body);

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

/// The scene's own values the grid is built from.
struct LteMapBase {
  std::string body;
  std::string point;
  double omega1 = 0.0;         ///< first clamped frequency, rad/s
  double spin = 0.0;           ///< |ω0| of the scene, rad/s
  Eigen::Vector3d axis_B;      ///< spin axis (unit, body frame)
  double inertia_flex = 0.0;   ///< the scene's I_flex about the axis through Br, kg·m²
  double inertia_rigid = 0.0;  ///< the scene's I_rigid about the axis through Br, kg·m²
  double hub_mass = 0.0;       ///< kg
  double hub_inertia = 0.0;    ///< the hub's own inertia about the axis (through its centre)
  Eigen::Vector3d p_BoHub_B;   ///< hub centre
  double flex_mass = 0.0;      ///< kg
  double flex_inertia = 0.0;   ///< the flexible part's inertia about the axis through its centre
  Eigen::Vector3d p_BoFlex_B;  ///< centre of mass of the flexible part (undeformed)
  double inertia_ratio = 0.0;  ///< the scene's y = I_flex/(a + b)
  double spin_ratio = 0.0;     ///< the scene's x = |ω0|/ω1
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

/// The scene's base values; throws std::invalid_argument when the model has no free flexible
/// body (or `body` is not one), no initial spin, or no node point.
LteMapBase lte_map_base(const core::Model& model, const LteMapOptions& options);

/// I_flex/I_rigid about the spin axis through the undeformed centre of mass when the hub is
/// scaled by s.
double lte_map_inertia_ratio(const LteMapBase& base, double hub_scale);

/// The scaling of grid point (x, y); throws std::invalid_argument for non-positive ratios or
/// when y cannot be reached with a hub scale in [1e-12, 1e12].
LteMapScaling lte_map_scaling(const LteMapBase& base, double spin_ratio, double inertia_ratio,
                              bool scale_loads);

/// Runs the grid (parallel over points; the numbers do not depend on jobs).
LteMapResult run_lte_map(const LteModelFactory& factory, const LteMapOptions& options);

/// A metric of the map: which simplification, which measure (absolute values).
enum class LteMapMetric { kTip, kEnvelope, kFrequency };
double lte_map_value(const LteMapPoint& point, bool classical, LteMapMetric metric);

/// Where a metric (default: the LTE tip error) crosses `level` along each inertia ratio's row:
/// the spin ratio by log-log interpolation between the bracketing grid points, NaN when the
/// row does not cross.
std::vector<double> lte_map_crossings(const LteMapResult& result, double level,
                                      bool classical = false,
                                      LteMapMetric metric = LteMapMetric::kTip);

/// `count` values spaced logarithmically in [lo, hi] (just lo when count is 1); throws
/// std::invalid_argument unless 0 < lo ≤ hi and count ≥ 1.
std::vector<double> log_spaced_values(double lo, double hi, int count);

/// CSV columns: spin_ratio,inertia_ratio,spin,omega1,hub_scale,load_scale,tip_error,
/// envelope_error,frequency_shift,attitude_error,classical_tip_error,classical_envelope_error,
/// classical_frequency_shift,max_deflection,truth_frequency,truth_estimate,lte_estimate,
/// classical_estimate,resolved,classical_resolved,status. A value that is not measured (a
/// failed point, the classical columns of a two-level map, a frequency the status says is
/// missing) is an empty cell, never NaN.
std::string lte_map_csv(const LteMapResult& result);
/// The terminal table: the LTE tip error (%) per inertia ratio (rows) and spin ratio (columns),
/// the classical coupled model's (stiffened truth), the crossings of the 1 %, 5 % and 20 % lines
/// of every metric, and the notes.
std::string format_lte_map_table(const LteMapResult& result);

}  // namespace flexref::studies
