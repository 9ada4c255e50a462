/// \file ida_solver.cpp
/// IDA (variable-order BDF for DAEs, fixed-leading-coefficient form) on the implicit
/// quasi-velocity form of reference/dae_form.hpp: M(θ̂, q) times the accelerations minus the
/// loads, never factorized — the residual path of the model (Model::dynamics_residual), where
/// CVODE, ARKODE and Odeint integrate its accelerations (docs/references.md, "IDA").
///
/// - Every component is differential and in the error test; the error weights are CVODE's
///   (error_weights.hpp). With ideal joints the form is the stabilized index-2 (GGL) system of
///   dae_form.hpp: the multipliers are algebraic (IDASetId) and out of the error test
///   (IDASetSuppressAlg), the other weights scaled by √(N/N_d) and the rotation's floored at
///   ErrorWeights::kIndex2Roundoff ε, and the Newton matrix is IDA's difference quotients
///   grouped by the bodies' coupling into a sparse matrix factored by KLU
///   (dae_coloured_jacobian.hpp; the works' corrections completed by ida_work_completion.hpp),
///   or with --newton-matrix dense IDA's own with a dense LU.
/// - BDF orders 1–5, or 1–2 (A-stable) where undamped modes oscillate far above every rate the
///   outputs show (choose_ida_method, reference/method_choice.hpp; --method bdf|bdf2 overrides).
/// - Newton iteration (choose_newton_jacobian): a flexible model's StructuredJacobian through
///   the structured Newton system (reference/ida_newton_solver.hpp); SolverOptions::jacobian
///   through P (c_j I − J) (reference/ode_jacobian.hpp) with a dense LU; coloured difference
///   quotients and KLU (ideal joints, choose_ida_newton_jacobian); or IDA's difference-quotient
///   Jacobian with a dense LU (rigid models).
/// - The iteration matrix is rebuilt whenever c_j = α/h changes (IDASetDeltaCjLSetup(0)),
///   measured on free_spin: with IDA's default reuse (until c_j changes by 25 %) the stale matrix
///   moved the step sequence and the error by up to 15× at the same rtol (1.7e-9 instead of
///   1.1e-10 rad at rtol 1e-12) for 1.3× the CPU time saved by fewer Jacobians.
/// - Where the rotation is weighted per unit step and IDA's Newton iteration cannot converge to
///   it (IDA_CONV_FAIL), IDA continues from its last step with SUNDIALS' weights and the run
///   says from when (method_reason). Measured on a parallelogram four-bar driven into its dead
///   point: the index-2 iteration's rounding grows with the inverse pivots of J M⁻¹ Jᵀ, and with
///   the share IDA stalled 1e-3 (rtol 1e-8) to 0.13 rad (rtol 1e-12) before the dead point, where
///   with SUNDIALS' weights it reached it (docs/references.md).
/// - θ is renormalized at every restart (load switch, contact event): between restarts |θ| is a
///   first integral and its drift by the local errors does not move the attitude θ̂.
/// - The segment loop (stops at load switches, restarts from consistent values at contact
///   events, outputs from IDA's own interpolating polynomial with tout = each output time) is
///   sundials_segment_driver.hpp.
/// - SolverOptions::max_steps is IDA's mxstep: the most steps taken to reach one output time.
#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "reference/dae_coloured_jacobian.hpp"
#include "reference/dae_form.hpp"
#include "reference/error_weights.hpp"
#include "reference/ida_callbacks.hpp"
#include "reference/ida_newton_solver.hpp"
#include "reference/ida_work_completion.hpp"
#include "reference/integral_weights.hpp"
#include "reference/method_choice.hpp"
#include "reference/ode_form.hpp"
#include "reference/ode_jacobian.hpp"
#include "reference/reference_solver.hpp"
#include "reference/step_clock.hpp"
#include "reference/structured_jacobian.hpp"
#include "reference/sundials_handle.hpp"
#include "reference/sundials_segment_driver.hpp"

namespace flexref::reference {
namespace {

namespace sun = sundials;
using namespace ida;  // IdaData and the callbacks (reference/ida_callbacks.hpp)

/// IDA on the DAE form, driven segment by segment by integrate_segments.
class IdaSegmentSolver final : public sun::SegmentSolver {
 public:
  /// `share_dropped_at`: set to the time IDA fell back to SUNDIALS' weights (else untouched).
  IdaSegmentSolver(const core::Model& model, const SolverOptions& options, int max_order,
                   NewtonJacobian newton, double span, bool rotation_per_step,
                   double* share_dropped_at)
      : model_(&model),
        share_dropped_at_(share_dropped_at),
        options_(options),
        max_order_(max_order),
        newton_kind_(newton),
        form_(model),
        ode_(model),
        weights_(form_.size(), options.rtol, options.absolute_tolerance(), span,
                 rotation_per_step ? rotation_blocks(form_) : std::vector<RotationBlock>{},
                 model.has_constraints() ? ErrorWeights::kIndex2Roundoff : ErrorWeights::kRoundoff),
        context_(sun::make_context()),
        y_(sun::make_vector(form_.size(), context_.get())),
        yp_(sun::make_vector(form_.size(), context_.get())),
        jacobian_(make_jacobian_matrix()),
        linear_solver_(make_linear_solver()),
        ida_(sun::check_created(IDACreate(context_.get()), "IDACreate")) {
    data_.form = &form_;
    data_.scratch = form_.make_scratch();
    // The joints' rounding in the rotation's floors (error_weights.hpp).
    if (model.has_constraints()) weights_.set_joint_rounding(model.joint_length_scale());
    // The integrals' error weights (reference/integral_weights.hpp): the worn depths and the
    // works, contiguous in y.
    data_.rtol = options.rtol;
    data_.atol = options.absolute_tolerance();
    // With ideal joints the works keep SUNDIALS' weights: the drive's power is the multipliers'
    // (F_cᵀ v), and the index-2 Newton iteration's rounding of λ (error_weights.hpp) in it
    // outgrows a step's share of the tolerance within a few thousand steps — IDA then fails
    // its corrector test on W_drive alone (IDA_CONV_FAIL at h ~ 1e-15 s on a driven
    // parallelogram, docs/references.md).
    const int works = form_.multiplier_count() > 0 ? 0 : form_.integral_count();
    data_.integrals = {form_.depth_index(), form_.depth_count() + works};
    data_.solver_memory = ida_.get();
    data_.steps_since_init = [](void* ida) {
      long steps = 0;
      return IDAGetNumSteps(ida, &steps) < 0 ? 0L : steps;
    };
    data_.error_weights = &weights_;
    data_.clock = &clock_;
    data_.ida = ida_.get();
    if (newton == NewtonJacobian::kStructured) {
      data_.structured = &*structured_;
      data_.structured_scratch = structured_->make_scratch();
      data_.newton = &*newton_;
    }
    if (newton == NewtonJacobian::kColoured) {
      data_.coloured = &*coloured_;
      data_.klu = klu_ ? klu_.get() : linear_solver_.get();
      if (completion_) data_.completion = &*completion_;
    }
    if (newton == NewtonJacobian::kUser) {
      const int n = form_.size();
      data_.jacobian = options.jacobian;
      data_.ode = &ode_;
      data_.ode_scratch = ode_.make_scratch();
      data_.ode_jacobian = Eigen::MatrixXd::Zero(n, n);
      data_.mass = Eigen::MatrixXd::Zero(n, n);
      data_.f = Eigen::VectorXd::Zero(n);
    }
  }

  void start_segment(const sun::Segment& segment, const core::State& state,
                     std::span<const double> integrals) override {
    data_.t_segment = segment.t_segment;
    segment_ = segment;
    // Consistent (y, y') on the new load branch: y' from the quasi-velocity accelerations.
    form_.initial_values(core::LoadContext{segment.start, segment.t_segment}, state,
                         sun::data(y_.get()), sun::data(yp_.get()));
    works_.start(integrals, sun::data(y_.get()));
    const int n = form_.size();
    if (form_.multiplier_count() > 0 && !initialized_) {
      double largest = 0.0;
      for (int j = form_.multiplier_index(); j < n; ++j) {
        largest = std::max(largest, std::abs(sun::data(y_.get())[j]));
      }
      multiplier_tolerance_ = kMultiplierTolerance * std::max(largest, 1.0);
    }
    if (!sun::all_finite(sun::data(y_.get()), n) || !sun::all_finite(sun::data(yp_.get()), n)) {
      throw sun::StartError("the loads are not finite at the initial state of the segment");
    }
    void* ida = ida_.get();
    if (!initialized_) {
      sun::check(IDAInit(ida, residual, segment.start, y_.get(), yp_.get()), "IDAInit");
      sun::check(IDASetUserData(ida, &data_), "IDASetUserData");
      sun::check(IDASetErrHandlerFn(ida, sun::record_error, &data_.log), "IDASetErrHandlerFn");
      if (form_.multiplier_count() > 0) {
        // The multipliers' absolute tolerance: the index-2 iteration matrix scales their Newton
        // corrections by 1/h (its smallest singular values fall like σ_min(Φ_q)²/c_j), so at the
        // state's own tolerance IDA's convergence test rejects every corrector from the first
        // step on (measured on andrews_squeezer: IDA_CONV_FAIL at t = 0 down to h = 1e-19;
        // 1e-3 of their size still failed at rtol 1e-12). They are out of the error test, and
        // with kMultiplierTolerance × their initial size out of the Newton test too: the state's
        // components decide convergence, as for an index-1 system (their weights × √(N/N_d):
        // error_weights.hpp).
        weights_.set_algebraic(form_.multiplier_index(), multiplier_tolerance_);
      }
      sun::check(IDAWFtolerances(ida, error_weights), "IDAWFtolerances");
      sun::check(IDASetLinearSolver(ida, linear_solver_.get(), jacobian_.get()),
                 "IDASetLinearSolver");
      if (newton_kind_ == NewtonJacobian::kUser) {
        sun::check(IDASetJacFn(ida, jacobian), "IDASetJacFn");
      } else if (newton_kind_ == NewtonJacobian::kStructured) {
        sun::check(IDASetJacFn(ida, structured_jacobian), "IDASetJacFn");
      } else if (newton_kind_ == NewtonJacobian::kColoured) {
        sun::check(IDASetJacFn(ida, coloured_jacobian), "IDASetJacFn");
      }
      sun::check(IDASetMaxOrd(ida, max_order_), "IDASetMaxOrd");
      sun::check(IDASetMaxNumSteps(ida, options_.max_steps), "IDASetMaxNumSteps");
      sun::check(IDASetDeltaCjLSetup(ida, 0.0), "IDASetDeltaCjLSetup");
      if (form_.multiplier_count() > 0) {
        // The joints' multipliers are algebraic and left out of the error test (index 2).
        const std::vector<double> ids = form_.differential_ids();
        sun::Vector id = sun::make_vector(form_.size(), context_.get());
        std::copy(ids.begin(), ids.end(), sun::data(id.get()));
        sun::check(IDASetId(ida, id.get()), "IDASetId");
        sun::check(IDASetSuppressAlg(ida, SUNTRUE), "IDASetSuppressAlg");
      }
      if (model_->has_constraints()) data_.tracker = model_->make_constraint_tracker();
      const int root_functions =
          model_->switching_function_count() + (model_->has_constraints() ? 1 : 0);
      if (root_functions > 0) {
        sun::check(IDARootInit(ida, root_functions, switching), "IDARootInit");
      }
      roots_.assign(static_cast<std::size_t>(root_functions), 0);
      initialized_ = true;
      clock_.start_run(segment.start);
    } else {
      sun::check(IDAReInit(ida, segment.start, y_.get(), yp_.get()), "IDAReInit");
      clock_.restart(segment.start);
    }
    sun::check(IDASetStopTime(ida, segment.end), "IDASetStopTime");
  }

  Advance advance(double tout, double /*next*/) override {
    Advance reached;
    for (;;) {
      int flag = IDASolve(ida_.get(), tout, &reached.t, y_.get(), yp_.get(), IDA_NORMAL);
      if (flag == IDA_CONV_FAIL && weights_.weighs_rotation()) {
        continue_without_share(reached.t);
        flag = IDASolve(ida_.get(), tout, &reached.t, y_.get(), yp_.get(), IDA_NORMAL);
      }
      sun::check(flag, "IDASolve");
      reached.root = flag == IDA_ROOT_RETURN;
      if (!reached.root) return on_physical_clock(reached);
      if (!model_->has_constraints()) return reached;
      // The joints' entry alone: the DAE takes the tracker's rows there and goes on (no event);
      // with a contact's root too, the driver's restart takes them.
      const int count = model_->switching_function_count();
      sun::check(IDAGetRootInfo(ida_.get(), roots_.data()), "IDAGetRootInfo");
      bool contact = false;
      for (int k = 0; k < count; ++k) contact = contact || roots_[static_cast<std::size_t>(k)] != 0;
      if (roots_[static_cast<std::size_t>(count)] != 0) {
        form_.set_active_rows(data_.tracker.rows);
        if (!contact) restart_at_root(reached.t, segment_);
      }
      if (contact) return reached;
      reached.root = false;
      if (!(reached.t < tout)) return on_physical_clock(reached);
    }
  }

  /// y_ from IDA's time t to the physical time t (step_clock.hpp): y(t + δ) ≈ y(t) + δ y'(t),
  /// with y' = yp_ (IDASolve returns it at t). Not at a root: the state stays where the
  /// switching function is zero (as in cvode_solver.cpp).
  Advance on_physical_clock(Advance reached) {
    record_steps(ida_.get(), clock_);
    const double offset = clock_.offset();
    if (offset != 0.0) N_VLinearSum(1.0, y_.get(), offset, yp_.get(), y_.get());
    return reached;
  }

  void restart_at_root(double t, const sun::Segment& segment) override {
    restart_from_state(t, segment.end);
  }

  void unpack(double t, core::State& state) const override {
    form_.unpack(t, sun::data(y_.get()), state);
  }
  void integrals(std::span<double> out) const override { works_.values(sun::data(y_.get()), out); }

  void add_counters(SolverStats& stats) const override {
    void* ida = ida_.get();
    long steps = 0, residuals = 0, jacobian_residuals = 0, jacobians = 0, error_fails = 0,
         convergence_fails = 0;
    sun::check(IDAGetNumSteps(ida, &steps), "IDAGetNumSteps");
    sun::check(IDAGetNumResEvals(ida, &residuals), "IDAGetNumResEvals");
    sun::check(IDAGetNumLinResEvals(ida, &jacobian_residuals), "IDAGetNumLinResEvals");
    sun::check(IDAGetNumJacEvals(ida, &jacobians), "IDAGetNumJacEvals");
    sun::check(IDAGetNumErrTestFails(ida, &error_fails), "IDAGetNumErrTestFails");
    sun::check(IDAGetNumNonlinSolvConvFails(ida, &convergence_fails),
               "IDAGetNumNonlinSolvConvFails");
    stats.steps += steps;
    stats.rhs_evaluations += residuals + jacobian_residuals;
    const long own = data_.coloured_residuals + (completion_ ? completion_->residuals() : 0L);
    stats.rhs_evaluations += own - coloured_counted_;
    coloured_counted_ = own;
    stats.jacobian_evaluations += jacobians;
    stats.error_test_failures += error_fails;
    stats.nonlinear_failures += convergence_fails;
    // A fallback's IDAReInit (continue_without_share) restarted IDA's counts.
    stats.steps += dropped_counters_.steps;
    stats.rhs_evaluations += dropped_counters_.rhs_evaluations;
    stats.jacobian_evaluations += dropped_counters_.jacobian_evaluations;
    stats.error_test_failures += dropped_counters_.error_test_failures;
    stats.nonlinear_failures += dropped_counters_.nonlinear_failures;
    dropped_counters_ = SolverStats{};
  }

  double current_time(double fallback) const override {
    double t = fallback;
    return IDAGetCurrentTime(ida_.get(), &t) < 0 ? fallback : t;
  }
  long current_steps() const override {
    long steps = 0;
    return (IDAGetNumSteps(ida_.get(), &steps) < 0 ? 0 : steps) + dropped_counters_.steps;
  }
  std::string failure_message(const std::string& what) const override {
    std::string message = sun::failure_message(what, data_, data_.failed_callback);
    if (model_->has_constraints() && initialized_) {
      // A corrector that fails with steps collapsing to nothing at a dead point: the state IDA
      // returned (its last step's) and the motion from it name the singular configuration.
      double t = 0.0;
      double h = 0.0;
      if (IDAGetCurrentTime(ida_.get(), &t) >= 0 && IDAGetLastStep(ida_.get(), &h) >= 0) {
        core::State state = model_->initial_state();
        form_.unpack(t, sun::data(y_.get()), state);
        const std::string ahead = model_->singular_configuration_ahead(t, state, 2.0 * h);
        if (!ahead.empty()) {
          message +=
              "; the mechanism is at a singular configuration, which no smaller step "
              "crosses: " +
              ahead;
        }
      }
    }
    return message;
  }

 private:
  /// The sparse matrix of the coloured path (its pattern and groups constructed here, before
  /// jacobian_ is sized by them) or a dense one.
  sun::Matrix make_jacobian_matrix() {
    if (newton_kind_ != NewtonJacobian::kColoured) {
      return sun::make_dense_matrix(form_.size(), context_.get());
    }
    coloured_.emplace(form_);
    return sun::Matrix(sun::check_created(
        SUNSparseMatrix(form_.size(), form_.size(), coloured_->nonzeros(), CSC_MAT, context_.get()),
        "SUNSparseMatrix"));
  }

  /// The structured Newton system (constructed here, before linear_solver_ refers to it), KLU
  /// for the coloured path, or a dense LU.
  sun::LinearSolver make_linear_solver() {
    if (newton_kind_ == NewtonJacobian::kColoured) {
      sun::LinearSolver klu(sun::check_created(
          SUNLinSol_KLU(y_.get(), jacobian_.get(), context_.get()), "SUNLinSol_KLU"));
      if (form_.work_index() < 0) return klu;
      // The works' corrections completed after KLU's (ida_work_completion.hpp).
      klu_ = std::move(klu);
      completion_.emplace(form_);
      return sun::LinearSolver(
          make_ida_work_completing_solver(klu_.get(), *completion_, data_.scratch, context_.get()));
    }
    if (newton_kind_ != NewtonJacobian::kStructured) {
      return sun::make_dense_linear_solver(y_.get(), jacobian_.get(), context_.get());
    }
    structured_.emplace(ode_);
    newton_.emplace(form_, ode_);
    return sun::LinearSolver(make_ida_newton_linear_solver(*newton_, context_.get()));
  }

  /// Restart from consistent values at the state in y_ (time t): θ back on the unit sphere.
  void restart_from_state(double t, double segment_end) {
    form_.unpack(t, sun::data(y_.get()), data_.scratch.state);
    works_.values(sun::data(y_.get()), integrals_at_event_);
    form_.initial_values(core::LoadContext{t, data_.t_segment}, data_.scratch.state,
                         sun::data(y_.get()), sun::data(yp_.get()));
    works_.start(integrals_at_event_, sun::data(y_.get()));
    sun::check(IDAReInit(ida_.get(), t, y_.get(), yp_.get()), "IDAReInit");
    clock_.restart(t);
    sun::check(IDASetStopTime(ida_.get(), segment_end), "IDASetStopTime");
  }

  /// IDA stopped with IDA_CONV_FAIL at t, its last step: restart there with SUNDIALS' weights.
  /// The state is IDA's at t moved to the physical time t (step_clock.hpp).
  void continue_without_share(double t) {
    void* ida = ida_.get();
    sun::check(IDAGetDky(ida, t, 0, y_.get()), "IDAGetDky");
    sun::check(IDAGetDky(ida, t, 1, yp_.get()), "IDAGetDky");
    record_steps(ida, clock_);
    const double offset = clock_.offset();
    if (offset != 0.0) N_VLinearSum(1.0, y_.get(), offset, yp_.get(), y_.get());
    SolverStats before;  // add_counters adds (and clears) dropped_counters_ too
    add_counters(before);
    dropped_counters_ = before;
    weights_.drop_rotation_share();
    data_.log.message.clear();
    *share_dropped_at_ = t;
    restart_from_state(t, segment_.end);
    // Near a singular configuration, what made the share fail can make IDA creep on with steps
    // below the time's resolution (measured: 2.7e-19 s steps at t = 1.56 s near a four-bar's
    // dead point, every other one a convergence failure): a step below kMinStepUlps ulp of the
    // time cannot advance it, and IDA stops there.
    const double time_scale = std::max(std::abs(t), std::abs(segment_.end));
    sun::check(
        IDASetMinStep(ida, kMinStepUlps * std::numeric_limits<double>::epsilon() * time_scale),
        "IDASetMinStep");
  }

  const core::Model* model_;
  sun::Segment segment_;    ///< the segment being integrated (a row switch restarts in it)
  std::vector<int> roots_;  ///< IDAGetRootInfo's flags
  double* share_dropped_at_;
  /// IDA's counters before a fallback's IDAReInit reset them (added in add_counters).
  mutable SolverStats dropped_counters_;
  /// The coloured path's residuals already added to the stats (add_counters).
  mutable long coloured_counted_ = 0;
  SolverOptions options_;
  int max_order_;
  NewtonJacobian newton_kind_;
  DaeForm form_;
  OdeForm ode_;
  ErrorWeights weights_;
  StepClock clock_;
  /// W_d and the extra integrals carried across a restart at an event (sized once).
  /// The works in y as increments since the last (re)start (reference/integral_weights.hpp).
  IntegralBase works_{{form_.work_index(), form_.integral_count()}};
  std::vector<double> integrals_at_event_ =
      std::vector<double>(static_cast<std::size_t>(form_.integral_count()));
  std::optional<StructuredJacobian> structured_;
  std::optional<IdaNewtonSystem> newton_;
  std::optional<DaeColouredJacobian> coloured_;
  std::optional<IdaWorkCompletion> completion_;
  IdaData data_;
  bool initialized_ = false;
  double multiplier_tolerance_ = 0.0;
  sun::Context context_;
  sun::Vector y_, yp_;
  sun::Matrix jacobian_;
  sun::LinearSolver klu_;  ///< KLU under the works' completion (freed after it)
  sun::LinearSolver linear_solver_;
  // Declared last so that it is freed first (as in SUNDIALS' examples).
  sun::IdaMemory ida_;
};

}  // namespace

ReferenceRun solve_ida(const core::Model& model, const std::vector<double>& output_times,
                       const SolverOptions& options) {
  if (options.cvode_method == CvodeMethod::kAdams) {
    throw std::invalid_argument("IDA has no Adams method (--method bdf or bdf2)");
  }
  CvodeMethodChoice choice{options.cvode_method, "chosen with --method"};
  if (options.cvode_method == CvodeMethod::kAuto) {
    choice = choose_ida_method(model, mean_output_spacing(output_times));
  }
  const int max_order = choice.method == CvodeMethod::kBdf2 ? 2 : 5;
  const NewtonJacobian newton = choose_ida_newton_jacobian(model, options);
  const double span = output_times.empty() ? 0.0 : output_times.back() - output_times.front();
  const bool per_step =
      rotation_weights_per_step(summarize_stiffness(model, mean_output_spacing(output_times)));
  double share_dropped_at = std::numeric_limits<double>::quiet_NaN();
  ReferenceRun run = sun::integrate_segments(model, output_times, options, "ida", [&] {
    return std::make_unique<IdaSegmentSolver>(model, options, max_order, newton, span, per_step,
                                              &share_dropped_at);
  });
  run.method = to_string(choice.method);
  run.method_reason = choice.reason;
  if (!std::isnan(share_dropped_at)) {
    std::ostringstream note;
    note.precision(6);
    note << "; SUNDIALS' error weights from t = " << share_dropped_at
         << " s (the Newton iteration did not converge to the rotation's per-step share)";
    run.method_reason += note.str();
  }
  run.jacobian = to_string(newton);
  return run;
}

}  // namespace flexref::reference
