#pragma once
/// \file modal_data.hpp
/// Modal data of a flexible body (docs/design/model.md, "Bodies and inertia invariants"),
/// independent of where it came from (the built-in beam model, flexible/beam_model.hpp, or a user's
/// file, scene/modal_data_reader.hpp), and the inertia invariants computed once from it.
///
/// The body is a set of lumped material points ("nodes") k = 1..N with mass m_k > 0 and
/// undeformed position x_k (body frame, from the frame origin Bo); the displacement of node k is
/// Φ_k q_f with the mode-shape rows Φ_k ∈ R^{3×n}. Only translational masses: the rotary inertia
/// of the material around each point is neglected (as in Shabana's lumped-mass floating frame).
/// Every body integral ∫ρ(·)dV is the sum Σ_k m_k(·). See docs/modal_data.md.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "flexible/geometric_stiffness.hpp"
#include "flexible/modal_invariants_tpl.hpp"

namespace flexref::flexible {

/// Relative threshold on the Cholesky pivots of m_ff below which a mode counts as a linear
/// combination of the modes before it (see first_dependent_mode).
inline constexpr double kDependentModeTolerance = 1e-10;

/// Modal data of one flexible body. Plain data: fill it, then call validate().
struct ModalData {
  /// m_k, kg (N entries).
  Eigen::VectorXd mass;
  /// x_k: undeformed position of node k from the frame origin Bo, body frame, m (3×N).
  Eigen::Matrix3Xd p_BoNode_B;
  /// Φ (3N×n): rows 3k, 3k+1, 3k+2 are Φ_k, the body-frame displacement of node k per unit
  /// modal coordinate (m per unit q_f).
  Eigen::MatrixXd phi;
  /// K_i, modal stiffness (n entries, ≥ 0); the modal stiffness matrix is diag(K).
  Eigen::VectorXd stiffness;
  /// ζ_i, modal damping ratios (n entries, ≥ 0; zeros for an undamped body).
  Eigen::VectorXd damping_ratio;
  /// Empty, or one unique non-empty name per node.
  std::vector<std::string> node_names;
  /// Empty, or one label per mode (e.g. "bending-xy-1").
  std::vector<std::string> mode_names;
  /// Geometric stiffening (flexible/geometric_stiffness.hpp): the unit-load matrices about Bo,
  /// or none (the linear floating frame, no stiffening).
  std::optional<GeometricStiffness> geometric;

  int node_count() const { return static_cast<int>(mass.size()); }
  int mode_count() const { return static_cast<int>(phi.cols()); }
  /// Φ_k (3×n).
  auto mode_rows(int k) const { return phi.middleRows<3>(3 * static_cast<Eigen::Index>(k)); }

  /// Throws std::invalid_argument naming the first problem: inconsistent sizes, no node,
  /// non-positive or non-finite nodal mass, non-finite position or mode shape, negative or
  /// non-finite stiffness or damping ratio, empty or duplicate node names, and a modal mass
  /// matrix m_ff = Σ m_k Φ_kᵀ Φ_k that is not positive definite (a mode without displacement,
  /// or one that is a linear combination of others; see first_dependent_mode).
  void validate() const;
};

/// m_ff = Σ_k m_k Φ_kᵀ Φ_k (n×n), by the direct nodal sum. Symmetric by construction.
Eigen::MatrixXd modal_mass_matrix(const ModalData& data);

/// Index (from 0) of the first mode that is, in the mass-weighted sense, a linear combination
/// of the modes before it, or −1 when m_ff is positive definite. Cholesky without pivoting:
/// the pivot d_i = m_ii − Σ_{j<i} l_ij² is the squared mass-norm distance of mode i from the
/// span of modes 0..i−1, so d_i ≤ tolerance · m_ii means that mode i lies within an angle
/// √tolerance of that span (d_i = m_ii = 0: a mode with no displacement at any node).
int first_dependent_mode(const Eigen::MatrixXd& m_ff, double tolerance = kDependentModeTolerance);

/// Natural frequencies ω (rad/s, ascending) of the modal coordinates with the frame held
/// fixed: the generalized eigenvalues of diag(K) φ = ω² m_ff φ. They equal √(K_i/μ_i) when
/// m_ff is diagonal (μ_i = m_ff,ii). `flexref check` prints them; 2/ω_max bounds the
/// step of central differences.
Eigen::VectorXd natural_frequencies(const ModalData& data);

/// Diagonal of the modal damping matrix D (docs/design/model.md): d_i = 2 ζ_i ω_i μ_i with
/// μ_i = m_ff,ii and ω_i = √(K_i/μ_i), i.e. d_i = 2 ζ_i √(K_i μ_i).
Eigen::VectorXd modal_damping(const ModalData& data);

/// The inertia invariants of the nodes (Shabana's inertia shape integrals), computed once so
/// that every state-dependent inertia quantity costs O(n²), independent of N; in double
/// (flexible/modal_invariants_tpl.hpp defines them for any scalar).
using ModalInvariants = ModalInvariantsTpl<double>;

/// Validates the data (ModalData::validate) and computes its invariants.
ModalInvariants make_modal_invariants(const ModalData& data);

/// \f[ s_t(q_f) = s_0 + S q_f = \textstyle\sum_k m_k \bar u_k \f]  (first moment about Bo).
/// This and the two inertia functions below include the foreshortening terms Δs, ΔĪ_θθ, ΔĪ_θf
/// when the invariants carry geometric stiffening (flexible/geometric_stiffness.hpp).
Eigen::Vector3d first_moment(const ModalInvariants& invariants,
                             const Eigen::Ref<const Eigen::VectorXd>& q_f);

/// d s_t/dt = S q̇_f (+ ΔS(q_f) q̇_f with geometric stiffening). O(n²), allocates nothing.
Eigen::Vector3d first_moment_rate(const ModalInvariants& invariants,
                                  const Eigen::Ref<const Eigen::VectorXd>& q_f,
                                  const Eigen::Ref<const Eigen::VectorXd>& qd_f);

/// \f[ \bar I_{\theta\theta}(q_f) = \textstyle\sum_k m_k \tilde{\bar u}_k^T \tilde{\bar u}_k
///     = \mathrm{tr}(J)\, I - J,\quad J = J_0 + L + L^T + Q,\;
///     L_{ab} = \textstyle\sum_k m_k x_{k,a} \Phi_{k,b} q_f,\;
///     Q_{ab} = q_f^T \bigl(\textstyle\sum_k m_k \Phi_{k,a}^T \Phi_{k,b}\bigr) q_f \f]
/// Inertia about Bo of the deformed body, body frame. O(n²), allocates nothing.
Eigen::Matrix3d inertia_theta_theta(const ModalInvariants& invariants,
                                    const Eigen::Ref<const Eigen::VectorXd>& q_f);

/// \f[ \bar I_{\theta f}(q_f) = \textstyle\sum_k m_k \tilde{\bar u}_k \Phi_k
///     = \bar I_{\theta f,0} + \bigl[q_f^T G_a\bigr]_{a=0,1,2} \f]
/// with G_a = phi_cross_phi[a]. Writes the 3×n result into `out` (e.g. a block of a mass
/// matrix); O(n²), allocates nothing. Throws std::invalid_argument on wrong sizes.
void inertia_theta_f(const ModalInvariants& invariants,
                     const Eigen::Ref<const Eigen::VectorXd>& q_f, Eigen::Ref<Eigen::MatrixXd> out);
/// Same, returning a new matrix.
Eigen::Matrix3Xd inertia_theta_f(const ModalInvariants& invariants,
                                 const Eigen::Ref<const Eigen::VectorXd>& q_f);

/// The same three quantities by direct sums over the nodes (O(N n)): the definitions the
/// invariant-based evaluations are tested against.
Eigen::Vector3d first_moment_direct(const ModalData& data,
                                    const Eigen::Ref<const Eigen::VectorXd>& q_f);
Eigen::Matrix3d inertia_theta_theta_direct(const ModalData& data,
                                           const Eigen::Ref<const Eigen::VectorXd>& q_f);
Eigen::Matrix3Xd inertia_theta_f_direct(const ModalData& data,
                                        const Eigen::Ref<const Eigen::VectorXd>& q_f);

}  // namespace flexref::flexible
