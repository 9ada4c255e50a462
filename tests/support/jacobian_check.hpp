#pragma once
/// \file jacobian_check.hpp
/// Checks of a Jacobian J = ∂f/∂y of the ODE form (reference/ode_form.hpp) against
/// Richardson-extrapolated central differences of OdeForm::rhs, with a bound derived per column
/// (tests/reference/structured_jacobian_test.cpp, stiff_reference_test.cpp).
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "flexible/flexible_dynamics.hpp"
#include "reference/ode_form.hpp"
#include "tests/support/floating_point.hpp"

namespace flexref::testing {

/// A random y: positions and velocities O(1), θ random of norm 1.2, modal coordinate k
/// O(0.05 s_k²) and its rate O(0.3 s_k) with s_k = modal_scale(k) (1: every mode alike; ω_1/ω_k
/// keeps the elastic forces K q of a many-mode body O(1) as in a physical state).
template <class Scale>
std::vector<double> random_y(const reference::OdeForm& form, std::mt19937& rng, Scale modal_scale) {
  std::normal_distribution<double> normal;
  std::vector<double> y(static_cast<std::size_t>(form.size()));
  for (double& v : y) v = normal(rng);
  for (const reference::OdeForm::Block& k : form.blocks()) {
    if (k.theta >= 0) {
      Eigen::Map<Eigen::Vector4d> theta(y.data() + k.theta);
      theta *= 1.2 / theta.norm();
    }
    for (int i = 0; i < k.n; ++i) {
      const double s = modal_scale(i);
      y[static_cast<std::size_t>(k.q + i)] *= 0.05 * s * s;
      y[static_cast<std::size_t>(k.qd + i)] *= 0.3 * s;
    }
  }
  if (form.work_index() >= 0) y[static_cast<std::size_t>(form.work_index())] = 0.0;
  return y;
}

inline std::vector<double> random_y(const reference::OdeForm& form, std::mt19937& rng) {
  return random_y(form, rng, [](int) { return 1.0; });
}

/// Largest condition number of the bodies' mass matrices at y, over the rows each body solves
/// for (free: all; pivot: rotation and modes; prescribed: modes). Flexible: the dense (6+n)²
/// matrix; rigid: diag(m, I_Br).
inline double mass_condition(const reference::OdeForm& form, const std::vector<double>& y,
                             double t) {
  core::State state = form.model().initial_state();
  form.unpack(t, y.data(), state);
  double kappa = 1.0;
  for (int i = 0; i < form.model().num_bodies(); ++i) {
    const core::Body& b = form.model().body(i);
    const int n = b.mode_count();
    const int known = b.is_free() ? 0 : (b.is_prescribed() ? 6 : 3);
    if (known == 6 && n == 0) continue;
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(6 + n, 6 + n);
    if (b.is_flexible()) {
      const core::BodyState& s = state[static_cast<std::size_t>(i)];
      flexible::flexible_mass_matrix(b.invariants(), rotation::rotation_matrix(s.theta_WB), s.q_f,
                                     M);
    } else {
      M.topLeftCorner<3, 3>() = b.mass() * Eigen::Matrix3d::Identity();
      M.bottomRightCorner<3, 3>() = b.I_Br_B();
    }
    const Eigen::MatrixXd U = M.bottomRightCorner(6 + n - known, 6 + n - known);
    const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(U).eigenvalues();
    kappa = std::max(kappa, lambda.maxCoeff() / lambda.minCoeff());
  }
  return kappa;
}

/// Per column c of y: E = (4 D(h/2) − D(h)) / 3 from central differences D of the right-hand
/// side with h = 1e-3 max(1, |y_c|). Bound: |D(h) − D(h/2)| (it bounds E's O(h⁴) truncation
/// while c h² ≫ h⁴) + 3 ε_f / h (E's rounding, ε_f the rounding of one evaluation: a solve
/// with M, ≤ 4 d κ(M) ε S_f with d = dim y terms of scale S_f = max |f| + 1, Higham Thm. 10.4)
/// + 4 ε_f / h_J (J's own central differences of the loads with h_J = ε^{1/3}: their rounding
/// mapped through M⁻¹; their truncation, (h_J/h)² |D(h) − D(h/2)|, is below the first term).
/// Returns the largest ratio |J − E| / bound over the entries (≤ 1 passes). Checks that each
/// column's bound is at most 1e-4 of its scale (the comparison is not vacuous).
inline double worst_jacobian_ratio(const reference::OdeForm& form, const core::LoadContext& context,
                                   const std::vector<double>& y, const Eigen::MatrixXd& J) {
  reference::OdeForm::Scratch scratch = form.make_scratch();
  const int d = form.size();
  Eigen::VectorXd f(d);
  form.rhs(context, y.data(), f.data(), scratch);
  const double S_f = f.cwiseAbs().maxCoeff() + 1.0;
  const double eps_f = 4.0 * d * mass_condition(form, y, context.t) * kEps * S_f;
  const double h_J = std::cbrt(kEps);
  double worst = 0.0;
  for (int c = 0; c < d; ++c) {
    const double h = 1e-3 * std::max(1.0, std::abs(y[static_cast<std::size_t>(c)]));
    const auto D = [&](double step) {
      std::vector<double> yp = y, ym = y;
      yp[static_cast<std::size_t>(c)] += step;
      ym[static_cast<std::size_t>(c)] -= step;
      Eigen::VectorXd fp(d), fm(d);
      form.rhs(context, yp.data(), fp.data(), scratch);
      form.rhs(context, ym.data(), fm.data(), scratch);
      return Eigen::VectorXd((fp - fm) / (2.0 * step));
    };
    const Eigen::VectorXd D1 = D(h), D2 = D(h / 2.0);
    const Eigen::VectorXd E = (4.0 * D2 - D1) / 3.0;
    const double bound = (D1 - D2).cwiseAbs().maxCoeff() + 3.0 * eps_f / h + 4.0 * eps_f / h_J;
    CHECK(bound <= 1e-4 * (E.cwiseAbs().maxCoeff() + S_f));
    worst = std::max(worst, (J.col(c) - E).cwiseAbs().maxCoeff() / bound);
  }
  return worst;
}

}  // namespace flexref::testing
