#include "reference/reduced_cvode.hpp"

#include <cvode/cvode.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <exception>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "reference/error_weights.hpp"
#include "reference/method_choice.hpp"
#include "reference/sundials_handle.hpp"

namespace flexref::reference {
namespace {

namespace sun = sundials;

/// What the right-hand side reads and leaves behind (one per run).
struct ReducedOde {
  const constraint::ReducedModel* reduced = nullptr;
  constraint::ReducedWorkspace ws;
  Eigen::VectorXd q, u, u_dot;
  double stabilization = 0.0;
  /// reference/error_weights.hpp's weights per unit step on the coordinates that turn.
  std::optional<ErrorWeights> weights;
  void* cvode = nullptr;
  sun::ErrorLog log;
  std::exception_ptr error;
};

/// y' = f(t, y): the Euler parameters normalized for the evaluation (the loads and the forward
/// kinematics see an orthogonal A(θ)), q̇ from u, u̇ from the reduced model. Never throws through C.
int reduced_rhs(double t, N_Vector y, N_Vector ydot, void* user_data) {
  auto& d = *static_cast<ReducedOde*>(user_data);
  try {
    const constraint::TreeKinematics& k = d.reduced->kinematics();
    const int nq = k.position_count();
    const int nu = k.velocity_count();
    const double* Y = sun::data(y);
    double* Yd = sun::data(ydot);
    d.q = Eigen::Map<const Eigen::VectorXd>(Y, nq);
    d.u = Eigen::Map<const Eigen::VectorXd>(Y + nq, nu);
    k.normalize(d.q.data());
    k.rates(d.q.data(), d.u.data(), Yd);
    d.reduced->accelerations({t, 0.0}, d.q, d.u, d.ws, d.u_dot, d.stabilization);
    Eigen::Map<Eigen::VectorXd>(Yd + nq, nu) = d.u_dot;
    return d.u_dot.allFinite() ? 0 : 1;  // 1: recoverable, CVODE retries with a smaller step
  } catch (...) {
    d.error = std::current_exception();
    return -1;
  }
}

/// The error weights per unit step of reference/error_weights.hpp on the joint coordinates
/// that turn — each angle (revolute, universal, a cylindrical joint's first) and each Euler
/// parameter block (spherical, pivot, free) with its rates — and SUNDIALS' rtol |y_i| + atol on
/// every other component: the errors of all the steps add up to (rtol + atol) times the angle
/// turned, as the maximal reference's (an angle's scale is the radian, not how many turns it has
/// made).
int reduced_weights(N_Vector y, N_Vector ewt, void* user_data) {
  const auto& d = *static_cast<const ReducedOde*>(user_data);
  long steps = 0;
  double t = 0.0;
  CVodeGetNumSteps(d.cvode, &steps);
  CVodeGetCurrentTime(d.cvode, &t);
  d.weights->evaluate(sun::data(y), steps > 0 ? t / static_cast<double>(steps) : 0.0,
                      sun::data(ewt));
  return 0;
}

/// Baumgarte's rate on the closures by the maximal reference's rule (constraint_stabilization_rate,
/// method_choice.hpp) read on the reduced ODE itself: the fastest rate the solution must resolve
/// at the initial state — the bodies' angular speeds, the modes damped less than critically
/// (|Re λ| ≤ |Im λ|) and the growth rates Re λ > 0 of the Jacobian of y' = f(y) (forward
/// differences, step √ε max(1, |y_j|); eigenvalues below 1e-6 of its largest entry are zero) —
/// or π/Δt_out when none is known. The maximal rule's own summary differences the maximal form
/// (13 states per body); the reduced Jacobian is n_q + n_u square and has the same mechanism's
/// spectrum.
double reduced_stabilization_rate(ReducedOde& d, const Eigen::VectorXd& y0, double spacing) {
  const int n = static_cast<int>(y0.size());
  const sun::Context context = sun::make_context();
  const sun::Vector y = sun::make_vector(n, context.get());
  const sun::Vector f0 = sun::make_vector(n, context.get());
  const sun::Vector f1 = sun::make_vector(n, context.get());
  Eigen::Map<Eigen::VectorXd> Y(sun::data(y.get()), n);
  const Eigen::Map<Eigen::VectorXd> F0(sun::data(f0.get()), n), F1(sun::data(f1.get()), n);
  Y = y0;
  const double alpha = d.stabilization;
  d.stabilization = 0.0;
  double rate = 0.0;
  for (const core::BodyState& s : d.ws.tree.state) rate = std::max(rate, s.w_WB_B.norm());
  bool finite = reduced_rhs(0.0, y.get(), f0.get(), &d) == 0;
  for (const core::BodyState& s : d.ws.tree.state) rate = std::max(rate, s.w_WB_B.norm());
  Eigen::MatrixXd jacobian(n, n);
  for (int j = 0; finite && j < n; ++j) {
    const double step =
        std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(y0(j)));
    Y(j) = y0(j) + step;
    finite = reduced_rhs(0.0, y.get(), f1.get(), &d) == 0;
    Y(j) = y0(j);
    jacobian.col(j) = (F1 - F0) / step;
  }
  d.stabilization = alpha;
  if (finite && jacobian.allFinite()) {
    const double noise = 1e-6 * jacobian.cwiseAbs().maxCoeff();
    for (const std::complex<double>& lambda : jacobian.eigenvalues()) {
      if (std::abs(lambda.real()) <= std::abs(lambda.imag()))
        rate = std::max(rate, std::abs(lambda));
      if (lambda.real() > noise) rate = std::max(rate, lambda.real());
    }
  }
  if (rate > 0.0) return rate;
  return spacing > 0.0 ? std::numbers::pi / spacing : 1.0;
}

}  // namespace

ReducedRun solve_reduced_cvode(const constraint::ReducedModel& reduced,
                               const std::vector<double>& output_times,
                               const SolverOptions& options) {
  const core::Model& model = reduced.model();
  sun::validate_output_times(output_times);
  sun::validate_tolerances(options.rtol, options.absolute_tolerance(), options.max_steps);
  if (!model.discontinuities().empty()) {
    throw std::invalid_argument(
        "the reduced reference has no segments yet: the model's loads switch at known times");
  }
  const constraint::TreeKinematics& k = reduced.kinematics();
  const int nq = k.position_count();
  const int nu = k.velocity_count();
  ReducedOde d;
  d.reduced = &reduced;
  d.ws = reduced.make_workspace();
  d.u_dot = Eigen::VectorXd::Zero(nu);
  Eigen::VectorXd q0, u0;
  reduced.coordinates(model.initial_state(), q0, u0);
  d.q = q0;
  d.u = u0;
  if (reduced.closure_joints() != nullptr) {
    Eigen::VectorXd y0(nq + nu);
    y0 << q0, u0;
    d.stabilization = reduced_stabilization_rate(d, y0, mean_output_spacing(output_times));
  }

  const sun::Context context = sun::make_context();
  const sun::Vector y = sun::make_vector(nq + nu, context.get());
  Eigen::Map<Eigen::VectorXd>(sun::data(y.get()), nq) = q0;
  Eigen::Map<Eigen::VectorXd>(sun::data(y.get()) + nq, nu) = u0;
  const sun::NonlinearSolver fixed_point = sun::make_fixed_point_solver(y.get(), 1, context.get());
  const sun::CvodeMemory cvode(
      sun::check_created(CVodeCreate(CV_ADAMS, context.get()), "CVodeCreate"));
  void* mem = cvode.get();
  sun::check(CVodeInit(mem, reduced_rhs, 0.0, y.get()), "CVodeInit");
  sun::check(CVodeSetUserData(mem, &d), "CVodeSetUserData");
  sun::check(CVodeSetErrHandlerFn(mem, sun::record_error, &d.log), "CVodeSetErrHandlerFn");
  d.cvode = mem;
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
  d.weights.emplace(nq + nu, options.rtol, options.absolute_tolerance(), output_times.back(),
                    std::move(turning));
  sun::check(CVodeWFtolerances(mem, reduced_weights), "CVodeWFtolerances");
  sun::check(CVodeSetNonlinearSolver(mem, fixed_point.get()), "CVodeSetNonlinearSolver");
  sun::check(CVodeSetMaxNumSteps(mem, options.max_steps), "CVodeSetMaxNumSteps");

  ReducedRun run;
  run.stabilization = d.stabilization;
  constraint::TreeWorkspace fk = k.make_workspace();
  Eigen::VectorXd q(nq), u(nu);
  const auto record = [&](double t, const double* Y) {
    q = Eigen::Map<const Eigen::VectorXd>(Y, nq);
    u = Eigen::Map<const Eigen::VectorXd>(Y + nq, nu);
    k.normalize(q.data());
    k.evaluate(q, u, fk);
    run.times.push_back(t);
    run.states.push_back(fk.state);
  };
  for (const double t_out : output_times) {
    if (t_out == 0.0) {
      record(0.0, sun::data(y.get()));
      continue;
    }
    double t_reached = 0.0;
    const int flag = CVode(mem, t_out, y.get(), &t_reached, CV_NORMAL);
    if (flag < 0) {
      long steps = 0;
      CVodeGetNumSteps(mem, &steps);
      if (d.error) std::rethrow_exception(d.error);
      throw core::SolverError(
          "cvode (reduced)", t_reached, steps,
          d.log.message.empty() ? sun::flag_name(flag, "CVode") : d.log.message);
    }
    record(t_out, sun::data(y.get()));
  }
  sun::check(CVodeGetNumSteps(mem, &run.steps), "CVodeGetNumSteps");
  sun::check(CVodeGetNumRhsEvals(mem, &run.evaluations), "CVodeGetNumRhsEvals");
  return run;
}

}  // namespace flexref::reference
