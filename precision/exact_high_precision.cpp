#include "precision/exact_high_precision.hpp"

// Eigen's NumTraits for float128 before any Eigen type of it.
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/float128.hpp>
#include <chrono>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "precision/ode_system.hpp"
#include "precision/parse_text.hpp"
#include "reference/exact_heavy_top.hpp"
#include "reference/exact_pendulum.hpp"
#include "reference/exact_rotation_tpl.hpp"
#include "reference/exact_solution.hpp"
#include "reference/exact_torque_free.hpp"
#include "scene/build_model.hpp"

namespace flexref::precision {
namespace {

using Quad = boost::multiprecision::float128;

template <typename S>
using Vector3 = Eigen::Matrix<S, 3, 1>;
template <typename S>
using Quaternion = Eigen::Matrix<S, 4, 1>;
template <typename S>
using Matrix3 = Eigen::Matrix<S, 3, 3>;

/// Principal moments and axes (columns of R_BP, det +1) of an inertia in precision S. The
/// bundled scenes give their inertia in principal axes, so it is usually diagonal, and then
/// the decomposition is exact (moments = diagonal, R_BP = I). Otherwise cyclic Jacobi
/// rotations in S (Golub & Van Loan §8.5.2; Eigen's SelfAdjointEigenSolver does not compile for
/// float128 with Boost 1.74's NumTraits, which lack infinity() and quiet_NaN()): each sweep
/// squares the off-diagonal size, and a rotation is skipped once |J_pq| ≤ ε/2 √(J_pp J_qq),
/// below which it would not change the diagonal in S; the moments are then accurate to a few
/// ε of S times the largest moment, the axes orthonormal to a few ε.
template <typename S>
struct Principal {
  Vector3<S> moments;
  Matrix3<S> R_BP;
};

template <typename S>
Principal<S> principal_axes(const Matrix3<S>& inertia) {
  using std::abs;
  using std::sqrt;
  Matrix3<S> J = inertia;
  Matrix3<S> V = Matrix3<S>::Identity();
  const S half_eps = std::numeric_limits<S>::epsilon() / S(2);
  for (int sweep = 0; sweep < 50; ++sweep) {
    bool rotated = false;
    for (const auto& [p, q] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}}) {
      if (abs(J(p, q)) <= half_eps * sqrt(abs(S(J(p, p) * J(q, q))))) {
        J(p, q) = J(q, p) = S(0);
        continue;
      }
      rotated = true;
      // tan of the rotation angle from cot 2φ = (J_qq − J_pp)/(2 J_pq), the smaller root.
      const S cot2 = (J(q, q) - J(p, p)) / (S(2) * J(p, q));
      const S t = (cot2 >= S(0) ? S(1) : S(-1)) / (abs(cot2) + sqrt(cot2 * cot2 + S(1)));
      const S c = S(1) / sqrt(t * t + S(1));
      const S s = t * c;
      Matrix3<S> G = Matrix3<S>::Identity();
      G(p, p) = c;
      G(q, q) = c;
      G(p, q) = s;
      G(q, p) = -s;
      const Matrix3<S> rotated_J = G.transpose() * J * G;
      J = rotated_J;
      J(p, q) = J(q, p) = S(0);
      V = Matrix3<S>(V * G);
    }
    if (!rotated) break;
  }
  Principal<S> result{J.diagonal(), V};
  if (result.R_BP.determinant() < S(0)) result.R_BP.col(2) *= S(-1);
  return result;
}

template <typename S>
HighPrecisionRun evaluate(const scene::SceneSpec& spec, const std::string& kind,
                          const std::vector<double>& output_times, Precision precision,
                          const char* type_name) {
  using std::isfinite;
  using std::sqrt;
  const auto start = std::chrono::steady_clock::now();
  const OdeSystemTpl<S> model(spec, core::FlexibleFormulation::kCoupled);
  const typename OdeSystemTpl<S>::MassProperties body = model.mass_properties(0);
  const std::vector<S> y0 = model.initial_state();  // (p_WBr), θ_WB (unit in S), (v_WBr), ω̄
  const reference::BodyBlock& block = model.blocks().front();
  const auto at = [](int offset, int k) { return static_cast<std::size_t>(offset + k); };
  const Quaternion<S> theta0(y0[at(block.theta, 0)], y0[at(block.theta, 1)], y0[at(block.theta, 2)],
                             y0[at(block.theta, 3)]);
  const Vector3<S> w0_B(y0[at(block.w, 0)], y0[at(block.w, 1)], y0[at(block.w, 2)]);
  const S t0(output_times.front());

  HighPrecisionRun run;
  run.precision = precision;
  run.rtol = 0.0;
  run.method = "exact (" + kind + "), " + type_name;
  run.columns = model.columns();
  run.table.columns = run.columns;
  const int digits = significant_digits(precision);
  std::vector<S> y = y0;
  const auto record = [&](double t, const Quaternion<S>& theta_WB, const Vector3<S>& w_B) {
    // A free body's centre of mass moves uniformly: p_WBr(t) = p_WBr(t0) + (t − t0) v_WBr.
    const S dt = S(t) - t0;
    if (block.p >= 0) {
      for (int k = 0; k < 3; ++k) y[at(block.p, k)] = y0[at(block.p, k)] + dt * y0[at(block.v, k)];
    }
    for (int k = 0; k < 4; ++k) y[at(block.theta, k)] = theta_WB(k);
    for (int k = 0; k < 3; ++k) y[at(block.w, k)] = w_B(k);
    std::vector<std::string> text;
    std::vector<double> values{t};
    for (const S& v : model.output_row(S(t), y)) {
      if (!static_cast<bool>(isfinite(v))) {
        throw std::invalid_argument("exact solution (" + kind +
                                    "): a non-finite value at t = " + std::to_string(t));
      }
      text.push_back(detail::print(v, digits));
      values.push_back(static_cast<double>(v));
    }
    run.text.push_back(std::move(text));
    run.table.rows.push_back(std::move(values));
  };

  const Principal<S> p = principal_axes(body.J_Br_B);
  if (kind == "torque_free") {
    // In the principal frame P: θ_WP = θ_WB ⊗ q_BP, ω_P = R_BPᵀ ω_B (as reference::solve_exact).
    const Quaternion<S> q_BP = reference::detail::euler_parameters_from_matrix<S>(p.R_BP);
    const Quaternion<S> q_PB(q_BP(0), -q_BP(1), -q_BP(2), -q_BP(3));
    const reference::TorqueFreeExactTpl<S> exact(
        p.moments, reference::detail::quaternion_multiply<S>(theta0, q_BP),
        Vector3<S>(p.R_BP.transpose() * w0_B));
    for (double t : output_times) {
      const reference::RigidAttitudeTpl<S> a = exact.at(S(t) - t0);
      record(t, reference::detail::quaternion_multiply<S>(a.theta, q_PB).normalized(),
             Vector3<S>(p.R_BP * a.w_B));
    }
  } else if (kind == "pendulum") {
    // Released from rest (classify_exact_solution checked it, and the planar axis, in double);
    // the inertia about the pivot and c_B are the model's, formed in S.
    const Vector3<S> g_W(S(spec.g_W.x()), S(spec.g_W.y()), S(spec.g_W.z()));
    const reference::PendulumExactTpl<S> exact(body.mass, body.c_B, body.J_Br_B, g_W, theta0);
    for (double t : output_times) {
      const reference::RigidAttitudeTpl<S> a = exact.at(S(t) - t0);
      record(t, a.theta, a.w_B);
    }
  } else {
    // Lagrange top: the two equal moments are J⊥, the third J_a (classify_exact_solution
    // checked the symmetry and that the centre of mass is on the axis, in double).
    using std::abs;
    // The axial index is the one whose two others are equal to classify_exact_solution's
    // 1e-12 (the moments here are not sorted).
    const S tolerance = S(1e-12) * p.moments.maxCoeff();
    int axis = 2;
    for (int k = 0; k < 3; ++k) {
      if (abs(S(p.moments((k + 1) % 3) - p.moments((k + 2) % 3))) <= tolerance) axis = k;
    }
    const S j_axial = p.moments(axis);
    const S j_perp = p.moments((axis + 1) % 3);
    const Vector3<S>& c_B = body.c_B;
    const S distance = c_B.norm();
    const Vector3<S> g_W(S(spec.g_W.x()), S(spec.g_W.y()), S(spec.g_W.z()));
    const reference::HeavyTopExactTpl<S> exact(body.mass, distance, Vector3<S>(c_B / distance),
                                               j_perp, j_axial, g_W, theta0, w0_B);
    for (double t : output_times) {
      const reference::RigidAttitudeTpl<S> a = exact.at(S(t) - t0);
      record(t, a.theta, a.w_B);
    }
  }
  run.steps = static_cast<long>(output_times.size());
  run.cpu_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

}  // namespace

HighPrecisionRun exact_high_precision(const scene::SceneSpec& spec,
                                      const std::vector<double>& output_times,
                                      Precision precision) {
  if (output_times.empty()) throw std::invalid_argument("exact_high_precision: no output times");
  const reference::ExactSolutionKind kind =
      reference::classify_exact_solution(scene::build_model(spec));
  if (kind.kind.empty()) {
    throw std::invalid_argument("no exact solution for this scene: " + kind.reason);
  }
  switch (precision) {
    case Precision::kDouble:
      return evaluate<double>(spec, kind.kind, output_times, precision, "double");
    case Precision::kExtended:
      return evaluate<long double>(spec, kind.kind, output_times, precision,
                                   "long double (x87 80-bit)");
    case Precision::kQuad:
      return evaluate<Quad>(spec, kind.kind, output_times, precision,
                            "float128 (IEEE binary128, libquadmath)");
  }
  throw std::invalid_argument("exact_high_precision: unknown precision");
}

trajectory::ReferenceEstimate exact_high_precision_estimate(const scene::SceneSpec& spec,
                                                            const std::vector<double>& output_times,
                                                            const HighPrecisionRun& exact,
                                                            const std::string& metric,
                                                            reference::SolveProgress* progress) {
  const double rtol = smallest_rtol(exact.precision);
  const HighPrecisionRun check = solve_high_precision(
      spec, output_times, exact.precision, rtol, core::FlexibleFormulation::kCoupled, progress);
  trajectory::ReferenceEstimate e;
  e.metric = metric;
  e.exact = true;
  trajectory::EstimateCheck c;
  c.role = "other";
  c.solver = "odeint";
  c.method = check.method;
  c.rtol = rtol;
  c.steps = check.steps;
  c.distance = distance(exact, check, metric);
  c.used = c.distance > 0.0;
  if (!c.used) c.note = "distance exactly 0";
  e.checks.push_back(c);
  e.value = c.used ? c.distance : std::numeric_limits<double>::infinity();
  std::ostringstream method;
  method << "distance, computed in " << to_string(exact.precision)
         << " precision, to an independent numerical solution (odeint Bulirsch-Stoer rtol "
         << std::setprecision(3) << rtol
         << "): bounds the exact solution's error plus the numerical one's";
  e.method = c.used ? method.str() : "none: the numerical solution equals the exact one";
  return e;
}

}  // namespace flexref::precision
