#pragma once
/// \file structured_jacobian.hpp
/// The Jacobian J = ∂f/∂y of the quasi-velocity ODE form y' = f(t, y) (reference/ode_form.hpp),
/// for implicit solvers (CVODE BDF's Newton matrix I − γJ), built from the model's structure
/// instead of 1 + dim y right-hand-side evaluations:
///
/// - kinematic rows, analytic: ṗ = v (∂/∂v = I); θ̇ = ½ θ ⊗ (0, ω̄) with the θ of y,
///   ∂θ̇/∂θ = ½ [0 −ω̄ᵀ; ω̄ −ω̄̃], ∂θ̇/∂ω̄ = ½ Ḡ(θ)ᵀ (euler_parameters.hpp); q̇_f' = q̇_f (I);
/// - acceleration rows (v̇ = a, ω̄̇ = α̅, q̈_f) from the dynamics residual R(y, x) = 0 of each body
///   (Model::dynamics_residual, the unknown rows): dx = −M_UU⁻¹ (∂R/∂y) dy, with
///     ∂R/∂y = ∂R_inertia/∂y − ∂ℓ/∂y,
///   ∂R_inertia/∂y analytic (flexible bodies: flexible/inertia_jacobian.hpp — the modal blocks
///   K, D, m_ff and the rigid–modal coupling; rigid bodies: ∂(ω̄ × I ω̄)/∂ω̄ = −(Iω̄)~ + ω̄̃ I),
///   ℓ = [f_W; Aᵀ τ_Br_W; Q_f] the loads of every body (generic force elements have no
///   derivatives) by central differences — cheap, since an evaluation of the loads alone
///   costs O(elements + n), not the O(n²) of the inertia terms — and M_UU⁻¹ applied with the
///   structured factorization of flexible/mass_matrix_solve.hpp (one factorization per body,
///   n² per column);
/// - the integrals' rows (W_d' = dissipated power, the applied and drives' power, wear work),
///   by central differences of Model::integral_rates.
///
/// Rows and columns are those of y. The accelerations depend on θ only through θ̂ = θ/|θ|
/// (OdeForm::unpack normalizes), so their θ columns are taken in a body-frame rotation π̄
/// (θ̂ → θ̂ ⊗ exp_quaternion(π̄), A → A exp(π̄̃)) and mapped by ∂π̄/∂θ = 2 Ḡ(θ̂)/|θ| (Ḡ θ̂ = 0
/// removes the radial direction, which θ̂ does not see). Total cost O(n³) for the dense result
/// (2n + 13 columns of n² solves): 0.42 ms at n = 64 against 2.0 ms for the 2n + 14
/// right-hand sides of a difference-quotient Jacobian (bench/flexible_model_benchmark.cpp).
///
/// Exceptions from callbacks: a SUNDIALS callback must catch what evaluate() throws (as the
/// drivers' rhs callbacks do) and return −1.
///
/// For IDA (reference/dae_form.hpp) the same pieces apply: the DAE's dynamics rows are
/// Model::dynamics_residual (θ rows premultiplied by 2Ḡᵀ, ω̄ = 2Ḡ v_θ, α̅ = 2Ḡ v̇_θ), whose
/// derivatives with respect to the state at fixed accelerations are BodyScratch::dR (tangent
/// columns, tangent_columns()) after evaluate(), and with respect to the accelerations are M
/// (flexible/inertia_terms.hpp: M_rr, M_rf, m_ff); the chain rule through Ḡ(θ) v_θ is the
/// driver's to add.
///
/// Accuracy: exact to rounding but for the loads' share, which has the central-difference error
/// h²/6 |ℓ'''| + ε |ℓ| / h per column with h = ε^{1/3} max(1, |y_j|) (≈ 6e-6: ~1e-11
/// relative for loads smooth on the scale of the state). Loads that switch inside ±h (contact
/// onset) get a difference quotient across the switch, as with any difference Jacobian.
/// Tested against central differences of OdeForm::rhs on rigid, free flexible, pivot and
/// prescribed bodies, both models (tests/reference/structured_jacobian_test.cpp).
///
/// Use from CVODE (dense SUNMatrix, column-major, ldim = rows):
///
///     int jac(sunrealtype t, N_Vector y, N_Vector, SUNMatrix J, void* user, N_Vector,
///             N_Vector, N_Vector) {
///       auto& d = *static_cast<CvodeData*>(user);
///       d.jacobian->evaluate(core::LoadContext{t, d.t_segment}, N_VGetArrayPointer(y),
///                            SM_DATA_D(J), static_cast<int>(SM_ROWS_D(J)),
///                            d.jacobian_scratch);
///       return 0;
///     }
///     CVodeSetJacFn(cvode, jac);
///
/// evaluate() allocates nothing and may throw what the model's evaluation throws.
#include <Eigen/Core>
#include <vector>

#include "core/model.hpp"
#include "flexible/inertia_jacobian.hpp"
#include "flexible/inertia_terms.hpp"
#include "flexible/mass_matrix_solve.hpp"
#include "reference/ode_form.hpp"

namespace flexref::reference {

class StructuredJacobian {
 public:
  /// The form must outlive the Jacobian.
  explicit StructuredJacobian(const OdeForm& form);

  /// Per body: the structured factorization and the residual derivatives (sized once).
  struct BodyScratch {
    flexible::InertiaTerms terms;
    flexible::MassSolveScratch solve;
    flexible::InertiaJacobianScratch inertia;
    Eigen::MatrixXd dR_inertia;  ///< ∂R_inertia/∂[π̄, ω̄, q_f, q̇_f] ((6+n)×(6+2n))
    Eigen::MatrixXd dR;          ///< ∂R/∂(tangent state of the model) ((6+n)×T)
    Eigen::VectorXd x;           ///< the accelerations (a, α̅, q̈_f) at y
    Eigen::VectorXd load_plus, load_minus, column, dx;
  };
  struct Scratch {
    core::State state, perturbed;
    core::Workspace workspace;
    core::Accelerations accelerations;
    std::vector<BodyScratch> bodies;
    /// ∂(integral rates)/∂(tangent state): one row per tracked integral (W_d, W_a, W_drive, wear
    /// work per channel: Model::integral_rates), integral_count × T.
    Eigen::MatrixXd work_rows;
    std::vector<double> rates_plus, rates_minus;  ///< integral_rates at ±h
  };

  int size() const { return form_->size(); }
  /// Dimension T of the tangent state (θ (4) → π̄ (3) per attitude).
  int tangent_size() const { return tangent_size_; }
  Scratch make_scratch() const;

  /// Writes ∂f/∂y at (context.t, y) into the column-major array J with leading dimension
  /// ld ≥ size() (every entry of the size()×size() block is written).
  void evaluate(const core::LoadContext& context, const double* y, double* J, int ld,
                Scratch& scratch) const;
  /// The same into a size()×size() matrix.
  void evaluate(const core::LoadContext& context, const double* y, Eigen::Ref<Eigen::MatrixXd> J,
                Scratch& scratch) const;

  /// One column of the tangent state.
  struct TangentColumn {
    enum class Kind { kPosition, kRotation, kVelocity, kAngularVelocity, kMode, kModeRate };
    int body = 0;
    Kind kind = Kind::kPosition;
    int index = 0;    ///< component (0..2, or the mode)
    int y_index = 0;  ///< its column in y (kRotation: the θ block's first column)
  };
  const std::vector<TangentColumn>& tangent_columns() const { return columns_; }

 private:
  /// Adds ±h to one tangent component of `state` (θ̂ ⊗ exp(±h e_k)/… for a rotation).
  void perturb(const TangentColumn& column, double h, core::State& state) const;
  /// ℓ of every body into load_plus (plus = true) or load_minus at the loads in ws.
  void store_loads(const core::Workspace& ws, bool plus, Scratch& scratch) const;

  const OdeForm* form_;
  std::vector<TangentColumn> columns_;
  std::vector<int> first_column_;  ///< per body: its first tangent column (−1: none)
  int tangent_size_ = 0;
};

}  // namespace flexref::reference
