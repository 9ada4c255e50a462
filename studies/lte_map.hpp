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
/// is integrated twice per point, with the coupled and with the LTE model, by the same
/// reference solver at the same tight tolerance, and the LTE model's error against the coupled
/// model is measured (both converged: a modelling error, not a discretization error).
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
/// **Metrics** (per point, over the output times of [0, end_time]):
///   - tip_error (primary): max_t |δ_LTE(t) − δ_C(t)| / max_t |δ_C(t)|, δ the elastic
///     deflection of the tracked point in the body frame, δ = p_BrP_B(P, q_f) − p_BrP_B(P, 0)
///     = Φ_P q_f (relative: the metric does not depend on the excitation's amplitude while the
///     response is linear);
///   - attitude_error: max_t of the geodesic angle between the two models' attitudes (rad).
/// **Reference accuracy** (the 100× rule of docs/design/studies.md): each of the two references is
/// rerun at estimate_factor·rtol (looser); the difference of the deflections (same
/// normalization) estimates the looser run's error, an upper bound of the tight run's. A point
/// is `resolved` when tip_error ≥ 100 × the larger of the two estimates.
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

/// Builds the scene's model for a formulation with a grid point's changes applied (std::nullopt:
/// the scene unchanged); called concurrently from several threads (must not share mutable
/// state).
using LteModelFactory =
    std::function<core::Model(core::FlexibleFormulation, const std::optional<LteMapScaling>&)>;

/// The factory of a scene: copies the spec, applies the scaling to body `body` (hub mass and
/// inertia, initial angular velocity) and to every [[load]] value, and builds the model.
LteModelFactory lte_map_factory(scene::SceneSpec spec, int body);

struct LteMapOptions {
  std::vector<double> spin_ratios;     ///< x = Ω0/ω1, > 0
  std::vector<double> inertia_ratios;  ///< y = I_flex/I_rigid about the spin axis, > 0
  double end_time = 10.0;              ///< s
  double output_step = 0.01;           ///< s
  std::string solver = "cvode";        ///< reference solver of both models
  double rtol = 1e-10;
  double estimate_factor = 10.0;  ///< the accuracy check reruns at estimate_factor·rtol
  bool scale_loads = true;
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
  double tip_error = 0.0;         ///< primary metric (relative)
  double attitude_error = 0.0;    ///< rad
  double max_deflection = 0.0;    ///< max_t |δ_C|, m
  double coupled_estimate = 0.0;  ///< estimated error of the coupled reference (tip metric units)
  double lte_estimate = 0.0;      ///< same for the LTE reference
  bool resolved = false;          ///< tip_error ≥ 100 × max(estimates)
  std::string status = "ok";      ///< "ok" or "failed: …"
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

/// Where the tip error crosses `level` along each inertia ratio's row: the spin ratio by
/// log-log interpolation between the bracketing grid points, NaN when the row does not cross.
std::vector<double> lte_map_crossings(const LteMapResult& result, double level);

/// `count` values spaced logarithmically in [lo, hi] (just lo when count is 1); throws
/// std::invalid_argument unless 0 < lo ≤ hi and count ≥ 1.
std::vector<double> log_spaced_values(double lo, double hi, int count);

/// CSV columns: spin_ratio,inertia_ratio,spin,omega1,hub_scale,load_scale,tip_error,
/// attitude_error,max_deflection,coupled_estimate,lte_estimate,resolved,status.
std::string lte_map_csv(const LteMapResult& result);
/// The terminal table: tip error (%) per inertia ratio (rows) and spin ratio (columns), the
/// crossings of the 1 %, 5 % and 20 % lines, and the notes.
std::string format_lte_map_table(const LteMapResult& result);

}  // namespace flexref::studies
