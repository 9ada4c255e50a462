#pragma once
/// \file reference_sidecar.hpp
/// What a reference says about itself: the `FILE.meta.toml` written next to `FILE` by
/// `flexref reference` (StudyRecord; its [error_estimate] table when the estimate was made),
/// read back so that a comparison can set the measured error beside the reference's own.
#include <limits>
#include <string>

namespace flexref::trajectory {

/// A measured error is certified when it is at least this many times the reference's
/// estimated error (docs/design/schemes.md: the reference then contributes at most 1 %).
inline constexpr double kCertificationFactor = 100.0;

/// The scene a result is of: the [scene] table of its sidecar (app::scene_record), or of the
/// scene a study reads.
struct SceneIdentity {
  std::string name;  ///< [scene] name; "" when unknown (no sidecar, or one without [scene])
  /// [scene] hash (scene/scene_identity.hpp); "" when unknown (a sidecar of an older flexref)
  std::string hash;
  std::string file;   ///< [scene] file, for messages
  std::string model;  ///< [scene] model ("lte", "coupled"); "" when absent
};

/// "" when `a` and `b` may be of the same scene: equal hashes; equal names when either hash is
/// unknown; either name unknown (nothing to check). Otherwise why not, naming both ("run.csv is
/// of scene coulomb_wall (fnv1a64:…, /x/coulomb_wall.toml) but ref.csv of free_spin (…)").
/// `a_what` and `b_what` name the two results in the message.
std::string scene_mismatch(const SceneIdentity& a, const std::string& a_what,
                           const SceneIdentity& b, const std::string& b_what);

struct ReferenceSidecar {
  std::string path;           ///< the sidecar file looked for
  bool found = false;         ///< the file exists
  SceneIdentity scene;        ///< its [scene] name, hash and file
  bool has_estimate = false;  ///< it has [error_estimate] (not --no-estimate)
  std::string metric;         ///< [error_estimate] metric
  /// [error_estimate] estimate; +inf when the reference found no usable check (its error is
  /// unknown, trajectory/certified_reference.hpp) — then nothing is certified against it.
  double estimate = 0.0;
  std::string estimate_method;  ///< [error_estimate] method: how it was made, "" when absent
  /// [error_estimate] energy_balance and energy_estimate, J (trajectory/certified_reference.hpp):
  /// the largest |E − E0 + W_d − W_a| and the estimated error of its terms; NaN when absent
  /// (a model that does not dissipate, or a file written before they were recorded).
  double energy_balance = std::numeric_limits<double>::quiet_NaN();
  double energy_estimate = std::numeric_limits<double>::quiet_NaN();
  std::string kind;    ///< [integrator] kind: "reference", "scheme"; "" when absent
  std::string solver;  ///< [integrator] solver, "" when absent
  double rtol = 0.0;   ///< [integrator] rtol, 0 when absent
  /// [integrator] precision ("double", "extended", "quad"; docs/precision.md), "double" when
  /// absent (every file but an extended/quad reference's).
  std::string precision = "double";
};

/// Reads the CSV's sidecar: `TARGET.meta.toml` beside the file a symbolic link `csv_path` points
/// to (where flexref writes it, io::sidecar_path), else `csv_path + ".meta.toml"`. A missing
/// file is not an error (found = false); a file that
/// is not TOML, or whose [error_estimate] lacks a non-negative `estimate` (+inf allowed: unknown;
/// NaN refused) or a `metric` string, is a core::InputError naming the file and key.
ReferenceSidecar read_reference_sidecar(const std::string& csv_path);

/// "certified" when error ≥ kCertificationFactor × estimate, else "NOT certified" (always for
/// an unknown, +inf estimate). Only meaningful when the sidecar has an estimate in the same
/// metric.
bool is_certified(double error, double estimate);

}  // namespace flexref::trajectory
