#pragma once
/// \file nodal_mass_lumping.hpp
/// Lumped nodal masses for a floating-frame body from a finite-element (consistent) mass
/// matrix, chosen so that the body's inertia invariants are those of the finite-element
/// model (docs/calculix.md, "Nodal masses").
///
/// The floating frame's inertia terms are nodal sums Σ m_k(·) (docs/modal_data.md). Every sum
/// that is linear in the masses has a finite-element counterpart that is a projection of the
/// consistent mass matrix: with M = M0 ⊗ I₃ (the same scalar mass matrix M0 in the three
/// directions, as for every solid element), positions x and mode shapes Φ interpolated by the
/// element shape functions (which represent x, and hence rigid motions, exactly),
///   m = 1ᵀM0 1,  s0 = Σ m x ↔ X̂ᵀM0 1,  J0 = Σ m x xᵀ ↔ X̂ᵀM0 X̂,
///   S = Σ m Φ ↔ Φ_bᵀM0 1 (3×n),  X_ab = Σ m x_a Φ_b ↔ x_aᵀM0 Φ_b (9×n),
///   m_ff = Σ m Φᵀ Φ ↔ Σ_a Φ_aᵀ M0 Φ_a (n×n),  P_ab = Σ m Φ_aᵀ Φ_b ↔ Φ_aᵀ M0 Φ_b,
/// where Φ_a (N×n) are the direction-a rows of Φ. Masses are chosen by
///   min Σ_k (m_k − m_k⁰)²/m_k⁰   subject to   A m = b
/// (the smallest relative change from m⁰, the diagonal scaling of M, Hinton–Rock–Zienkiewicz
/// 1976, "HRZ", positive for every element, unlike row sums, which are negative at the corners
/// of 20-node bricks), whose solution is m = m⁰ + W Aᵀλ, W = diag(m⁰), (A W Aᵀ)λ = b − A m⁰.
/// Two levels of constraints A m = b:
///   - moment_matched_masses: the ten rigid-body moments (m, s0, J0): always possible with four
///     or more non-coplanar nodes, unless a mass turns negative;
///   - invariant_matched_masses: in addition S, X and m_ff — every invariant the mass matrix
///     of the floating frame depends on at q_f = 0 — so that the body's frequencies, its
///     coupling of rigid and elastic motion and the centrifugal load on its modes are those of
///     the finite-element model; 10 + 12n + n(n+1)/2 constraints, which need more nodes than
///     that and may fail (a negative mass): the caller then falls back to the moments.
/// P_ab (quadratic in q_f: the centrifugal softening and the inertia change with deformation)
/// stays lumped; its difference is reported.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <string>
#include <vector>

namespace flexref::scene {

/// Rigid-body mass properties about the frame origin Bo.
struct MassProperties {
  double mass = 0.0;                             ///< m, kg
  Eigen::Vector3d s0 = Eigen::Vector3d::Zero();  ///< Σ m x, kg·m
  Eigen::Matrix3d J0 = Eigen::Matrix3d::Zero();  ///< Σ m x xᵀ, kg·m²
  /// Inertia about Bo, tr(J0) I − J0.
  Eigen::Matrix3d I0() const;
  /// Centre of mass s0/m.
  Eigen::Vector3d centre() const { return s0 / mass; }
};

/// Relative differences of b against a: |Δm|/m, |Δs0|/(m ρ) and ‖ΔI0‖_F/‖I0‖_F, with
/// ρ = √(tr J0/m) the radius of gyration about Bo (so that a first moment that vanishes by
/// symmetry is measured against the body's size).
struct MassPropertyDifference {
  double mass = 0.0;
  double first_moment = 0.0;
  double inertia = 0.0;
  double max() const;
};
MassPropertyDifference relative_difference(const MassProperties& a, const MassProperties& b);

/// The inertia invariants that the masses enter linearly (see the file comment); the shapes Φ
/// are 3N×n with rows 3k + a.
struct LinearInvariants {
  MassProperties rigid;
  Eigen::MatrixXd S;                 ///< 3×n
  Eigen::MatrixXd X;                 ///< 9×n, row 3a + b: Σ m x_a Φ_b
  Eigen::MatrixXd m_ff;              ///< n×n
  std::array<Eigen::MatrixXd, 9> P;  ///< [3a + b]: Σ m Φ_aᵀ Φ_b (n×n)
};

/// Relative differences of b against a: S and X against their Cauchy–Schwarz bounds
/// √(m tr m_ff) and √(tr J0 tr m_ff), m_ff and P (all nine) against tr m_ff (Frobenius norms).
struct InvariantDifference {
  MassPropertyDifference rigid;
  double S = 0.0;
  double X = 0.0;
  double m_ff = 0.0;
  double P = 0.0;
  double max_linear() const;  ///< the largest but P's
};
InvariantDifference relative_difference(const LinearInvariants& a, const LinearInvariants& b);

/// Σ m_k (1, x_k, x_k x_kᵀ).
MassProperties nodal_mass_properties(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& x);
/// The nodal sums of LinearInvariants.
LinearInvariants nodal_invariants(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& x,
                                  const Eigen::MatrixXd& phi);

/// M0, the x-direction block of a mass matrix whose row 3k + a is direction a of node k.
/// `anisotropy` receives max |M − M0 ⊗ I₃| / max |M| (0 for solid elements; a mass matrix with
/// direction couplings or different directions is not one of the floating frame).
Eigen::SparseMatrix<double> scalar_mass_matrix(const Eigen::SparseMatrix<double>& M,
                                               double& anisotropy);
/// The finite-element counterparts of LinearInvariants from M0 (N×N).
LinearInvariants consistent_invariants(const Eigen::SparseMatrix<double>& M0,
                                       const Eigen::Matrix3Xd& x, const Eigen::MatrixXd& phi);

/// HRZ masses: the diagonal of M0 (given as a vector) scaled to the total mass.
Eigen::VectorXd diagonal_scaled_masses(const Eigen::VectorXd& M0_diagonal, double total_mass);

/// Moves every node's mass to the nearest node of `kept` (indices into x), for a body that keeps
/// a subset of the nodes; returns the masses of the kept nodes in the order of `kept`.
Eigen::VectorXd masses_on_nearest(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& x,
                                  const std::vector<int>& kept);

/// Masses at x, starting from `initial` (> 0), with the moments m, s0, J0 of `target`. Throws
/// std::invalid_argument when the nodes cannot carry them (coplanar, collinear or fewer than
/// four nodes) or a mass would become ≤ 0, saying which.
Eigen::VectorXd moment_matched_masses(const Eigen::VectorXd& initial, const Eigen::Matrix3Xd& x,
                                      const MassProperties& target);

/// Which invariants invariant_matched_masses matches besides m, s0, J0.
struct InvariantSelection {
  bool modal_masses = true;      ///< diag(m_ff): each mode's modal mass (n constraints)
  bool full_modal_mass = false;  ///< all of m_ff (n(n+1)/2 constraints; implies the diagonal)
  bool first_moment = false;     ///< S (3n)
  bool position_moment = false;  ///< X (9n)
  /// "m, s0, J0, diag(m_ff), S", …
  std::string describe() const;
};

/// The selections tried by the CalculiX import, most to least complete: m_ff, S and X; then
/// diag(m_ff), S and X; diag(m_ff) and S; diag(m_ff); none (the moments only).
std::vector<InvariantSelection> invariant_selections();

/// Masses at x with the moments and the selected invariants of `target` for the shapes `phi`
/// (3N×n, the kept nodes' rows). Throws std::invalid_argument when the constraints cannot be met
/// (more constraints than the nodes can carry, or a mass would become ≤ 0).
Eigen::VectorXd invariant_matched_masses(const Eigen::VectorXd& initial, const Eigen::Matrix3Xd& x,
                                         const Eigen::MatrixXd& phi, const LinearInvariants& target,
                                         const InvariantSelection& selection);

}  // namespace flexref::scene
