/// \file cvode_solver.cpp
/// CVODE on the quasi-velocity ODE form of docs/design/model.md (reference/ode_form.hpp), Adams
/// or BDF (docs/references.md, "CVODE: Adams or BDF"):
///
/// - **Adams** (Adams–Moulton, orders 1–12) where the model has no stiff element. No projection:
///   CVODE 6.4 supports one only with BDF (CVodeSetProjFn returns CV_ILL_INPUT for CV_ADAMS,
///   "Projection is only supported with BDF methods", cvode_proj.c), and none is needed: |θ| is
///   a first integral of θ̇ = ½ θ ⊗ (0, ω̄) and the form is homogeneous in θ, so a drift of |θ|
///   by the local errors leaves the attitude θ̂ alone (the driver renormalizes at restarts).
/// - **BDF** (orders 1–5) with Newton iteration and a projection (CVodeSetProjFn) that puts the
///   Euler parameters back on the unit sphere after every step, where contacts, joints or stiff
///   modes make the model stiff (reference/method_choice.hpp picks; --method overrides).
/// - **BDF orders 1–2** (CVodeSetMaxOrd(2), A-stable; with the projection) where undamped modes
///   oscillate far above every rate the outputs show (reference/method_choice.hpp).
/// Adams on a model with ideal joints iterates its corrector by fixed-point iteration with
/// Anderson acceleration (CVODE's recommendation for non-stiff problems, user guide 2.1): the
/// difference-quotient Jacobian of the constrained right-hand side costs one constrained solve
/// per state component (91 on Andrews' squeezer: 13 Jacobians were 1183 of 2099 evaluations,
/// 103 ms at rtol 1e-10; 41 ms with fixed-point iteration, docs/references.md). Everything else
/// uses Newton iteration. The Newton systems (choose_newton_jacobian): a flexible model's
/// StructuredJacobian (reference/structured_jacobian.hpp) with the structured Newton solve
/// (reference/newton_linear_solver.hpp); SolverOptions::jacobian (reference/ode_jacobian.hpp)
/// with a dense LU; or CVODE's difference-quotient Jacobian with a dense LU (rigid models).
///
/// The segment loop (stops at load switches, restarts at contact events, outputs from CVODE's
/// own interpolation with tout = each output time) is sundials_segment_driver.hpp.
/// SolverOptions::max_steps is CVODE's mxstep: the most steps taken to reach one output time.
#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <cvode/cvode_proj.h>

#include <algorithm>
#include <exception>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "reference/cvode_support.hpp"
#include "reference/error_weights.hpp"
#include "reference/integral_weights.hpp"
#include "reference/method_choice.hpp"
#include "reference/newton_linear_solver.hpp"
#include "reference/ode_form.hpp"
#include "reference/reference_solver.hpp"
#include "reference/step_clock.hpp"
#include "reference/structured_jacobian.hpp"
#include "reference/sundials_handle.hpp"
#include "reference/sundials_ode_callbacks.hpp"
#include "reference/sundials_segment_driver.hpp"

namespace flexref::reference {
namespace {

namespace sun = sundials;

/// CVEwtFn: CVODE calls it before every step (error_weights.hpp, then the integrals' share of
/// their stretch, integral_weights.hpp), with the state of the step it accepted last; it also
/// records the step just taken on the clock and there moves the joints' tracker where
/// evaluations chose rows of their own (sun::accept_step). Allocates nothing but there.
int error_weights(N_Vector y, N_Vector ewt, void* user_data) {
  auto& d = *static_cast<sun::OdeCallbackData*>(user_data);
  try {
    if (d.rows_chosen) {
      double t = 0.0;
      sun::check(CVodeGetCurrentTime(d.cvode, &t), "CVodeGetCurrentTime");
      sun::accept_step(d, t, sun::data(y));
    }
    record_cvode_steps(d.cvode, *d.clock);
    sun::step_error_weights(d, y, ewt);
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;
  }
  return 0;
}

/// The rotation blocks of the ODE form's bodies (θ and ω̄ offsets in y).
std::vector<RotationBlock> rotation_blocks(const OdeForm& form) {
  std::vector<RotationBlock> blocks;
  for (const OdeForm::Block& k : form.blocks()) {
    if (k.theta >= 0) blocks.push_back({k.theta, k.w, k.p, k.v});
  }
  return blocks;
}

/// True where the corrector iterates by fixed-point iteration instead of Newton: Adams (chosen
/// where nothing is stiff) on a model with ideal joints (see the file's comment).
bool uses_fixed_point(const core::Model& model, CvodeMethod method) {
  return method == CvodeMethod::kAdams && model.has_constraints();
}

/// CVODE on the ODE form, driven segment by segment by integrate_segments.
class CvodeSegmentSolver final : public sun::SegmentSolver {
 public:
  /// `stabilization`: Baumgarte's rate of the ODE form (Adams on ideal joints; 0 otherwise).
  CvodeSegmentSolver(const core::Model& model, const SolverOptions& options, CvodeMethod method,
                     NewtonJacobian newton, double stabilization, double span,
                     bool rotation_per_step)
      : model_(&model),
        options_(options),
        method_(method),
        newton_(newton),
        form_(model, stabilization),
        weights_(form_.size(), options.rtol, options.absolute_tolerance(), span,
                 rotation_per_step ? rotation_blocks(form_) : std::vector<RotationBlock>{}),
        context_(sun::make_context()),
        y_(sun::make_vector(form_.size(), context_.get())),
        ydot_(sun::make_vector(form_.size(), context_.get())),
        jacobian_(sun::make_dense_matrix(form_.size(), context_.get())),
        linear_solver_(
            newton == NewtonJacobian::kStructured
                ? sun::LinearSolver(make_newton_linear_solver(form_, context_.get()))
                : sun::make_dense_linear_solver(y_.get(), jacobian_.get(), context_.get())),
        cvode_(sun::check_created(
            CVodeCreate(method == CvodeMethod::kAdams ? CV_ADAMS : CV_BDF, context_.get()),
            "CVodeCreate")) {
    if (uses_fixed_point(model, method)) {
      // Anderson acceleration over one earlier iterate: heavy_top_spherical at rtol 1e-10 took
      // 13 ms with it, 19 ms without (more convergence failures, more steps); deeper histories
      // changed nothing on Andrews' squeezer.
      fixed_point_ = sun::make_fixed_point_solver(y_.get(), 1, context_.get());
    }
    data_.form = &form_;
    sun::bind_scratch(data_);
    // The joints' rounding in the rotation's floors (error_weights.hpp).
    if (model.has_constraints()) weights_.set_joint_rounding(model.joint_length_scale());
    // The integrals' error weights (reference/integral_weights.hpp): the worn depths and the
    // works, contiguous in y.
    data_.rtol = options.rtol;
    data_.atol = options.absolute_tolerance();
    data_.integrals = {form_.depth_index(), form_.depth_count() + form_.integral_count()};
    data_.solver_memory = cvode_.get();
    data_.steps_since_init = cvode_steps;
    if (model.has_constraints()) data_.projected.resize(static_cast<std::size_t>(form_.size()));
    data_.jacobian = options.jacobian;
    data_.error_weights = &weights_;
    data_.clock = &clock_;
    data_.cvode = cvode_.get();
    if (newton == NewtonJacobian::kStructured) {
      structured_.emplace(form_);
      data_.structured = &*structured_;
      data_.structured_scratch = structured_->make_scratch();
    }
  }

  void start_segment(const sun::Segment& segment, const core::State& state,
                     std::span<const double> integrals) override {
    data_.t_segment = segment.t_segment;
    before_switch_ = SolverStats{};
    form_.pack(state, sun::data(y_.get()));
    // Ideal joints: every segment starts on the constraint manifold, where the joints' tracker
    // moves.
    form_.project(segment.start, sun::data(y_.get()), data_.scratch);
    sun::accept_tracker(data_, segment.start, sun::data(y_.get()));
    works_.start(integrals, sun::data(y_.get()));
    void* cvode = cvode_.get();
    if (!initialized_) {
      sun::check(CVodeInit(cvode, sun::ode_rhs, segment.start, y_.get()), "CVodeInit");
      sun::check(CVodeSetUserData(cvode, &data_), "CVodeSetUserData");
      sun::check(CVodeSetErrHandlerFn(cvode, sun::record_error, &data_.log),
                 "CVodeSetErrHandlerFn");
      sun::check(CVodeWFtolerances(cvode, error_weights), "CVodeWFtolerances");
      if (iterates_fixed_point()) {
        sun::check(CVodeSetNonlinearSolver(cvode, fixed_point_.get()), "CVodeSetNonlinearSolver");
      } else {
        attach_newton(cvode);
      }
      if (method_ != CvodeMethod::kAdams) {
        // BDF projects after each step: θ onto the unit sphere, and with ideal joints the
        // state onto Φ = 0, J v + Φ_t = 0 (docs/joints.md).
        sun::check(CVodeSetProjFn(cvode, model_->has_constraints() ? sun::project_constraints
                                                                   : sun::project_euler_parameters),
                   "CVodeSetProjFn");
      }
      if (method_ == CvodeMethod::kBdf2) sun::check(CVodeSetMaxOrd(cvode, 2), "CVodeSetMaxOrd");
      sun::check(CVodeSetMaxNumSteps(cvode, iterates_fixed_point()
                                                ? std::min(options_.max_steps, kStiffnessWindow)
                                                : options_.max_steps),
                 "CVodeSetMaxNumSteps");
      if (model_->switching_function_count() > 0) {
        sun::check(CVodeRootInit(cvode, model_->switching_function_count(), sun::ode_switching),
                   "CVodeRootInit");
      }
      initialized_ = true;
      clock_.start_run(segment.start);
    } else {
      sun::check(CVodeReInit(cvode, segment.start, y_.get()), "CVodeReInit");
      clock_.restart(segment.start);
    }
    sun::check(CVodeSetStopTime(cvode, segment.end), "CVodeSetStopTime");
    segment_end_ = segment.end;
    // The first step is taken towards the segment end: CVODE sizes it from the distance to
    // the first tout, which would let the output grid steer the steps (an output 1e-7 after
    // a switch made the run take 360 steps instead of 200 and moved the state by 1e-8 at
    // rtol 1e-10). After this, outputs are interpolated or stepped to as usual, and the
    // solution does not depend on the output times.
    // (Not with switching functions: a root in that step would be returned before the
    // outputs that precede it.)
    if (model_->switching_function_count() == 0) {
      double t_internal = segment.start;
      sun::check(CVode(cvode, segment.end, y_.get(), &t_internal, CV_ONE_STEP), "CVode");
    }
  }

  Advance advance(double tout, double /*next*/) override {
    Advance reached;
    int flag = 0;
    if (!iterates_fixed_point()) {
      flag = CVode(cvode_.get(), tout, y_.get(), &reached.t, CV_NORMAL);
    } else {
      // Fixed-point iteration in windows, Newton where it stalls (cvode_support.hpp).
      flag = advance_fixed_point(cvode_.get(), tout, y_.get(), reached.t, options_.max_steps,
                                 [this](double t) { switch_to_newton(t); });
    }
    sun::check(flag, "CVode");
    reached.root = flag == CV_ROOT_RETURN;
    // At a root the state stays where the switching function is zero (moved, the restart could
    // find the same root again); the clock restarts there, and the time offset (≲ 1e-12 s on
    // scenes with contacts, whose runs take few steps between events) is not carried over.
    if (!reached.root) to_physical_time(reached.t);
    return reached;
  }

  /// Moves y_, CVODE's solution at its time t, to the physical time t (cvode_support.hpp).
  void to_physical_time(double t) {
    reference::to_physical_time(cvode_.get(), clock_, t, y_.get(), ydot_.get());
  }

  /// True while the corrector iterates by fixed-point iteration (until a switch to Newton).
  bool iterates_fixed_point() const { return fixed_point_ && !newton_solver_; }

  /// Newton iteration: CVODE's Newton solver on the chosen linear solver and Jacobian.
  void attach_newton(void* cvode) {
    sun::check(CVodeSetLinearSolver(cvode, linear_solver_.get(), jacobian_.get()),
               "CVodeSetLinearSolver");
    if (newton_ == NewtonJacobian::kUser) {
      sun::check(CVodeSetJacFn(cvode, sun::ode_jacobian), "CVodeSetJacFn");
    } else if (newton_ == NewtonJacobian::kStructured) {
      sun::check(CVodeSetJacFn(cvode, sun::structured_ode_jacobian), "CVodeSetJacFn");
    }
  }

  /// From fixed-point to Newton iteration at t (advance), restarting from the state there.
  void switch_to_newton(double t) {
    void* cvode = cvode_.get();
    to_physical_time(t);
    SolverStats so_far;
    add_counters(so_far);  // CVodeReInit below starts CVODE's counters again
    before_switch_ = so_far;
    newton_solver_ = sun::make_newton_solver(y_.get(), context_.get());
    sun::check(CVodeSetNonlinearSolver(cvode, newton_solver_.get()), "CVodeSetNonlinearSolver");
    attach_newton(cvode);
    works_.rebase(sun::data(y_.get()));
    restart_with_newton(cvode, t, y_.get(), options_.max_steps, segment_end_, clock_);
  }

  void restart_at_root(double t, const sun::Segment& segment) override {
    before_switch_ = SolverStats{};  // added to the run's by the driver before the restart
    // A new order-1 step sequence from the solution at the event; θ back on the sphere (BDF's
    // projection keeps it there already).
    if (method_ == CvodeMethod::kAdams || model_->has_constraints()) {
      form_.project(t, sun::data(y_.get()), data_.scratch);
    }
    sun::accept_tracker(data_, t, sun::data(y_.get()));
    works_.rebase(sun::data(y_.get()));
    sun::check(CVodeReInit(cvode_.get(), t, y_.get()), "CVodeReInit");
    clock_.restart(t);
    sun::check(CVodeSetStopTime(cvode_.get(), segment.end), "CVodeSetStopTime");
    segment_end_ = segment.end;
  }

  void unpack(double t, core::State& state) const override {
    form_.unpack(t, sun::data(y_.get()), state);
  }
  void accept_output(double t, const core::State& state) override {
    sun::accept_output(data_, t, state);
  }
  void integrals(std::span<double> out) const override { works_.values(sun::data(y_.get()), out); }

  void add_counters(SolverStats& stats) const override {
    add_cvode_counters(cvode_.get(), !iterates_fixed_point(), before_switch_, stats);
  }

  double current_time(double fallback) const override {
    return cvode_current_time(cvode_.get(), fallback);
  }
  long current_steps() const override { return cvode_steps(cvode_.get()) + before_switch_.steps; }
  std::string failure_message(const std::string& what) const override {
    return sun::failure_message(what, data_, "right-hand side");
  }

 private:
  const core::Model* model_;
  SolverOptions options_;
  CvodeMethod method_;
  NewtonJacobian newton_;
  OdeForm form_;
  ErrorWeights weights_;
  StepClock clock_;
  std::optional<StructuredJacobian> structured_;
  /// The works in y as increments since the last (re)start (reference/integral_weights.hpp).
  IntegralBase works_{{form_.work_index(), form_.integral_count()}};
  sun::OdeCallbackData data_;
  bool initialized_ = false;
  sun::Context context_;
  sun::Vector y_;
  sun::Vector ydot_;  ///< ẏ at an output (to_physical_time)
  sun::Matrix jacobian_;
  sun::LinearSolver linear_solver_;
  sun::NonlinearSolver fixed_point_;    ///< set where uses_fixed_point (else CVODE's Newton)
  sun::NonlinearSolver newton_solver_;  ///< Newton after a switch from fixed-point iteration
  /// The segment's counters up to a switch to Newton (add_counters adds them to CVODE's).
  SolverStats before_switch_;
  double segment_end_ = 0.0;
  // Declared last so that it is freed first (as in SUNDIALS' examples).
  sun::CvodeMemory cvode_;
};

}  // namespace

ReferenceRun solve_cvode(const core::Model& model, const std::vector<double>& output_times,
                         const SolverOptions& options) {
  // One spectrum for the method, Baumgarte's rate and the rotation's weights (each summary is
  // a difference-quotient Jacobian and its eigenvalues: 8 % of Andrews' reference at rtol 1e-10
  // when it was taken twice).
  const double spacing = mean_output_spacing(output_times);
  const StiffnessSummary summary = summarize_stiffness(model, spacing);
  CvodeMethodChoice choice{options.cvode_method, "chosen with --method"};
  if (options.cvode_method == CvodeMethod::kAuto) choice = choose_cvode_method(summary);
  const NewtonJacobian newton = choose_newton_jacobian(model, options);
  // Adams cannot project (CVODE 6.4): the joints' drift is damped instead (Baumgarte).
  const double stabilization = choice.method == CvodeMethod::kAdams
                                   ? constraint_stabilization_rate(model, summary, spacing)
                                   : 0.0;
  const double span = output_times.empty() ? 0.0 : output_times.back() - output_times.front();
  // Adams is chosen exactly where the rotation is weighted per unit step; a method given with
  // --method leaves the model to decide.
  const bool per_step = options.cvode_method == CvodeMethod::kAuto
                            ? choice.method == CvodeMethod::kAdams
                            : rotation_weights_per_step(summary);
  ReferenceRun run = sun::integrate_segments(model, output_times, options, "cvode", [&] {
    return std::make_unique<CvodeSegmentSolver>(model, options, choice.method, newton,
                                                stabilization, span, per_step);
  });
  run.method = to_string(choice.method);
  run.method_reason = choice.reason;
  run.jacobian = uses_fixed_point(model, choice.method)
                     ? "none (fixed-point iteration, Anderson acceleration of depth 1)"
                     : to_string(newton);
  return run;
}

}  // namespace flexref::reference
