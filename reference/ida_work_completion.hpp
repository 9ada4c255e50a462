#pragma once
/// \file ida_work_completion.hpp
/// The sparse path's linear solver for IDA (reference/dae_coloured_jacobian.hpp): KLU on the
/// coloured Newton matrix G, whose rows of the works W hold their diagonal c_j alone, then each
/// work's correction completed with the state's. The works' rows Ẇ − P(y) read every state (a
/// dense row no column grouping separates), and nothing reads W, so G is block lower triangular:
///
///     [G_ss  0  ] [x_s]   [b_s]        x_s = G_ss⁻¹ b_s              (KLU)
///     [G_Ws c_j I] [x_W] = [b_W],       x_W = (b_W − G_Ws x_s) / c_j,
///
/// with G_Ws x_s by one directional difference of the residual at the Newton iterate (SUNDIALS'
/// idaLsDQJtimes: σ = 1/‖x_s‖_WRMS, [F(y + σ x_s, y' + c_j σ x_s) − F(y, y')]_W / σ). Without
/// it, a work's correction lags the state's by one iteration, and over a run the works drift by
/// the Newton tolerance per step (measured on slider_crank at rtol 1e-8: the energy balance 44×
/// further from a tight reference than with the dense difference quotients). One residual per
/// linear solve, for models that track work only.
///
/// IDA's residual callback hands each iterate to remember() (the last residual IDA evaluated is
/// at the iterate the solve corrects: the Jacobian's residuals do not pass through it).
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>

#include <vector>

#include "reference/dae_form.hpp"

namespace flexref::reference {

class IdaWorkCompletion {
 public:
  /// The form must outlive this and track work (work_index() ≥ 0).
  explicit IdaWorkCompletion(const DaeForm& form);

  /// The iterate IDA evaluated last: t, y, y', F (copies; allocates nothing).
  void remember(double t, double t_segment, const double* y, const double* yp, const double* r);
  /// The iteration matrix's c_j and error weights (set with each matrix).
  void set_matrix(double c_j, const double* ewt);
  /// x (the solution with the works' rows diagonal) → the full one; false when the
  /// residual was not finite. Allocates nothing.
  bool complete(double* x, DaeForm::Scratch& scratch);
  long residuals() const { return residuals_; }

 private:
  const DaeForm* form_;
  int first_ = 0, count_ = 0;  ///< the works' indices in y
  double t_ = 0.0, t_segment_ = 0.0, c_j_ = 1.0;
  std::vector<double> y_, yp_, r_, ewt_, y_moved_, yp_moved_, r_moved_;
  long residuals_ = 0;
};

/// A direct SUNLinearSolver: `klu` (not owned) then completion->complete (not owned; both
/// must outlive the solver, which is freed with SUNLinSolFree). scratch: the residual's.
SUNLinearSolver make_ida_work_completing_solver(SUNLinearSolver klu, IdaWorkCompletion& completion,
                                                DaeForm::Scratch& scratch, SUNContext context);

}  // namespace flexref::reference
