#include "reference/method_choice.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "reference/ode_form.hpp"

namespace flexref::reference {

namespace {

/// J = ∂f/∂y of the ODE form at the initial state by forward differences (step
/// √u · max(1, |y_j|), the optimum for a forward difference), on the first segment's loads.
Eigen::MatrixXd initial_jacobian(const core::Model& model) {
  const OdeForm form(model);
  const int n = form.size();
  OdeForm::Scratch scratch = form.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(n)), f0(y.size()), f1(y.size());
  form.pack(model.initial_state(), y.data());
  const std::vector<double>& switches = model.discontinuities();
  const double t_segment = switches.empty() ? 0.0 : 0.5 * switches.front();
  const core::LoadContext context{0.0, t_segment};
  form.rhs(context, y.data(), f0.data(), scratch);
  Eigen::MatrixXd jacobian(n, n);
  for (int j = 0; j < n; ++j) {
    const auto u = static_cast<std::size_t>(j);
    const double saved = y[u];
    const double step =
        std::sqrt(std::numeric_limits<double>::epsilon()) * std::max(1.0, std::abs(saved));
    y[u] = saved + step;
    form.rhs(context, y.data(), f1.data(), scratch);
    y[u] = saved;
    for (int i = 0; i < n; ++i) {
      const auto v = static_cast<std::size_t>(i);
      jacobian(i, j) = (f1[v] - f0[v]) / step;
    }
  }
  return jacobian;
}

}  // namespace

bool StiffnessSummary::stiff() const {
  return switching_functions > 0 || fastest_decay > kStiffnessRatio * resolved_rate;
}

StiffnessSummary summarize_stiffness(const core::Model& model) {
  StiffnessSummary summary;
  summary.switching_functions = model.switching_function_count();
  for (const core::BodyState& s : model.initial_state()) {
    summary.resolved_rate = std::max(summary.resolved_rate, s.w_WB_B.norm());
  }
  const Eigen::MatrixXd jacobian = initial_jacobian(model);
  if (jacobian.size() == 0) return summary;
  if (!jacobian.allFinite()) {
    // Singular loads at the initial state: the solvers report it; no stiffness to infer.
    return summary;
  }
  // Eigenvalues below the difference quotients' noise, ~1e-6 of the largest entry, are zero.
  const double noise = 1e-6 * jacobian.cwiseAbs().maxCoeff();
  const Eigen::VectorXcd eigenvalues = jacobian.eigenvalues();
  for (const std::complex<double>& lambda : eigenvalues) {
    const double magnitude = std::abs(lambda);
    summary.fastest_rate = std::max(summary.fastest_rate, magnitude);
    if (-lambda.real() > noise)
      summary.fastest_decay = std::max(summary.fastest_decay, -lambda.real());
    if (std::abs(lambda.real()) <= std::abs(lambda.imag())) {
      summary.resolved_rate = std::max(summary.resolved_rate, magnitude);
    }
  }
  return summary;
}

CvodeMethodChoice choose_cvode_method(const core::Model& model) {
  const StiffnessSummary s = summarize_stiffness(model);
  std::ostringstream why;
  why.precision(3);
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

const char* to_string(CvodeMethod method) {
  switch (method) {
    case CvodeMethod::kAuto:
      return "auto";
    case CvodeMethod::kAdams:
      return "adams";
    case CvodeMethod::kBdf:
      return "bdf";
  }
  return "auto";
}

CvodeMethod parse_cvode_method(const std::string& name) {
  if (name == "auto") return CvodeMethod::kAuto;
  if (name == "adams") return CvodeMethod::kAdams;
  if (name == "bdf") return CvodeMethod::kBdf;
  throw std::invalid_argument("unknown CVODE method '" + name + "' (auto, adams, bdf)");
}

}  // namespace flexref::reference
