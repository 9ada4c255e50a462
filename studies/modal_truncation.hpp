#pragma once
/// \file modal_truncation.hpp
/// The `modes` study (docs/design/studies.md): how many modes a scene's flexible body
/// needs. The scene is integrated with the body's modal basis truncated to each of the given
/// mode counts (a beam body, [body.beam], is solved again with `modes = m`: the m lowest modes of
/// the same finite-element model; a body whose modes come from a file keeps the file's first m
/// modes), by the same reference solver at the same tolerance, and each run is compared with
/// the run of the largest count (the most complete model, the study's reference):
///
///   - tip_error (primary): max_t |δ_m(t) − δ_M(t)| / max_t |δ_M(t)|, δ the elastic deflection
///     of the tracked node point in the body frame, δ = p_BrP_B(P, q_f) − p_BrP_B(P, 0) = Φ_P q_f
///     (as in the lte-map study), and the same in metres (tip_error_m);
///   - attitude_error: max_t of the geodesic angle between the body's attitudes (rad).
///
/// **Reference accuracy** (docs/design/studies.md): every run is repeated at rtol/estimate_factor
/// on the same output times, and the difference estimates the run's integration error (as a
/// certified reference's 'vs tighter' check); a check that took the run's own number of steps is
/// not a different solution, and its estimate is +∞ (the row is then unresolved). No solver's
/// steps depend on the output grid (every solver interpolates its output), and the grid enters the
/// automatic method choice (reference/method_choice.hpp): the check runs the same method. A row is
/// `resolved` when its errors are at least 10× the larger estimate of the two runs compared
/// (its own and the reference's): below that the truncation error is not separated from the
/// integration error and the value is an upper bound.
///
/// Initial modal coordinates q0, q̇0 are truncated with the basis (the first m entries); a
/// per-mode list of damping ratios likewise. More modes than the scene gives them for is an
/// error.
#include <string>
#include <vector>

#include "core/model.hpp"
#include "scene/scene_spec.hpp"

namespace flexref::studies {

struct ModalTruncationOptions {
  std::vector<int> mode_counts = {4, 8, 16, 32, 64};  ///< ≥ 1, distinct; sorted by the study
  double end_time = 10.0;                             ///< s
  double output_step = 0.01;                          ///< s
  std::string solver = "odeint";
  double rtol = 1e-10;
  double estimate_factor = 10.0;  ///< the accuracy check reruns at rtol/estimate_factor
  core::FlexibleFormulation formulation = core::FlexibleFormulation::kCoupled;
  int body = -1;      ///< the flexible body (−1: the first one)
  std::string point;  ///< the tracked node point (empty: the node point farthest from Br)
  int jobs = 1;
  bool progress = false;  ///< "modes: k/n runs" on stderr
};

struct ModalTruncationRow {
  int modes = 0;
  double omega_max = 0.0;          ///< highest natural frequency retained (frame fixed), rad/s
  double tip_error = 0.0;          ///< relative (see the file comment); 0 for the reference row
  double tip_error_m = 0.0;        ///< m
  double attitude_error = 0.0;     ///< rad
  double max_deflection = 0.0;     ///< max_t |δ_m|, m
  double tip_estimate = 0.0;       ///< estimated integration error of this run, tip_error units
  double attitude_estimate = 0.0;  ///< same for the attitude, rad
  bool resolved = false;  ///< both errors ≥ 10 × the larger estimate of this run and the reference
  long steps = 0;         ///< solver steps of the tight run
  double cpu_seconds = 0.0;   ///< CPU time of the tight run
  std::string status = "ok";  ///< "ok" or "failed: …"
};

struct ModalTruncationResult {
  ModalTruncationOptions options;  ///< with mode_counts sorted
  std::string body;
  std::string point;
  int reference_modes = 0;
  std::vector<ModalTruncationRow> rows;  ///< ascending mode count; the last is the reference
  std::vector<std::string> notes;
};

/// The scene with body `body`'s modal basis truncated to `modes` (see the file comment).
/// Throws std::invalid_argument when the body is not flexible or has fewer modes available.
scene::SceneSpec truncate_modes(const scene::SceneSpec& spec, int body, int modes);

/// Runs the study (parallel over the runs; the numbers do not depend on jobs). Throws
/// std::invalid_argument on bad options (no flexible body, no node point, a mode count below 1
/// or repeated, fewer than two counts).
ModalTruncationResult run_modal_truncation(const scene::SceneSpec& spec,
                                           const ModalTruncationOptions& options);

/// CSV columns: modes,omega_max,tip_error,tip_error_m,attitude_error,max_deflection,
/// tip_estimate,attitude_estimate,resolved,steps,cpu_seconds,status.
std::string modal_truncation_csv(const ModalTruncationResult& result);
/// The terminal table with the notes.
std::string format_modal_truncation_table(const ModalTruncationResult& result);

}  // namespace flexref::studies
