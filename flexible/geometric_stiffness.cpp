/// \file geometric_stiffness.cpp
/// See geometric_stiffness.hpp and docs/geometric_stiffening.md for the formulas.
#include "flexible/geometric_stiffness.hpp"

#include <cstddef>
#include <stdexcept>
#include <string>

namespace flexref::flexible {
namespace {

constexpr std::size_t at(int k) { return static_cast<std::size_t>(k); }

const char* const kAxis[3] = {"x", "y", "z"};

std::string name_E(int c) { return std::string("E_") + kAxis[c]; }
std::string name_F(int ab) { return std::string("F_") + kAxis[ab / 3] + kAxis[ab % 3]; }

void check_matrix(const Eigen::MatrixXd& M, const std::string& name, int n) {
  if (M.rows() != n || M.cols() != n) {
    throw std::invalid_argument("geometric stiffness " + name + " is " + std::to_string(M.rows()) +
                                "×" + std::to_string(M.cols()) + ", expected " + std::to_string(n) +
                                "×" + std::to_string(n) + " (one per mode)");
  }
  if (!M.allFinite()) {
    throw std::invalid_argument("geometric stiffness " + name + " has a non-finite entry");
  }
  // The Lagrangian needs symmetric matrices (GS-3); 1e-10 of the largest entry admits a file
  // written with 17 significant digits from a symmetric matrix and refuses a transposition slip.
  const double scale = M.cwiseAbs().maxCoeff();
  if ((M - M.transpose()).cwiseAbs().maxCoeff() > 1e-10 * scale) {
    throw std::invalid_argument("geometric stiffness " + name + " is not symmetric");
  }
}

}  // namespace

void GeometricStiffness::validate(int n) const {
  for (int c = 0; c < 3; ++c) check_matrix(E[at(c)], name_E(c), n);
  for (int ab = 0; ab < 9; ++ab) check_matrix(F[at(ab)], name_F(ab), n);
}

GeometricStiffness GeometricStiffness::shifted(const Eigen::Vector3d& p) const {
  GeometricStiffness out = *this;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) out.F[at(3 * a + b)] -= p(b) * E[at(a)];
  }
  return out;
}

GeometricInvariants make_geometric_invariants(const GeometricStiffness& data, int n) {
  data.validate(n);
  return geometric_invariants_tpl<double>(data.E, data.F);
}

GeometricProducts make_geometric_products(int mode_count) {
  return make_geometric_products_tpl<double>(mode_count);
}

void compute_geometric_products(const GeometricInvariants& g,
                                const Eigen::Ref<const Eigen::VectorXd>& q_f,
                                const Eigen::Ref<const Eigen::VectorXd>& qd_f,
                                GeometricProducts& p) {
  compute_geometric_products_tpl<double>(g, q_f, qd_f, p);
}

void set_zero_geometric_products(GeometricProducts& p) { set_zero_geometric_products_tpl(p); }

double bilinear_form(const Eigen::MatrixXd& M, const Eigen::Ref<const Eigen::VectorXd>& x,
                     const Eigen::Ref<const Eigen::VectorXd>& y) {
  double sum = 0.0;
  for (Eigen::Index j = 0; j < M.cols(); ++j) sum += y(j) * M.col(j).dot(x);
  return sum;
}

Eigen::Vector3d foreshortening_first_moment_rate(const GeometricInvariants& g,
                                                 const Eigen::Ref<const Eigen::VectorXd>& q_f,
                                                 const Eigen::Ref<const Eigen::VectorXd>& u) {
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (const int c : g.E_nonzero) out(c) = -bilinear_form(g.E[at(c)], q_f, u);
  return out;
}

Eigen::Matrix3d foreshortening_inertia(const GeometricInvariants& g,
                                       const Eigen::Ref<const Eigen::VectorXd>& q_f) {
  Eigen::Matrix3d dJ = Eigen::Matrix3d::Zero();
  for (const int ab : g.F_nonzero) {
    const double v = -0.5 * bilinear_form(g.F[at(ab)], q_f, q_f);
    dJ(ab / 3, ab % 3) += v;
    dJ(ab % 3, ab / 3) += v;
  }
  return dJ.trace() * Eigen::Matrix3d::Identity() - dJ;
}

Eigen::Vector3d foreshortening_theta_f(const GeometricInvariants& g,
                                       const Eigen::Ref<const Eigen::VectorXd>& q_f,
                                       const Eigen::Ref<const Eigen::VectorXd>& u) {
  Eigen::Vector3d out = Eigen::Vector3d::Zero();
  for (const int c : g.Z_nonzero) out(c) = -bilinear_form(g.Z[at(c)], q_f, u);
  return out;
}

void foreshortening_terms(const Eigen::Ref<const Eigen::VectorXd>& q_f,
                          const Eigen::Ref<const Eigen::VectorXd>& qd_f, const GeometricProducts& p,
                          ForeshorteningTerms& f) {
  foreshortening_terms_tpl<double>(q_f, qd_f, p, f);
}

}  // namespace flexref::flexible
