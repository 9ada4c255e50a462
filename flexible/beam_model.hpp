#pragma once
/// \file beam_model.hpp
/// The built-in beam finite-element model that produces modal data
/// (docs/modal_data.md): a straight, uniform 3D beam along the body x axis, Euler–Bernoulli
/// bending in the planes xy and xz (Hermite cubics), axial extension and torsion (linear),
/// 12 DOF per element, consistent stiffness and consistent mass. The four families of modes
/// are uncoupled for a straight beam whose centroid and shear centre lie on its axis, so each
/// family is solved on its own (Eigen::GeneralizedSelfAdjointEigenSolver): modes are pure and
/// classified exactly even when EI_y = EI_z makes the two bending families degenerate.
///
/// The modal data's material points are the 5-point Gauss–Lobatto points of every element (the
/// two element ends, shared with the neighbours, and three interior points), weighted by ρA
/// times the quadrature weights, with the mode shapes interpolated by the element's own shape
/// functions. That quadrature integrates polynomials of degree 7 exactly, so every nodal sum
/// of the floating-frame model (m, s0, I0, S, m_ff, Ī_θθ(q_f), Ī_θf(q_f), …; at most degree 6)
/// equals the integral over the finite-element beam: the modes are exactly orthonormal
/// w.r.t. the point masses, and the floating-frame model vibrates at the finite-element
/// frequencies, which converge as O(h⁴). Rotary inertia of the cross-sections is neglected
/// (Euler–Bernoulli, points on the axis); torsion modes carry no displacement of the axis and
/// are therefore not part of the modal data (their frequencies are available here).
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "flexible/modal_data.hpp"

namespace flexref::flexible {

enum class BeamBoundary {
  kClampedFree,  ///< all 6 DOF fixed at the root x = origin, tip free
  kFreeFree,     ///< both ends free; the 6 rigid-body modes are excluded
  /// Root clamped, tip pinned: the tip node's displacements (u, v, w, θx) fixed, its slopes free
  /// (a tube between a clamped end and a simple support).
  kClampedPinned,
  kClampedClamped,  ///< both ends clamped (all 6 DOF of both end nodes fixed)
};

enum class BeamModeFamily {
  kAxial,      ///< displacement u along x; EA, ρA
  kBendingXY,  ///< deflection v along y, bending about z; EI_z, ρA
  kBendingXZ,  ///< deflection w along z, bending about y; EI_y, ρA
  kTorsion,    ///< rotation θx about x; GJ, ρJ
};

/// "axial", "bending-xy", "bending-xz", "torsion".
std::string to_string(BeamModeFamily family);

/// A straight uniform beam along the body x axis, from `origin` to origin + length·e_x.
struct BeamParameters {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< root point, body frame, m
  double length = 1.0;                               ///< L, m
  int elements = 20;                                 ///< equal elements
  double EA = 1.0;                                   ///< axial stiffness, N
  double EI_y = 1.0;  ///< bending stiffness about y (deflection along z), N·m²
  double EI_z = 1.0;  ///< bending stiffness about z (deflection along y), N·m²
  /// Torsional stiffness, N·m². Default (EI_y + EI_z)/(2(1 + ν)) with ν = 0.3: a solid circular
  /// section (J = I_p) of an isotropic material.
  std::optional<double> GJ;
  double rho_A = 1.0;  ///< mass per length ρA, kg/m
  /// Polar mass moment per length ρJ = ρ I_p, kg·m. Default ρA (EI_y + EI_z)/EA, exact for any
  /// homogeneous cross-section (I_p = I_y + I_z and the same E and ρ over the section).
  std::optional<double> rho_J;
  BeamBoundary boundary = BeamBoundary::kClampedFree;
};

/// Why the parameters are unusable (non-positive or non-finite values, no element), or empty.
std::string beam_parameters_problem(const BeamParameters& parameters);

/// One elastic mode of the finite-element beam, normalized to unit modal mass with the
/// consistent mass (∫ρA v² dx = 1 for a bending mode, ∫ρJ θ² dx = 1 for torsion) and signed so
/// that its value at the tip (x = origin + L) is positive.
struct BeamMode {
  BeamModeFamily family = BeamModeFamily::kBendingXY;
  int order = 1;  ///< 1 for the family's lowest elastic mode
  /// rad/s; ω² is the Rayleigh quotient of the mode evaluated from the element strains (the
  /// eigenvalue without its rounding floor ε·λ_max/λ, see docs/modal_data.md).
  double omega = 0.0;
  /// The family's field at the elements + 1 nodes, root to tip: u, v, w (m) or θx (rad).
  Eigen::VectorXd value;
  /// Its derivative d/dx at the nodes (bending families: dv/dx, dw/dx); empty otherwise.
  Eigen::VectorXd slope;
};

/// All elastic modes of one family, ascending in ω; rigid-body modes (free-free) excluded.
/// Throws std::invalid_argument on bad parameters.
std::vector<BeamMode> solve_beam_family(const BeamParameters& parameters, BeamModeFamily family);

/// All elastic modes of all four families, ascending in ω (ties: in the family order above).
std::vector<BeamMode> solve_beam_modes(const BeamParameters& parameters);

/// Which families enter the modal data. Torsion never does (see the file comment).
struct BeamModeFilter {
  bool axial = true;
  bool bending_xy = true;
  bool bending_xz = true;
};

enum class BeamModeNormalization {
  kUnitModalMass,        ///< μ_i = Σ m_k |Φ_k,i|² = 1 (default)
  kUnitTipDisplacement,  ///< the family's displacement at the tip is 1 m per unit q_i
};

/// Modal data of the beam: the n_modes lowest elastic modes of the families in `filter`, on
/// the Gauss–Lobatto material points (names "node0" … "nodeE" for the element ends, root to
/// tip, and "eJ_q1" … "eJ_q3" for the interior points of element J = 0 … E−1), stiffness
/// K_i = ω_i² μ_i, zero damping ratios, mode names "<family>-<order>" ("bending-xy-1").
/// Throws std::invalid_argument on bad parameters or when fewer than n_modes modes exist.
///
/// `geometric_stiffness`: also the unit-load geometric stiffness matrices E_c, F_ab of the
/// foreshortening (flexible/geometric_stiffness.hpp), from the Hermite slopes of the modes and
/// the axial force of the unit fields; clamped-free beams only (std::invalid_argument otherwise).
ModalData make_beam_modal_data(
    const BeamParameters& parameters, int n_modes, const BeamModeFilter& filter = {},
    BeamModeNormalization normalization = BeamModeNormalization::kUnitModalMass,
    bool geometric_stiffness = false);

}  // namespace flexref::flexible
