#pragma once
/// \file lte_map_grid.hpp
/// The grid points of the `lte-map` study (studies/lte_map.hpp): the scene's base values (the
/// flexible body, its tracked point, ω1, the spin axis and the inertia split), the scaling of a
/// grid point (x, y) and the factory that builds the scene's model at a level with a point's
/// scaling applied.
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
#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/body.hpp"
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

/// The free flexible body the map varies: `requested` when it is one (≥ 0), else the first;
/// throws std::invalid_argument when there is none (or `requested` is not one).
int lte_map_body(const core::Model& model, int requested);
/// The body's node point named `name`, or (empty name) the node point farthest from Br; throws
/// std::invalid_argument when the name is not a node point or the body tracks none.
const core::TrackedPoint& lte_map_point(const core::Body& body, const std::string& name);

/// The scene's base values of body `body` (lte_map_body) and point `point` (lte_map_point);
/// throws std::invalid_argument when the model has no free flexible body (or `body` is not
/// one), no initial spin, or no node point.
LteMapBase lte_map_base(const core::Model& model, int body, const std::string& point);

/// I_flex/I_rigid about the spin axis through the undeformed centre of mass when the hub is
/// scaled by s.
double lte_map_inertia_ratio(const LteMapBase& base, double hub_scale);

/// The scaling of grid point (x, y); throws std::invalid_argument for non-positive ratios or
/// when y cannot be reached with a hub scale in [1e-12, 1e12].
LteMapScaling lte_map_scaling(const LteMapBase& base, double spin_ratio, double inertia_ratio,
                              bool scale_loads);

/// `count` values spaced logarithmically in [lo, hi] (just lo when count is 1); throws
/// std::invalid_argument unless 0 < lo ≤ hi and count ≥ 1.
std::vector<double> log_spaced_values(double lo, double hi, int count);

}  // namespace flexref::studies
