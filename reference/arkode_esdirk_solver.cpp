/// \file arkode_esdirk_solver.cpp
/// ARKODE's ARKStep with an L-stable ESDIRK table on the quasi-velocity ODE form
/// (reference/ode_form.hpp), fully implicit (f_I = f, no explicit part): the A-stable reference
/// of order > 2 for stiff oscillatory scenes, where BDF must stop at order 2
/// (reference/method_choice.hpp; docs/references.md, "Stiff oscillatory scenes").
///
/// - Newton iteration on every stage with A = I − γJ: a flexible model's StructuredJacobian and
///   the structured Newton solve (reference/newton_linear_solver.hpp), else ARKODE's
///   difference-quotient Jacobian with a dense LU (or SolverOptions::jacobian).
/// - Outputs from ARKODE's Lagrange interpolant (ARK_INTERP_LAGRANGE, degree 5: built from the
///   solutions at past steps only, ARKODE's recommendation for stiff problems — the Hermite one
///   uses f(y), in which the stiff modes' derivatives are large) with tout = each output time.
/// - The segment loop (stops at load switches, restarts at contact events) is
///   sundials_segment_driver.hpp; each segment's first step is sized towards its end, so the
///   output grid does not steer the steps; θ is renormalized at every restart (no projection in
///   ARKStep; |θ| is a first integral and the form is homogeneous in θ).
#include "reference/arkode_esdirk_solver.hpp"

#include <arkode/arkode.h>
#include <arkode/arkode_arkstep.h>

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "reference/method_choice.hpp"
#include "reference/newton_linear_solver.hpp"
#include "reference/ode_form.hpp"
#include "reference/reference_solver.hpp"
#include "reference/structured_jacobian.hpp"
#include "reference/sundials_handle.hpp"
#include "reference/sundials_ode_callbacks.hpp"
#include "reference/sundials_segment_driver.hpp"

namespace flexref::reference {
namespace {

namespace sun = sundials;

/// Kennedy & Carpenter's ESDIRK5(4)7L[2]SA (2016): 7 stages (6 implicit, the first explicit),
/// order 5 with an embedded order 4, L-stable and stiffly accurate, stage order 2. Chosen among
/// SUNDIALS 6.4's DIRK tables of order 4 and 5 by error per CPU second on flexible_spinner_64
/// (docs/references.md, "Stiff oscillatory scenes").
constexpr ARKODE_DIRKTableID kTable = ARKODE_ESDIRK547L2SA_7_4_5;

class EsdirkSegmentSolver final : public sun::SegmentSolver {
 public:
  /// `stabilization`: Baumgarte's rate of the ODE form (ARKStep cannot project).
  EsdirkSegmentSolver(const core::Model& model, const SolverOptions& options, NewtonJacobian newton,
                      double stabilization)
      : model_(&model),
        options_(options),
        newton_(newton),
        form_(model, stabilization),
        context_(sun::make_context()),
        y_(sun::make_vector(form_.size(), context_.get())),
        jacobian_(sun::make_dense_matrix(form_.size(), context_.get())),
        linear_solver_(
            newton == NewtonJacobian::kStructured
                ? sun::LinearSolver(make_newton_linear_solver(form_, context_.get()))
                : sun::make_dense_linear_solver(y_.get(), jacobian_.get(), context_.get())) {
    data_.form = &form_;
    sun::bind_scratch(data_);
    data_.jacobian = options.jacobian;
    // The integrals' error weights (reference/integral_weights.hpp): the worn depths and the
    // works, contiguous in y (ARKStepReInit restarts ARKODE's step count).
    data_.rtol = options.rtol;
    data_.atol = options.absolute_tolerance();
    data_.integrals = {form_.depth_index(), form_.depth_count() + form_.integral_count()};
    data_.steps_since_init = [](void* ark) {
      long steps = 0;
      return ark == nullptr || ARKStepGetNumSteps(ark, &steps) < 0 ? 0L : steps;
    };
    if (newton == NewtonJacobian::kStructured) {
      structured_.emplace(form_);
      data_.structured = &*structured_;
      data_.structured_scratch = structured_->make_scratch();
    }
  }

  void start_segment(const sun::Segment& segment, const core::State& state,
                     std::span<const double> integrals) override {
    data_.t_segment = segment.t_segment;
    form_.pack(state, sun::data(y_.get()));
    // Ideal joints: every segment starts on the constraint manifold (else θ unit), where the
    // joints' tracker moves.
    form_.project(segment.start, sun::data(y_.get()), data_.scratch);
    sun::accept_tracker(data_, segment.start, sun::data(y_.get()));
    works_.start(integrals, sun::data(y_.get()));
    if (!ark_) {
      ark_.reset(sun::check_created(
          ARKStepCreate(nullptr, sun::ode_rhs, segment.start, y_.get(), context_.get()),
          "ARKStepCreate"));
      void* ark = ark_.get();
      sun::check(ARKStepSetTableNum(ark, kTable, ARKODE_ERK_NONE), "ARKStepSetTableNum");
      sun::check(ARKStepSetUserData(ark, &data_), "ARKStepSetUserData");
      sun::check(ARKStepSetErrHandlerFn(ark, sun::record_error, &data_.log),
                 "ARKStepSetErrHandlerFn");
      data_.solver_memory = ark;
      if (data_.integrals.count > 0) {
        sun::check(ARKStepWFtolerances(ark, sun::integral_error_weights<sun::OdeCallbackData>),
                   "ARKStepWFtolerances");
      } else {
        sun::check(ARKStepSStolerances(ark, options_.rtol, options_.absolute_tolerance()),
                   "ARKStepSStolerances");
      }
      sun::check(ARKStepSetInterpolantType(ark, ARK_INTERP_LAGRANGE), "ARKStepSetInterpolantType");
      sun::check(ARKStepSetLinearSolver(ark, linear_solver_.get(), jacobian_.get()),
                 "ARKStepSetLinearSolver");
      if (newton_ == NewtonJacobian::kUser) {
        sun::check(ARKStepSetJacFn(ark, sun::ode_jacobian), "ARKStepSetJacFn");
      } else if (newton_ == NewtonJacobian::kStructured) {
        sun::check(ARKStepSetJacFn(ark, sun::structured_ode_jacobian), "ARKStepSetJacFn");
      }
      sun::check(ARKStepSetMaxNumSteps(ark, options_.max_steps), "ARKStepSetMaxNumSteps");
      if (model_->switching_function_count() > 0) {
        sun::check(ARKStepRootInit(ark, model_->switching_function_count(), sun::ode_switching),
                   "ARKStepRootInit");
      }
    } else {
      sun::check(ARKStepReInit(ark_.get(), nullptr, sun::ode_rhs, segment.start, y_.get()),
                 "ARKStepReInit");
    }
    sun::check(ARKStepSetStopTime(ark_.get(), segment.end), "ARKStepSetStopTime");
    // The first step is taken towards the segment end, as in the CVODE driver: ARKODE sizes it
    // from the distance to the first tout, which would let the output grid steer the steps.
    // (Not with switching functions: a root in that step would be returned before the outputs
    // that precede it.)
    if (model_->switching_function_count() == 0) {
      double t_internal = segment.start;
      sun::check(ARKStepEvolve(ark_.get(), segment.end, y_.get(), &t_internal, ARK_ONE_STEP),
                 "ARKStepEvolve");
    }
  }

  Advance advance(double tout, double /*next*/) override {
    Advance reached;
    const int flag = ARKStepEvolve(ark_.get(), tout, y_.get(), &reached.t, ARK_NORMAL);
    sun::check(flag, "ARKStepEvolve");
    reached.root = flag == ARK_ROOT_RETURN;
    return reached;
  }

  void restart_at_root(double t, const sun::Segment& segment) override {
    form_.project(t, sun::data(y_.get()), data_.scratch);
    sun::accept_tracker(data_, t, sun::data(y_.get()));
    works_.rebase(sun::data(y_.get()));
    sun::check(ARKStepReInit(ark_.get(), nullptr, sun::ode_rhs, t, y_.get()), "ARKStepReInit");
    sun::check(ARKStepSetStopTime(ark_.get(), segment.end), "ARKStepSetStopTime");
  }

  void unpack(double t, core::State& state) const override {
    form_.unpack(t, sun::data(y_.get()), state);
  }
  void accept_output(double t, const core::State& state) override {
    sun::accept_output(data_, t, state);
  }
  void integrals(std::span<double> out) const override { works_.values(sun::data(y_.get()), out); }

  void add_counters(SolverStats& stats) const override {
    void* ark = ark_.get();
    long steps = 0, fe = 0, fi = 0, jacobians = 0, error_fails = 0, convergence_fails = 0;
    sun::check(ARKStepGetNumSteps(ark, &steps), "ARKStepGetNumSteps");
    sun::check(ARKStepGetNumRhsEvals(ark, &fe, &fi), "ARKStepGetNumRhsEvals");
    sun::check(ARKStepGetNumJacEvals(ark, &jacobians), "ARKStepGetNumJacEvals");
    sun::check(ARKStepGetNumErrTestFails(ark, &error_fails), "ARKStepGetNumErrTestFails");
    sun::check(ARKStepGetNumNonlinSolvConvFails(ark, &convergence_fails),
               "ARKStepGetNumNonlinSolvConvFails");
    stats.steps += steps;
    stats.rhs_evaluations += fe + fi;
    stats.jacobian_evaluations += jacobians;
    stats.error_test_failures += error_fails;
    stats.nonlinear_failures += convergence_fails;
  }

  double current_time(double fallback) const override {
    double t = fallback;
    return ARKStepGetCurrentTime(ark_.get(), &t) < 0 ? fallback : t;
  }
  long current_steps() const override {
    long steps = 0;
    return ARKStepGetNumSteps(ark_.get(), &steps) < 0 ? 0 : steps;
  }
  std::string failure_message(const std::string& what) const override {
    return sun::failure_message(what, data_, "right-hand side");
  }

 private:
  const core::Model* model_;
  SolverOptions options_;
  NewtonJacobian newton_;
  OdeForm form_;
  /// The works in y as increments since the last (re)start (reference/integral_weights.hpp).
  IntegralBase works_{{form_.work_index(), form_.integral_count()}};
  std::optional<StructuredJacobian> structured_;
  sun::OdeCallbackData data_;
  sun::Context context_;
  sun::Vector y_;
  sun::Matrix jacobian_;
  sun::LinearSolver linear_solver_;
  // Declared last so that it is freed first.
  sun::ArkStepMemory ark_;
};

}  // namespace

ReferenceRun solve_arkode_esdirk(const core::Model& model, const std::vector<double>& output_times,
                                 const SolverOptions& options) {
  const NewtonJacobian newton = choose_newton_jacobian(model, options);
  // ARKStep has no projection: the joints' drift is damped instead (Baumgarte).
  const double stabilization =
      constraint_stabilization_rate(model, mean_output_spacing(output_times));
  ReferenceRun run = sun::integrate_segments(model, output_times, options, "arkode", [&] {
    return std::make_unique<EsdirkSegmentSolver>(model, options, newton, stabilization);
  });
  run.method = "esdirk547l2sa-7-4-5";
  run.method_reason = "chosen with --method";
  run.jacobian = to_string(newton);
  return run;
}

}  // namespace flexref::reference
