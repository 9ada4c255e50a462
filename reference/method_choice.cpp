#include "reference/method_choice.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "reference/ode_form.hpp"

namespace flexref::reference {

namespace {

/// The ODE form's size above which the spectrum comes from a Krylov space instead of the dense
/// Jacobian: the dense eigenvalues cost O(n³) and its difference quotients n evaluations (a
/// chain of 128 bodies, n = 1664: 10 s, fifteen times its whole CVODE reference), where
/// kKrylovSteps evaluations and O(n k²) find the outer eigenvalues the summary reads
/// (docs/decisions.md, "Constrained systems at scale"). Every bundled scene is below it.
constexpr int kDenseSpectrumSize = 400;
/// Arnoldi steps of the Krylov estimate: the Ritz values of k steps approximate the eigenvalues
/// on the outside of the spectrum (the largest |λ|, the most negative and most positive Re λ),
/// which are the rates the choice compares with factors of kStiffnessRatio.
constexpr int kKrylovSteps = 80;

/// The ODE form at the initial state, on the first segment's loads, for difference quotients.
struct InitialPoint {
  explicit InitialPoint(const core::Model& model) : form(model), scratch(form.make_scratch()) {
    const auto n = static_cast<std::size_t>(form.size());
    y.resize(n);
    f0.resize(n);
    f1.resize(n);
    form.pack(model.initial_state(), y.data());
    const std::vector<double>& switches = model.discontinuities();
    context = core::LoadContext{0.0, switches.empty() ? 0.0 : 0.5 * switches.front()};
    form.rhs(context, y.data(), f0.data(), scratch);
  }
  OdeForm form;
  OdeForm::Scratch scratch;
  std::vector<double> y, f0, f1;
  core::LoadContext context{0.0, 0.0};
};

/// J = ∂f/∂y of the ODE form at the initial state by forward differences (step
/// √u · max(1, |y_j|), the optimum for a forward difference), on the first segment's loads.
Eigen::MatrixXd initial_jacobian(InitialPoint& p) {
  const int n = p.form.size();
  Eigen::MatrixXd jacobian(n, n);
  for (int j = 0; j < n; ++j) {
    const auto u = static_cast<std::size_t>(j);
    const double saved = p.y[u];
    const double step =
        std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(saved));
    p.y[u] = saved + step;
    p.form.rhs(p.context, p.y.data(), p.f1.data(), p.scratch);
    p.y[u] = saved;
    for (int i = 0; i < n; ++i) {
      const auto v = static_cast<std::size_t>(i);
      jacobian(i, j) = (p.f1[v] - p.f0[v]) / step;
    }
  }
  return jacobian;
}

/// The Ritz values of kKrylovSteps Arnoldi steps on J (Saad, Numerical Methods for Large
/// Eigenvalue Problems, Algorithm 6.2, with the Gram–Schmidt pass done twice), each product J v
/// a forward difference along the unit vector v (step √u · max(1, |y|)); the start vector a
/// fixed pseudo-random one (the same answer on every machine). Also the difference quotients'
/// noise level: 1e-6 of the largest |J v| met.
Eigen::VectorXcd krylov_eigenvalues(InitialPoint& p, double& noise) {
  const int n = p.form.size();
  const int k = std::min(n, kKrylovSteps);
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(n, k + 1);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(k + 1, k);
  Eigen::VectorXd y0(n);
  for (int i = 0; i < n; ++i) y0(i) = p.y[static_cast<std::size_t>(i)];
  const double step = std::sqrt(std::numeric_limits<double>::epsilon()) *
                      std::max(1.0, y0.lpNorm<Eigen::Infinity>());
  std::mt19937 random(20260052u);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  for (int i = 0; i < n; ++i) V(i, 0) = gaussian(random);
  V.col(0).normalize();
  double largest = 0.0;
  int steps = k;
  for (int j = 0; j < k; ++j) {
    for (int i = 0; i < n; ++i) p.y[static_cast<std::size_t>(i)] = y0(i) + step * V(i, j);
    p.form.rhs(p.context, p.y.data(), p.f1.data(), p.scratch);
    Eigen::VectorXd w(n);
    for (int i = 0; i < n; ++i) {
      const auto u = static_cast<std::size_t>(i);
      w(i) = (p.f1[u] - p.f0[u]) / step;
    }
    largest = std::max(largest, w.norm());
    for (int pass = 0; pass < 2; ++pass) {
      for (int i = 0; i <= j; ++i) {
        const double h = V.col(i).dot(w);
        H(i, j) += h;
        w -= h * V.col(i);
      }
    }
    H(j + 1, j) = w.norm();
    if (!(H(j + 1, j) > 1e-12 * largest)) {  // an invariant subspace: its Ritz values are exact
      steps = j + 1;
      break;
    }
    V.col(j + 1) = w / H(j + 1, j);
  }
  for (int i = 0; i < n; ++i) p.y[static_cast<std::size_t>(i)] = y0(i);
  noise = 1e-6 * largest;
  if (!std::isfinite(largest)) return Eigen::VectorXcd::Constant(1, largest);
  return Eigen::MatrixXd(H.topLeftCorner(steps, steps)).eigenvalues();
}

}  // namespace

bool StiffnessSummary::stiff() const {
  return switching_functions > 0 || fastest_decay > kStiffnessRatio * resolved_rate;
}

bool StiffnessSummary::stiff_oscillatory() const {
  return switching_functions == 0 && fastest_oscillation > kStiffnessRatio * accuracy_rate;
}

double mean_output_spacing(const std::vector<double>& output_times) {
  if (output_times.empty()) return 0.0;
  if (output_times.size() == 1) return output_times.front();
  return (output_times.back() - output_times.front()) /
         static_cast<double>(output_times.size() - 1);
}

namespace {

/// The summary's rates that need no spectrum: the switching functions, the bodies' angular
/// speeds and ω_acc.
StiffnessSummary initial_rates(const core::Model& model, double output_spacing) {
  StiffnessSummary summary;
  summary.switching_functions = model.switching_function_count();
  double angular_speed = 0.0;
  for (const core::BodyState& s : model.initial_state()) {
    angular_speed = std::max(angular_speed, s.w_WB_B.norm());
  }
  summary.resolved_rate = angular_speed;
  summary.accuracy_rate = output_spacing > 0.0
                              ? std::max(std::numbers::pi / output_spacing, angular_speed)
                              : std::numeric_limits<double>::infinity();
  return summary;
}

/// Adds the eigenvalues' rates to the summary.
void read_spectrum(std::span<const std::complex<double>> eigenvalues, double noise,
                   StiffnessSummary& summary) {
  for (const std::complex<double>& lambda : eigenvalues) {
    const double magnitude = std::abs(lambda);
    summary.fastest_rate = std::max(summary.fastest_rate, magnitude);
    if (-lambda.real() > noise)
      summary.fastest_decay = std::max(summary.fastest_decay, -lambda.real());
    if (std::abs(lambda.real()) <= std::abs(lambda.imag())) {
      summary.resolved_rate = std::max(summary.resolved_rate, magnitude);
      summary.fastest_oscillation = std::max(summary.fastest_oscillation, magnitude);
    }
    // A growing mode is resolved whatever the method (its growth sets the step): a mechanism
    // linearized away from equilibrium has real pairs ±σ (Andrews' squeezer: ±471/s at its
    // initial state), whose decaying half is then no faster than what the solution resolves.
    if (lambda.real() > noise) {
      summary.resolved_rate = std::max(summary.resolved_rate, lambda.real());
    }
  }
}

}  // namespace

StiffnessSummary summarize_spectrum(const core::Model& model,
                                    std::span<const std::complex<double>> eigenvalues, double noise,
                                    double output_spacing) {
  StiffnessSummary summary = initial_rates(model, output_spacing);
  read_spectrum(eigenvalues, noise, summary);
  return summary;
}

StiffnessSummary summarize_stiffness(const core::Model& model, double output_spacing) {
  StiffnessSummary summary = initial_rates(model, output_spacing);
  InitialPoint point(model);
  if (point.form.size() == 0) return summary;
  // Eigenvalues below the difference quotients' noise, ~1e-6 of the largest entry, are zero.
  double noise = 0.0;
  Eigen::VectorXcd eigenvalues;
  if (point.form.size() > kDenseSpectrumSize) {
    eigenvalues = krylov_eigenvalues(point, noise);
    if (!eigenvalues.allFinite()) return summary;
  } else {
    const Eigen::MatrixXd jacobian = initial_jacobian(point);
    if (!jacobian.allFinite()) {
      // Singular loads at the initial state: the solvers report it; no stiffness to infer.
      return summary;
    }
    noise = 1e-6 * jacobian.cwiseAbs().maxCoeff();
    eigenvalues = jacobian.eigenvalues();
  }
  read_spectrum(std::span<const std::complex<double>>(eigenvalues.data(),
                                                      static_cast<std::size_t>(eigenvalues.size())),
                noise, summary);
  return summary;
}

namespace {

/// "stiff oscillatory: ..." and what follows for the method (`then`).
std::string stiff_oscillatory_reason(const StiffnessSummary& s, const std::string& then) {
  std::ostringstream why;
  why.precision(3);
  why << "stiff oscillatory: a lightly damped mode at " << s.fastest_oscillation
      << " rad/s, more than " << kStiffnessRatio << "x the accuracy rate " << s.accuracy_rate
      << " rad/s (output Nyquist rate, angular speeds); " << then;
  return why.str();
}

constexpr const char* kBdf2Reason =
    "BDF orders 3-5 are unstable near the imaginary axis, so BDF max order 2 (A-stable)";

}  // namespace

CvodeMethodChoice choose_cvode_method(const core::Model& model, double output_spacing) {
  return choose_cvode_method(summarize_stiffness(model, output_spacing));
}

CvodeMethodChoice choose_cvode_method(const StiffnessSummary& s) {
  std::ostringstream why;
  why.precision(3);
  if (s.stiff_oscillatory()) {
    return {CvodeMethod::kBdf2, stiff_oscillatory_reason(s, kBdf2Reason)};
  }
  if (s.switching_functions > 0) {
    why << "stiff: contact (" << s.switching_functions << " switching functions)";
    return {CvodeMethod::kBdf, why.str()};
  }
  if (s.stiff()) {
    why << "stiff: a mode decays at " << s.fastest_decay << "/s, more than " << kStiffnessRatio
        << "x the fastest resolved rate " << s.resolved_rate << "/s";
    return {CvodeMethod::kBdf, why.str()};
  }
  why << "non-stiff: fastest rate " << s.fastest_rate << "/s, fastest decay " << s.fastest_decay
      << "/s (not above " << kStiffnessRatio << "x the resolved rate " << s.resolved_rate
      << "/s), no contact";
  return {CvodeMethod::kAdams, why.str()};
}

CvodeMethodChoice choose_ida_method(const core::Model& model, double output_spacing) {
  const StiffnessSummary s = summarize_stiffness(model, output_spacing);
  if (s.stiff_oscillatory()) {
    return {CvodeMethod::kBdf2, stiff_oscillatory_reason(s, kBdf2Reason)};
  }
  return {CvodeMethod::kBdf, "IDA's BDF on the implicit quasi-velocity form"};
}

ArkodeMethodChoice choose_arkode_method(const core::Model& model, double output_spacing) {
  return choose_arkode_method(summarize_stiffness(model, output_spacing));
}

ArkodeMethodChoice choose_arkode_method(const StiffnessSummary& s) {
  if (s.stiff_oscillatory()) {
    return {ArkodeMethod::kEsdirk,
            stiff_oscillatory_reason(s,
                                     "the explicit method's step would be held by the stability "
                                     "limit, so ARKStep ESDIRK5(4)7L[2]SA (L-stable, order 5)")};
  }
  return {ArkodeMethod::kErk,
          "ARKODE ERKStep, ARKODE_FEHLBERG_13_7_8, order-8 continuous extension"};
}

ReferenceSolverChoice choose_reference_solver(const core::Model& model, double output_spacing) {
  const StiffnessSummary s = summarize_stiffness(model, output_spacing);
  if (s.stiff_oscillatory()) {
    return {"arkode", stiff_oscillatory_reason(
                          s,
                          "arkode (ESDIRK, L-stable, order 5): the high modes damped, the steps "
                          "set by the accuracy; BDF of order > 2 is unstable there")};
  }
  return {"cvode", "the default reference (no stiff oscillatory mode)"};
}

bool rotation_weights_per_step(const StiffnessSummary& summary) {
  return summary.switching_functions == 0 && !summary.stiff() && !summary.stiff_oscillatory();
}

double constraint_stabilization_rate(const core::Model& model, double output_spacing) {
  if (!model.has_constraints()) return 0.0;
  return constraint_stabilization_rate(model, summarize_stiffness(model, output_spacing),
                                       output_spacing);
}

double constraint_stabilization_rate(const core::Model& model, const StiffnessSummary& summary,
                                     double output_spacing) {
  if (!model.has_constraints()) return 0.0;
  if (summary.resolved_rate > 0.0) return summary.resolved_rate;
  return output_spacing > 0.0 ? std::numbers::pi / output_spacing : 1.0;
}

NewtonJacobian choose_newton_jacobian(const core::Model& model, const SolverOptions& options) {
  // A user's or the structured Jacobian is the unconstrained right-hand side's; with ideal
  // joints (and for IDA's multiplier rows) the difference quotients are the system's own.
  if (model.has_constraints()) return NewtonJacobian::kDifferenceQuotients;
  if (options.jacobian != nullptr) return NewtonJacobian::kUser;
  if (model.has_flexible_bodies()) return NewtonJacobian::kStructured;
  return NewtonJacobian::kDifferenceQuotients;
}

NewtonJacobian choose_ida_newton_jacobian(const core::Model& model, const SolverOptions& options) {
  const NewtonJacobian chosen = choose_newton_jacobian(model, options);
  if (chosen != NewtonJacobian::kDifferenceQuotients || !model.has_constraints()) return chosen;
  return options.newton_matrix == NewtonMatrix::kDense ? chosen : NewtonJacobian::kColoured;
}

const char* to_string(NewtonJacobian jacobian) {
  switch (jacobian) {
    case NewtonJacobian::kDifferenceQuotients:
      return "difference quotients, dense LU";
    case NewtonJacobian::kStructured:
      return "structured, structured Newton solve";
    case NewtonJacobian::kUser:
      return "user, dense LU";
    case NewtonJacobian::kColoured:
      return "coloured difference quotients, sparse LU (KLU)";
  }
  return "difference quotients, dense LU";
}

const char* to_string(CvodeMethod method) {
  switch (method) {
    case CvodeMethod::kAuto:
      return "auto";
    case CvodeMethod::kAdams:
      return "adams";
    case CvodeMethod::kBdf:
      return "bdf";
    case CvodeMethod::kBdf2:
      return "bdf2";
  }
  return "auto";
}

const char* to_string(ArkodeMethod method) {
  switch (method) {
    case ArkodeMethod::kAuto:
      return "auto";
    case ArkodeMethod::kErk:
      return "erk";
    case ArkodeMethod::kEsdirk:
      return "esdirk";
  }
  return "auto";
}

ArkodeMethod parse_arkode_method(const std::string& name) {
  if (name == "auto") return ArkodeMethod::kAuto;
  if (name == "erk") return ArkodeMethod::kErk;
  if (name == "esdirk") return ArkodeMethod::kEsdirk;
  throw std::invalid_argument("unknown ARKODE method '" + name + "' (auto, erk, esdirk)");
}

const char* to_string(Coordinates coordinates) {
  switch (coordinates) {
    case Coordinates::kAuto:
      return "auto";
    case Coordinates::kMaximal:
      return "maximal";
    case Coordinates::kJoint:
      return "joint";
  }
  return "auto";
}

Coordinates parse_coordinates(const std::string& name) {
  if (name == "auto") return Coordinates::kAuto;
  if (name == "maximal") return Coordinates::kMaximal;
  if (name == "joint") return Coordinates::kJoint;
  throw std::invalid_argument("unknown coordinates '" + name + "' (auto, maximal, joint)");
}

CvodeMethod parse_cvode_method(const std::string& name) {
  if (name == "auto") return CvodeMethod::kAuto;
  if (name == "adams") return CvodeMethod::kAdams;
  if (name == "bdf") return CvodeMethod::kBdf;
  if (name == "bdf2") return CvodeMethod::kBdf2;
  throw std::invalid_argument("unknown CVODE method '" + name + "' (auto, adams, bdf, bdf2)");
}

}  // namespace flexref::reference
