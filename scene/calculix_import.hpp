#pragma once
/// \file calculix_import.hpp
/// Modal data of a floating-frame body from a CalculiX model (docs/calculix.md): the mode
/// shapes and eigenvalues of a `*FREQUENCY` step (calculix_frd.hpp) and the consistent mass and
/// stiffness matrices of the free solid (calculix_matrices.hpp).
///
/// Steps (each checked; any failure is an error and nothing is produced):
///  1. the .dof rows are mapped onto the .frd nodes (calculix_dof_map.hpp): every .frd node has
///     its 3 directions or belongs to a shell or beam expansion; the rows the .frd does not show
///     (bubble amplitudes, tied expansions, held rows) are condensed (calculix_condensation.hpp);
///     a rigid motion must carry no force (kRigidForceTolerance) and leave the bubble
///     amplitudes at rest (kInternalRigidTolerance);
///  2. the mass matrix must be M0 ⊗ I₃ on the .frd's nodes (solid elements: anisotropy ≤
///     kAnisotropyTolerance); its projections on the fields at every row give the solid's m,
///     s0, J0 and the other invariants that are linear in the masses (nodal_mass_lumping.hpp);
///  3. rigid-body modes (a free or partly free solid) are those whose shape lies within
///     `rigid_tolerance` (M-norm, relative) of a rigid motion; they are removed, and the
///     elastic modes are made exactly M-orthogonal to the rigid motions they span;
///  4. each kept elastic mode is checked against the matrices: its Rayleigh quotient
///     φᵀKφ/φᵀMφ must equal ccx's eigenvalue within kRayleighTolerance (wrong files, or modes
///     of another model, fail here);
///  5. nodal masses on the kept nodes (the .frd's, and the shell and beam nodes of the deck that
///     no expanded node lies at) reproduce the solid's m, s0, J0 and as many of the
///     kept modes' invariants m_ff, S, X as the nodes can carry with positive masses (the
///     first of invariant_selections() that succeeds; a note says when not all);
///     m, s0, J0 are checked to kMassPropertyTolerance;
///  6. shapes are scaled to unit modal mass with these masses, μ_i = Σ m_k |Φ_k,i|² = 1, and
///     the stiffness is the finite-element strain energy of the scaled shape,
///     K_i = λ_i (φ_iᵀ M φ_i)/μ_i (exact for an eigenvector);
///  7. self-check: the body's own frequencies, eig(diag K, m_ff) with m_ff = Σ m_k Φ_kᵀΦ_k,
///     against ccx's √λ_i; the relative difference per mode is the error of the lumped mass
///     model; self_check_passed says whether all are within `frequency_tolerance` (the
///     command line refuses to write the file otherwise, unless --accept).
#include <string>
#include <utility>
#include <vector>

#include "flexible/modal_data.hpp"
#include "scene/calculix_dof_map.hpp"
#include "scene/calculix_frd.hpp"
#include "scene/calculix_input_deck.hpp"
#include "scene/calculix_matrices.hpp"
#include "scene/nodal_mass_lumping.hpp"

namespace flexref::scene {

/// Default of `frequency_tolerance` (docs/calculix.md, "Self-check"): 1 %. It accepts the
/// lumped-mass error left when the modal masses are matched (step 5) and refuses the larger
/// one of the moments alone (HRZ-type lumping), whose higher modes come out low by more than a
/// percent on coarse meshes (measured: docs/calculix.md, "Nodal masses" and "Accuracy").
inline constexpr double kDefaultFrequencyTolerance = 0.01;
/// A mode lies within this relative M-norm distance of a rigid motion: rigid-body mode.
inline constexpr double kDefaultRigidTolerance = 1e-3;
/// Rayleigh quotient against ccx's eigenvalue: the .frd's 6 significant digits perturb a
/// shape by ≈ 5e-6 relative per entry, whose strain energy raises the quotient by
/// ≈ (5e-6)² λ_max/λ_i, λ_max the mesh's highest eigenvalue, so 1e-2 allows λ_max/λ_1 up to
/// 4e8 (thin elements raise λ_max: the example blade's are near it, docs/calculix.md step 4).
/// Files of another model differ by O(1).
inline constexpr double kRayleighTolerance = 1e-2;
/// ccx scales its modes to unit modal mass with its mass matrix: φᵀMφ = 1 up to the .frd's
/// rounding, first order in the shapes' 5e-6 perturbation (≈ 1e-5). A mass matrix of another
/// model (another density, mesh or element type) misses by its ratio.
inline constexpr double kModalMassTolerance = 1e-4;
/// Bubble amplitudes of incompatible modes are zero on rigid motions (the patch test: zero to
/// round-off, docs/calculix.md): a row the .frd does not show that moves more than this with a
/// rigid motion is a node of another mesh.
inline constexpr double kInternalRigidTolerance = 1e-6;
/// Largest force of a rigid motion of the .frd's nodes with the stiffness matrix, relative to
/// max|K| max|R|: the positions' 6 printed digits leave ≲ 5e-6; rows mapped to wrong nodes
/// (another mesh, wrong shell or beam nodes) give O(1e-2…1).
inline constexpr double kRigidForceTolerance = 1e-4;
/// Nodal mass properties against the finite-element ones (the requirement).
inline constexpr double kMassPropertyTolerance = 1e-6;
/// M − M0 ⊗ I₃ relative to max |M|: ccx computes the three direction blocks of a solid element
/// from the same numbers and prints 14 digits, so they agree to ≈ 1e-14.
inline constexpr double kAnisotropyTolerance = 1e-10;

struct CalculixImportOptions {
  int frequency_step = 1;  ///< which *FREQUENCY step of the .frd (1: the first)
  std::vector<int> modes;  ///< 1-based indices among the elastic modes; empty: all
  /// Ranges [first, last] of ccx node numbers to keep (empty: all nodes). A range keeps the
  /// mesh nodes it contains and must contain one; a single number must be a mesh node.
  std::vector<std::pair<int, int>> nodes;
  double frequency_tolerance = kDefaultFrequencyTolerance;
  double rigid_tolerance = kDefaultRigidTolerance;
};

/// One kept elastic mode.
struct CalculixModeCheck {
  int ccx_mode = 0;                    ///< ccx's mode number
  double omega_ccx = 0.0;              ///< √λ, rad/s (from the .frd's frequency, 10 digits)
  double rayleigh_difference = 0.0;    ///< φᵀKφ/(φᵀMφ λ) − 1
  double consistent_modal_mass = 0.0;  ///< φᵀMφ of ccx's shape (1 with ccx's normalization)
  double omega_body = 0.0;             ///< the body's frequency of the same rank, rad/s
  double difference = 0.0;             ///< ω_body/ω_ccx − 1
};

/// A removed rigid-body mode.
struct CalculixRigidMode {
  int ccx_mode = 0;
  double eigenvalue = 0.0;  ///< ccx's λ (≈ 0)
  double distance = 0.0;    ///< relative M-norm distance of the shape from a rigid motion
};

struct CalculixImport {
  flexible::ModalData data;
  int frequency_step = 0;  ///< ccx's step number
  int total_nodes = 0;     ///< nodes of the .frd (the body keeps data.node_count() of these and
                           ///< of dof_map.added)
  MassProperties solid;    ///< from the mass matrix (all nodes)
  MassProperties body;     ///< from the nodal masses
  MassPropertyDifference mass_difference;
  /// Nodal invariants of the kept modes (ccx's normalization) against the mass matrix's.
  InvariantDifference invariant_difference;
  /// What the nodal masses match (InvariantSelection::describe: "m, s0, J0, diag(m_ff), S", …).
  std::string mass_model;
  double anisotropy = 0.0;
  /// Which rows of the matrices are the .frd's nodes, which are condensed or held.
  CalculixDofMap dof_map;
  /// max |K R| / (max|K| max|R|) over the rigid fields R at every row.
  double rigid_force = 0.0;
  double rigid_orthogonalization = 0.0;  ///< largest relative M-norm change of step 3
  std::vector<CalculixRigidMode> rigid_modes;
  std::vector<CalculixModeCheck> modes;  ///< in the order of the kept modes
  double max_difference = 0.0;           ///< max |ω_body/ω_ccx − 1|
  double frequency_tolerance = 0.0;
  bool self_check_passed = false;  ///< max_difference ≤ frequency_tolerance
  std::vector<std::string> notes;
};

/// Runs steps 1–7. `dat`: the eigenvalue tables of the run's .dat (nullptr: not checked);
/// when given, their count per step must equal the .frd's modes and their eigenvalues agree.
/// `deck`: the input deck (nullptr: none), needed when ccx expanded shells or beams
/// (calculix_dof_map.hpp).
/// Throws core::InputError naming the file (and line where one applies): bad selections,
/// inconsistent files, failed checks of steps 1–6 (not the self-check: see
/// self_check_passed).
CalculixImport import_calculix_modes(const CalculixModes& frd, const CalculixMatrices& matrices,
                                     const std::vector<CalculixEigenvalueTable>* dat,
                                     const CalculixImportOptions& options,
                                     const CalculixDeck* deck = nullptr);

}  // namespace flexref::scene
