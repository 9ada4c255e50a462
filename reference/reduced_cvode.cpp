#include "reference/reduced_cvode.hpp"

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
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

#include "constraint/reduced_model.hpp"
#include "reference/cvode_support.hpp"
#include "reference/error_weights.hpp"
#include "reference/integral_weights.hpp"
#include "reference/method_choice.hpp"
#include "reference/step_clock.hpp"
#include "reference/sundials_handle.hpp"
#include "reference/sundials_segment_driver.hpp"

namespace flexref::reference {
namespace {

namespace sun = sundials;

/// What the callbacks read and leave behind (one per run; make_ode). The works in y are
/// CallbackRecord::integrals (none while the spectrum is read, and when the model tracks no
/// work).
struct ReducedOde : sun::CallbackRecord {
  const constraint::ReducedModel* reduced = nullptr;
  constraint::ReducedWorkspace ws;
  constraint::ClosureTracker tracker;
  Eigen::VectorXd q, u, u_dot;
  Eigen::VectorXd force;  ///< the closures' generalized force (the drives' power)
  double stabilization = 0.0;
  double t_segment = 0.0;
  /// Each body's Euler parameters at the last accepted step with the sign that makes them
  /// continuous in time (accept_lift): the maximal references integrate θ itself, which keeps
  /// its sign, where forward kinematics returns θ or −θ as its conversion from the rotation
  /// matrix picks.
  std::vector<Eigen::Vector4d> lift;
};

/// The callback data of `reduced`: its workspace, the initial configuration's tracker and the
/// scratch, sized once (the solver's part of the record is the solver's to set).
ReducedOde make_ode(const constraint::ReducedModel& reduced) {
  ReducedOde d;
  d.reduced = &reduced;
  d.ws = reduced.make_workspace();
  d.tracker = reduced.make_tracker();
  d.q = Eigen::VectorXd::Zero(reduced.position_count());
  d.u = Eigen::VectorXd::Zero(reduced.velocity_count());
  d.u_dot = Eigen::VectorXd::Zero(reduced.velocity_count());
  d.force = Eigen::VectorXd::Zero(reduced.model().velocity_layout().size());
  d.lift.resize(static_cast<std::size_t>(reduced.model().num_bodies()));
  return d;
}

/// θ or −θ, whichever is nearer to `previous` (the same rotation; the bodies turn through far
/// less than π between two accepted steps or between a step and an output within it).
Eigen::Vector4d continued(const Eigen::Vector4d& theta, const Eigen::Vector4d& previous) {
  return theta.dot(previous) < 0.0 ? Eigen::Vector4d(-theta) : theta;
}

/// The lift moves to the bodies' attitudes at the last evaluation (that of the step accepted),
/// whose Euler parameters are formed here (the evaluations leave them to attitudes()).
void accept_lift(ReducedOde& d) {
  d.reduced->attitudes(d.ws);
  for (std::size_t b = 0; b < d.lift.size(); ++b) {
    d.lift[b] = continued(d.ws.tree.state[b].theta_WB, d.lift[b]);
  }
}

/// y' = f(t, y): the Euler parameters normalized for the evaluation (the loads and the forward
/// kinematics see an orthogonal A(θ)), q̇ from u, u̇ from the reduced model on the tracker's rows,
/// and the works' rates at the bodies' states.
void evaluate(ReducedOde& d, double t, const double* Y, double* Yd) {
  const constraint::ReducedModel& reduced = *d.reduced;
  const constraint::TreeKinematics& k = reduced.kinematics();
  const int nq = reduced.position_count();
  const int nu = reduced.velocity_count();
  d.q = Eigen::Map<const Eigen::VectorXd>(Y, nq);
  d.u = Eigen::Map<const Eigen::VectorXd>(Y + nq, nu);
  k.normalize(d.q.data());
  k.rates(d.q.data(), d.u.data(), Yd);
  const core::LoadContext context{t, d.t_segment};
  reduced.accelerations(context, d.q, d.u, d.ws, d.u_dot, d.stabilization, &d.tracker);
  Eigen::Map<Eigen::VectorXd>(Yd + nq, nu) = d.u_dot;
  if (d.integrals.count > 0) {
    reduced.attitudes(d.ws);  // the works' rates pose the bodies from their Euler parameters
    reduced.closure_force(d.ws, d.force);
    reduced.model().integral_rates(
        context, d.ws.tree.state, d.ws.model,
        std::span<double>(Yd + d.integrals.first, static_cast<std::size_t>(d.integrals.count)),
        &d.force);
  }
}

/// CVRhsFn. Never throws through C: an exception (a singular configuration) stops CVODE and
/// reaches the failure message; a non-finite derivative, or closure rows turned too far since the
/// accepted state for the orientation test (ReducedWorkspace::rows_turned), make it retry with a
/// smaller step.
int reduced_rhs(double t, N_Vector y, N_Vector ydot, void* user_data) {
  auto& d = *static_cast<ReducedOde*>(user_data);
  try {
    evaluate(d, t, sun::data(y), sun::data(ydot));
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;
  }
  if (d.ws.rows_turned) return 1;
  if (!sun::all_finite(sun::data(ydot), N_VGetLength_Serial(ydot))) {
    d.last_nonfinite_time = t;
    return 1;
  }
  return 0;
}

/// CVEwtFn, called before every step with the state CVODE accepted last: the closures' tracker
/// moves there (the last evaluation was the accepted step's final corrector iterate, within the
/// tolerance of that state), the step goes on the clock, and the weights are the rotation's per
/// unit step and the works' (sun::step_error_weights). Allocates nothing.
int reduced_error_weights(N_Vector y, N_Vector ewt, void* user_data) {
  auto& d = *static_cast<ReducedOde*>(user_data);
  try {
    double t = 0.0;
    sun::check(CVodeGetCurrentTime(d.solver_memory, &t), "CVodeGetCurrentTime");
    d.reduced->accept(t, d.ws, d.tracker);
    accept_lift(d);
    record_cvode_steps(d.solver_memory, *d.clock);
    sun::step_error_weights(d, y, ewt);
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;
  }
  return 0;
}

/// The rotation blocks of the coordinates that turn: each angle (revolute, universal, a
/// cylindrical joint's first) with its rate, each Euler-parameter block (spherical, pivot, free)
/// with ω̄ — an angle's scale is the radian, not how many turns it has made.
std::vector<RotationBlock> turning_blocks(const constraint::TreeKinematics& k) {
  const int nq = k.position_count();
  std::vector<RotationBlock> turning;
  for (const constraint::Mobilizer& m : k.tree().mobilizers) {
    const int u_first = nq + m.u_offset;
    switch (m.kind) {
      case constraint::MobilizerKind::kRevolute:
      case constraint::MobilizerKind::kCylindrical:
        turning.push_back({m.q_offset, u_first, -1, -1, 1, 1});
        break;
      case constraint::MobilizerKind::kUniversal:
        turning.push_back({m.q_offset, u_first, -1, -1, 1, 1});
        turning.push_back({m.q_offset + 1, u_first + 1, -1, -1, 1, 1});
        break;
      case constraint::MobilizerKind::kSpherical:
      case constraint::MobilizerKind::kPivot:
        turning.push_back({m.q_offset, u_first, -1, -1, 4, 3});
        break;
      case constraint::MobilizerKind::kFree:
        turning.push_back({m.q_offset + 3, u_first + 3, -1, -1, 4, 3});
        break;
      default:
        break;
    }
  }
  return turning;
}

/// The joint-coordinate form behind the segment loop.
class ReducedSegmentSolver final : public sun::SegmentSolver {
 public:
  /// `ode`: make_ode's data of the reduced model (the spectrum's, reused).
  ReducedSegmentSolver(ReducedOde ode, const SolverOptions& options, double stabilization,
                       double span, bool rotation_per_step)
      : reduced_(ode.reduced),
        options_(options),
        nq_(reduced_->position_count()),
        nu_(reduced_->velocity_count()),
        work_count_(reduced_->model().tracks_work() ? 1 + reduced_->model().extra_integral_count()
                                                    : 0),
        size_(nq_ + nu_ + work_count_),
        weights_(size_, options.rtol, options.absolute_tolerance(), span,
                 rotation_per_step ? turning_blocks(reduced_->kinematics())
                                   : std::vector<RotationBlock>{}),
        works_({nq_ + nu_, work_count_}),
        d_(std::move(ode)),
        fk_(reduced_->kinematics().make_workspace()),
        context_(sun::make_context()),
        y_(sun::make_vector(size_, context_.get())),
        ydot_(sun::make_vector(size_, context_.get())),
        fixed_point_(sun::make_fixed_point_solver(y_.get(), 1, context_.get())),
        cvode_(sun::check_created(CVodeCreate(CV_ADAMS, context_.get()), "CVodeCreate")) {
    d_.stabilization = stabilization;
    d_.rtol = options.rtol;
    d_.atol = options.absolute_tolerance();
    d_.integrals = {nq_ + nu_, work_count_};
    d_.solver_memory = cvode_.get();
    d_.steps_since_init = cvode_steps;
    d_.error_weights = &weights_;
    d_.clock = &clock_;
    q_ = Eigen::VectorXd::Zero(nq_);
    u_ = Eigen::VectorXd::Zero(nu_);
  }

  void start_segment(const sun::Segment& segment, const core::State& state,
                     std::span<const double> integrals) override {
    d_.t_segment = segment.t_segment;
    before_switch_ = SolverStats{};
    double* y = sun::data(y_.get());
    reduced_->coordinates(state, q_, u_);
    Eigen::Map<Eigen::VectorXd>(y, nq_) = q_;
    Eigen::Map<Eigen::VectorXd>(y + nq_, nu_) = u_;
    works_.start(integrals, y);
    for (std::size_t b = 0; b < d_.lift.size(); ++b) d_.lift[b] = state[b].theta_WB;
    // The closures' tracker moves to the segment's start (an evaluation there, accepted).
    evaluate(d_, segment.start, y, sun::data(ydot_.get()));
    reduced_->accept(segment.start, d_.ws, d_.tracker);
    void* cvode = cvode_.get();
    if (!initialized_) {
      sun::check(CVodeInit(cvode, reduced_rhs, segment.start, y_.get()), "CVodeInit");
      sun::check(CVodeSetUserData(cvode, &d_), "CVodeSetUserData");
      sun::check(CVodeSetErrHandlerFn(cvode, sun::record_error, &d_.log), "CVodeSetErrHandlerFn");
      sun::check(CVodeWFtolerances(cvode, reduced_error_weights), "CVodeWFtolerances");
      sun::check(CVodeSetNonlinearSolver(cvode, fixed_point_.get()), "CVodeSetNonlinearSolver");
      sun::check(CVodeSetMaxNumSteps(cvode, std::min(options_.max_steps, kStiffnessWindow)),
                 "CVodeSetMaxNumSteps");
      initialized_ = true;
      clock_.start_run(segment.start);
    } else {
      sun::check(CVodeReInit(cvode, segment.start, y_.get()), "CVodeReInit");
      clock_.restart(segment.start);
    }
    sun::check(CVodeSetStopTime(cvode, segment.end), "CVodeSetStopTime");
    segment_end_ = segment.end;
    // The first step towards the segment end, so that the output grid does not size it
    // (cvode_solver.cpp's start_segment has the measurement).
    double t_internal = segment.start;
    sun::check(CVode(cvode, segment.end, y_.get(), &t_internal, CV_ONE_STEP), "CVode");
  }

  Advance advance(double tout, double /*next*/) override {
    Advance reached;
    int flag = 0;
    if (newton_solver_) {
      flag = CVode(cvode_.get(), tout, y_.get(), &reached.t, CV_NORMAL);
    } else {
      // Fixed-point iteration in windows, Newton where it stalls (cvode_support.hpp).
      flag = advance_fixed_point(cvode_.get(), tout, y_.get(), reached.t, options_.max_steps,
                                 [this](double t) { switch_to_newton(t); });
    }
    sun::check(flag, "CVode");
    to_physical_time(reached.t);
    return reached;
  }

  void restart_at_root(double /*t*/, const sun::Segment& /*segment*/) override {
    throw std::logic_error("the joint-coordinate form has no switching functions");
  }

  void unpack(double /*t*/, core::State& state) const override {
    const double* y = sun::data(y_.get());
    q_ = Eigen::Map<const Eigen::VectorXd>(y, nq_);
    u_ = Eigen::Map<const Eigen::VectorXd>(y + nq_, nu_);
    const constraint::TreeKinematics& k = reduced_->kinematics();
    k.normalize(q_.data());
    k.evaluate_state(q_, u_, fk_);
    state = fk_.state;
    for (std::size_t b = 0; b < state.size(); ++b) {
      state[b].theta_WB = continued(state[b].theta_WB, d_.lift[b]);
    }
  }
  void integrals(std::span<double> out) const override { works_.values(sun::data(y_.get()), out); }

  void add_counters(SolverStats& stats) const override {
    add_cvode_counters(cvode_.get(), static_cast<bool>(newton_solver_), before_switch_, stats);
  }

  double current_time(double fallback) const override {
    return cvode_current_time(cvode_.get(), fallback);
  }
  long current_steps() const override { return cvode_steps(cvode_.get()) + before_switch_.steps; }
  std::string failure_message(const std::string& what) const override {
    return sun::failure_message(what, d_, "right-hand side");
  }

 private:
  /// Moves y_, CVODE's solution at its time t, to the physical time t (cvode_support.hpp).
  void to_physical_time(double t) {
    reference::to_physical_time(cvode_.get(), clock_, t, y_.get(), ydot_.get());
  }

  /// From fixed-point to Newton iteration at t, on CVODE's dense difference quotients (the
  /// reduced form's n_q + n_u + works columns), restarting from the state there.
  void switch_to_newton(double t) {
    void* cvode = cvode_.get();
    to_physical_time(t);
    SolverStats so_far;
    add_counters(so_far);  // CVodeReInit below starts CVODE's counters again
    before_switch_ = so_far;
    jacobian_ = sun::make_dense_matrix(size_, context_.get());
    linear_solver_ = sun::make_dense_linear_solver(y_.get(), jacobian_.get(), context_.get());
    newton_solver_ = sun::make_newton_solver(y_.get(), context_.get());
    sun::check(CVodeSetNonlinearSolver(cvode, newton_solver_.get()), "CVodeSetNonlinearSolver");
    sun::check(CVodeSetLinearSolver(cvode, linear_solver_.get(), jacobian_.get()),
               "CVodeSetLinearSolver");
    works_.rebase(sun::data(y_.get()));
    restart_with_newton(cvode, t, y_.get(), options_.max_steps, segment_end_, clock_);
  }

  const constraint::ReducedModel* reduced_;
  SolverOptions options_;
  int nq_, nu_, work_count_, size_;
  ErrorWeights weights_;
  StepClock clock_;
  /// The works in y as increments since the last (re)start (reference/integral_weights.hpp).
  IntegralBase works_;
  ReducedOde d_;
  mutable constraint::TreeWorkspace fk_;  ///< forward kinematics at the outputs
  mutable Eigen::VectorXd q_, u_;
  bool initialized_ = false;
  double segment_end_ = 0.0;
  SolverStats before_switch_;
  sun::Context context_;
  sun::Vector y_;
  sun::Vector ydot_;
  sun::NonlinearSolver fixed_point_;
  sun::Matrix jacobian_;
  sun::LinearSolver linear_solver_;
  sun::NonlinearSolver newton_solver_;
  // Declared last so that it is freed first (as in SUNDIALS' examples).
  sun::CvodeMemory cvode_;
};

/// The reduced ODE's spectrum at the initial state (Baumgarte off, the first segment's loads):
/// forward differences of (q̇, u̇) in (q, u), step √ε max(1, |y_j|), as summarize_stiffness
/// differences the maximal form; the same mechanism's spectrum without the maximal form's
/// drift modes.
StiffnessSummary reduced_summary(ReducedOde& d, double spacing) {
  const constraint::ReducedModel& reduced = *d.reduced;
  const core::Model& model = reduced.model();
  const std::vector<double>& switches = model.discontinuities();
  d.t_segment = switches.empty() ? 0.0 : 0.5 * switches.front();
  const int n = reduced.position_count() + reduced.velocity_count();
  Eigen::VectorXd y0(n), f0(n), f1(n);
  y0 << reduced.initial_positions(), reduced.initial_velocities();
  Eigen::VectorXd y = y0;
  Eigen::MatrixXd jacobian(n, n);
  evaluate(d, 0.0, y0.data(), f0.data());
  for (int j = 0; j < n; ++j) {
    const double step =
        std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(y0(j)));
    y(j) = y0(j) + step;
    evaluate(d, 0.0, y.data(), f1.data());
    y(j) = y0(j);
    jacobian.col(j) = (f1 - f0) / step;
  }
  if (!jacobian.allFinite()) return summarize_spectrum(model, {}, 0.0, spacing);
  const Eigen::VectorXcd eigenvalues = jacobian.eigenvalues();
  return summarize_spectrum(model,
                            std::span<const std::complex<double>>(
                                eigenvalues.data(), static_cast<std::size_t>(eigenvalues.size())),
                            1e-6 * jacobian.cwiseAbs().maxCoeff(), spacing);
}

/// Why the joint-coordinate form does not apply to the model with these options, or nothing.
std::optional<std::string> refusal(const core::Model& model, const SolverOptions& options) {
  if (!model.has_constraints()) return "no ideal joints";
  if (options.cvode_method == CvodeMethod::kBdf || options.cvode_method == CvodeMethod::kBdf2) {
    return std::string("--method ") + to_string(options.cvode_method) +
           ": BDF projects the maximal form (the joint coordinates run Adams)";
  }
  if (options.jacobian != nullptr) return "a user's Jacobian is of the maximal form";
  return std::nullopt;
}

/// The automatic choice's cost rule: the joint form's evaluation sums, body by body, over pairs of
/// the body's tree coordinates (its ancestors' columns of S: M_r = Σ_b S_bᵀ M_b S_b), Σ_b c_b²
/// terms, and factors M_r, dense where the tree is a chain; the maximal form's evaluation costs
/// about the same per body and row whatever the tree. Measured on spherical chains
/// (scripts/scenes/make_chain.py, CVODE at rtol 1e-8, CPU per evaluation joint/maximal): 6 rods
/// (Σ_b c_b² = 136 per body) 5.2/5.0 µs, 8 rods (230) 8.0/6.9 µs, 32 rods 239/25 µs; Andrews'
/// squeezer (about 5 per body) 2.1/8.2 µs. The joint form is chosen up to half the break-even.
constexpr double kJointTreeCostPerBody = 64.0;

/// The joint-coordinate run, or nothing with `why_not` set where the form does not apply or, when
/// `automatic`, where its tree is too deep to be the cheaper (kJointTreeCostPerBody).
std::optional<ReferenceRun> try_reduced(const core::Model& model,
                                        const std::vector<double>& output_times,
                                        const SolverOptions& options, bool automatic,
                                        std::string& why_not) {
  if (const std::optional<std::string> no = refusal(model, options)) {
    why_not = *no;
    return std::nullopt;
  }
  std::unique_ptr<constraint::ReducedModel> reduced;
  try {
    reduced = std::make_unique<constraint::ReducedModel>(model);
  } catch (const std::invalid_argument& e) {
    why_not = e.what();
    return std::nullopt;
  }
  double tree_cost = 0.0;
  for (int b = 0; b < model.num_bodies(); ++b) {
    const auto columns = static_cast<double>(reduced->kinematics().body_columns(b).size());
    tree_cost += columns * columns;
  }
  const double bodies = static_cast<double>(model.num_bodies());
  if (automatic && tree_cost > kJointTreeCostPerBody * bodies) {
    std::ostringstream why;
    why << "a deep tree: the bodies' tree coordinates give sum c_b^2 = " << tree_cost << " over "
        << model.num_bodies() << " bodies (more than " << kJointTreeCostPerBody
        << " per body), where the joint form's evaluation costs more than the maximal form's";
    why_not = why.str();
    return std::nullopt;
  }
  sun::validate_output_times(output_times);
  sun::validate_tolerances(options.rtol, options.absolute_tolerance(), options.max_steps);
  const double spacing = mean_output_spacing(output_times);
  ReducedOde ode = make_ode(*reduced);
  const StiffnessSummary summary = reduced_summary(ode, spacing);
  CvodeMethodChoice choice{CvodeMethod::kAdams, "chosen with --method"};
  if (options.cvode_method == CvodeMethod::kAuto) {
    choice = choose_cvode_method(summary);
    if (choice.method != CvodeMethod::kAdams) {
      why_not = "the joint coordinates' spectrum asks for BDF (" + choice.reason + ")";
      return std::nullopt;
    }
  }
  const double stabilization = reduced->closure_joints() != nullptr
                                   ? constraint_stabilization_rate(model, summary, spacing)
                                   : 0.0;
  const double span = output_times.empty() ? 0.0 : output_times.back() - output_times.front();
  // Adams chosen from the spectrum is where the rotation is weighted per unit step (as
  // solve_cvode's rule); Adams asked for leaves the spectrum to decide.
  const bool per_step =
      options.cvode_method == CvodeMethod::kAuto || rotation_weights_per_step(summary);
  ReferenceRun run = sun::integrate_segments(model, output_times, options, "cvode", [&] {
    return std::make_unique<ReducedSegmentSolver>(std::move(ode), options, stabilization, span,
                                                  per_step);
  });
  run.method = to_string(CvodeMethod::kAdams);
  run.method_reason = choice.reason;
  run.jacobian = "none (fixed-point iteration, Anderson acceleration of depth 1)";
  run.coordinates = "joint";
  const int closures =
      reduced->closure_joints() != nullptr ? reduced->closure_joints()->row_count() : 0;
  run.coordinates_reason = "rigid bodies on ideal joints, no contact, Adams: " +
                           std::to_string(reduced->velocity_count()) +
                           " joint coordinates of the spanning tree, " + std::to_string(closures) +
                           " loop-closure rows (" +
                           std::to_string(reduced->independent_rows().size()) + " independent)";
  return run;
}

}  // namespace

ReferenceRun solve_reduced_cvode(const core::Model& model, const std::vector<double>& output_times,
                                 const SolverOptions& options) {
  std::string why_not;
  std::optional<ReferenceRun> run = try_reduced(model, output_times, options, false, why_not);
  if (!run) throw std::invalid_argument("joint coordinates do not apply: " + why_not);
  return std::move(*run);
}

ReferenceRun solve_cvode_in_coordinates(const core::Model& model,
                                        const std::vector<double>& output_times,
                                        const SolverOptions& options) {
  if (options.coordinates == Coordinates::kJoint) {
    ReferenceRun run = solve_reduced_cvode(model, output_times, options);
    run.coordinates_reason = "chosen with --coordinates; " + run.coordinates_reason;
    return run;
  }
  std::string why_not = "chosen with --coordinates";
  if (options.coordinates == Coordinates::kAuto) {
    if (std::optional<ReferenceRun> run =
            try_reduced(model, output_times, options, true, why_not)) {
      return std::move(*run);
    }
  }
  ReferenceRun run = solve_cvode(model, output_times, options);
  run.coordinates = "maximal";
  run.coordinates_reason = why_not;
  return run;
}

}  // namespace flexref::reference
