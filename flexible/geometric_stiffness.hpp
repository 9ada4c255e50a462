#pragma once
/// \file geometric_stiffness.hpp
/// Geometric (centrifugal) stiffening of a flexible body by first-order foreshortening
/// (docs/geometric_stiffening.md, equations GS-1 … GS-14).
///
/// The linear floating frame moves node k by Φ_k q_f only, so a beam spun about its root
/// *softens* (in-plane ω_i² − Ω²; docs/design/model.md, "Geometric stiffening"). A bent beam
/// shortens along its axis: node k also moves by the second-order displacement
///
///     w_k(q_f) = −½ e_k q_fᵀ D_k q_f,     D_k = ∫_root^k φ'ᵀ φ' ds   (n×n, symmetric)    (GS-1)
///
/// with e_k the unit axis direction at k and φ' the transverse slopes of the modes along the
/// path from the clamped root to k (Kane, Ryan and Banerjee 1987; OpenFAST ElastoDyn). flexref
/// adds to the kinetic energy of the linear model its part of second order in (q_f, q̇_f) that is
/// linear in w (GS-3). The equations of motion follow from that Lagrangian, so energy and
/// angular momentum stay exact invariants of the free body, and the modal rows gain
///
///     K_G = −Σ_k m_k (a_k · e_k) D_k = −Σ_c a0_c E_c − Σ_ab B_ab F_ab (GS-8)
///
/// for the inertial acceleration a_k = a0 + B x_k of the undeformed node (B = Ẇ + W², W = ω̄̃):
/// the modal geometric stiffness of the beam finite element under the axial force of that field.
/// Its centrifugal part Σ_ab (W²)_ab F_ab sits in Qv; its translational and angular acceleration
/// parts enter through the mass matrix (the coupling rows A ΔS(q_f) and ΔĪ_θf(q_f)). The data are
/// the twelve unit-load matrices
///
///     E_c  = Σ_k m_k e_k,c D_k            (unit uniform acceleration along c; c = x, y, z)
///     F_ab = Σ_k m_k e_k,a x_k,b D_k      (unit acceleration field x̄_b along a)
///
/// with x_k from the frame origin, computed once (flexible/beam_model.hpp for the built-in beam,
/// the modal-data file's [geometric_stiffness] for user modes: docs/modal_data.md), so every
/// evaluation costs O(n²) independently of the node count.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "flexible/geometric_stiffness_tpl.hpp"

namespace flexref::flexible {

/// The unit-load geometric stiffness matrices of one flexible body (plain data, about the frame
/// origin the node positions are measured from).
struct GeometricStiffness {
  std::array<Eigen::MatrixXd, 3> E;  ///< E_c (n×n, symmetric)
  std::array<Eigen::MatrixXd, 9> F;  ///< [3a+b]: F_ab (n×n, symmetric)

  int mode_count() const { return static_cast<int>(E[0].rows()); }

  /// Throws std::invalid_argument naming the first problem: a matrix not n×n, a non-finite
  /// entry, or one not symmetric to 1e-10 of its largest entry (refused, not symmetrized).
  /// `mode_count` is the body's n.
  void validate(int mode_count) const;

  /// The same data about the point p (positions x_k − p): F_ab − p_b E_a (GS-2).
  GeometricStiffness shifted(const Eigen::Vector3d& p) const;
};

/// What the evaluations read (GeometricInvariantsTpl, flexible/geometric_stiffness_tpl.hpp), in
/// double.
using GeometricInvariants = GeometricInvariantsTpl<double>;

/// Validates `data` against n modes and builds the invariants.
GeometricInvariants make_geometric_invariants(const GeometricStiffness& data, int mode_count);

using GeometricProducts = GeometricProductsTpl<double>;

GeometricProducts make_geometric_products(int mode_count);

/// O(n²), allocates nothing.
void compute_geometric_products(const GeometricInvariants& g,
                                const Eigen::Ref<const Eigen::VectorXd>& q_f,
                                const Eigen::Ref<const Eigen::VectorXd>& qd_f,
                                GeometricProducts& p);

/// Zero products (the LTE model's inertia at q_f = q̇_f = 0: no stiffening).
void set_zero_geometric_products(GeometricProducts& p);

using ForeshorteningTerms = ForeshorteningTermsTpl<double>;

/// x·M y by columns (no temporary).
double bilinear_form(const Eigen::MatrixXd& M, const Eigen::Ref<const Eigen::VectorXd>& x,
                     const Eigen::Ref<const Eigen::VectorXd>& y);

/// Δs(q_f) (GS-4) is part of first_moment_tpl (modal_invariants_tpl.hpp), in every precision.
/// ΔS(q_f) u = −[q_f·E_c u]_c (GS-5; u = q̇_f gives d(Δs)/dt).
Eigen::Vector3d foreshortening_first_moment_rate(const GeometricInvariants& g,
                                                 const Eigen::Ref<const Eigen::VectorXd>& q_f,
                                                 const Eigen::Ref<const Eigen::VectorXd>& u);
/// ΔĪ_θθ(q_f) = tr(ΔJ) I − ΔJ, ΔJ_ab = −½ q_f·(F_ab + F_ba) q_f (GS-4).
Eigen::Matrix3d foreshortening_inertia(const GeometricInvariants& g,
                                       const Eigen::Ref<const Eigen::VectorXd>& q_f);
/// ΔĪ_θf(q_f) u = −[q_f·Z_c u]_c (GS-5).
Eigen::Vector3d foreshortening_theta_f(const GeometricInvariants& g,
                                       const Eigen::Ref<const Eigen::VectorXd>& q_f,
                                       const Eigen::Ref<const Eigen::VectorXd>& u);

void foreshortening_terms(const Eigen::Ref<const Eigen::VectorXd>& q_f,
                          const Eigen::Ref<const Eigen::VectorXd>& qd_f, const GeometricProducts& p,
                          ForeshorteningTerms& f);

}  // namespace flexref::flexible
