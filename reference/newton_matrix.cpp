/// \file newton_matrix.cpp
/// See newton_matrix.hpp for the elimination.
#include "reference/newton_matrix.hpp"

#include <Eigen/LU>
#include <cmath>
#include <cstddef>

namespace flexref::reference {
namespace {

std::size_t at(int i) { return static_cast<std::size_t>(i); }

}  // namespace

NewtonMatrixSolver::NewtonMatrixSolver(const OdeForm& form)
    : size_(form.size()),
      work_(form.work_index()),
      integrals_(form.work_index() >= 0 ? form.integral_count() : 0) {
  kind_.assign(at(size_), 2);
  reduced_.assign(at(size_), -1);
  const auto add_position = [&](int y) {
    kind_[at(y)] = 0;
    reduced_[at(y)] = static_cast<int>(position_.size());
    position_.push_back(y);
  };
  const auto add_velocity = [&](int y) {
    kind_[at(y)] = 1;
    reduced_[at(y)] = static_cast<int>(velocity_.size());
    velocity_.push_back(y);
  };
  for (const OdeForm::Block& k : form.blocks()) {
    for (int i = 0; k.p >= 0 && i < 3; ++i) add_position(k.p + i);
    for (int i = 0; k.theta >= 0 && i < 4; ++i) add_position(k.theta + i);
    for (int i = 0; i < k.n; ++i) add_position(k.q + i);
    for (int i = 0; k.v >= 0 && i < 3; ++i) add_velocity(k.v + i);
    for (int i = 0; k.w >= 0 && i < 3; ++i) add_velocity(k.w + i);
    for (int i = 0; i < k.n; ++i) add_velocity(k.qd + i);
  }
  partner_.assign(at(size_), -1);
  theta_of_.assign(at(size_), -1);
  for (const OdeForm::Block& k : form.blocks()) {
    for (int i = 0; k.p >= 0 && i < 3; ++i) {
      pairs_.push_back({k.p + i, k.v + i, reduced_[at(k.v + i)], 0.0});
      partner_[at(k.p + i)] = k.v + i;
    }
    for (int i = 0; i < k.n; ++i) {
      pairs_.push_back({k.q + i, k.qd + i, reduced_[at(k.qd + i)], 0.0});
      partner_[at(k.q + i)] = k.qd + i;
    }
    if (k.theta >= 0) {
      ThetaBlock t;
      t.theta = k.theta;
      t.w = k.w;
      t.w_reduced = reduced_[at(k.w)];
      for (int i = 0; i < 4; ++i) theta_of_[at(k.theta + i)] = static_cast<int>(thetas_.size());
      thetas_.push_back(t);
    }
  }
  const auto nv = static_cast<Eigen::Index>(velocity_.size());
  const auto np = static_cast<Eigen::Index>(position_.size());
  A_VP = Eigen::MatrixXd::Zero(nv, np);
  A_WP = Eigen::MatrixXd::Zero(integrals_, np);
  A_WV = Eigen::MatrixXd::Zero(integrals_, nv);
  A_WW = Eigen::VectorXd::Ones(integrals_);
  S = Eigen::MatrixXd::Zero(nv, nv);
  lu_ = Eigen::PartialPivLU<Eigen::MatrixXd>(nv);
  z_P_ = Eigen::VectorXd::Zero(np);
  x_V_ = Eigen::VectorXd::Zero(nv);
  rhs_V_ = Eigen::VectorXd::Zero(nv);
}

bool NewtonMatrixSolver::factor(const double* A_data, int ld) {
  const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> A(A_data, size_, size_,
                                                                     Eigen::OuterStride<>(ld));
  // The pattern: a position row has non-zeros only on its own diagonal and its velocity (p, q_f)
  // or within its θ block and the body's ω̄ (θ); the W column is e_W.
  for (const int row : position_) {
    const int partner = partner_[at(row)];
    const int theta = theta_of_[at(row)];
    for (int col = 0; col < size_; ++col) {
      if (A(row, col) == 0.0 || col == row || col == partner) continue;
      if (theta >= 0) {
        const int w = thetas_[at(theta)].w;
        const int t0 = thetas_[at(theta)].theta;
        if ((col >= t0 && col < t0 + 4) || (col >= w && col < w + 3)) continue;
      }
      return false;
    }
  }
  for (const ScalarPair& p : pairs_) {
    if (A(p.position, p.position) != 1.0) return false;
  }
  for (int k = 0; k < integrals_; ++k) {
    const int w = work_ + k;
    for (int row = 0; row < size_; ++row) {
      if (row != w && A(row, w) != 0.0) return false;
    }
    A_WW(k) = A(w, w);
    if (!(A_WW(k) != 0.0) || !std::isfinite(A_WW(k))) return false;
  }

  // Gather A(V, V), A(V, P) and row W.
  const auto nv = static_cast<Eigen::Index>(velocity_.size());
  const auto np = static_cast<Eigen::Index>(position_.size());
  for (Eigen::Index j = 0; j < nv; ++j) {
    for (Eigen::Index i = 0; i < nv; ++i)
      S(i, j) = A(velocity_[at(static_cast<int>(i))], velocity_[at(static_cast<int>(j))]);
  }
  for (Eigen::Index j = 0; j < np; ++j) {
    for (Eigen::Index i = 0; i < nv; ++i) {
      A_VP(i, j) = A(velocity_[at(static_cast<int>(i))], position_[at(static_cast<int>(j))]);
    }
  }
  for (int k = 0; k < integrals_; ++k) {
    for (Eigen::Index j = 0; j < np; ++j) {
      A_WP(k, j) = A(work_ + k, position_[at(static_cast<int>(j))]);
    }
    for (Eigen::Index j = 0; j < nv; ++j) {
      A_WV(k, j) = A(work_ + k, velocity_[at(static_cast<int>(j))]);
    }
  }

  // S = A_VV − A_VP A_PP⁻¹ A_PV.
  for (ScalarPair& p : pairs_) {
    p.c = A(p.position, p.velocity);
    if (p.c != 0.0) S.col(p.velocity_reduced) -= p.c * A_VP.col(reduced_[at(p.position)]);
  }
  for (ThetaBlock& t : thetas_) {
    const Eigen::Matrix4d T = A.block<4, 4>(t.theta, t.theta);
    bool invertible = false;
    double det = 0.0;
    T.computeInverseAndDetWithCheck(t.T_inverse, det, invertible);
    if (!invertible) return false;
    t.C = A.block<4, 3>(t.theta, t.w);
    const Eigen::Matrix<double, 4, 3> TinvC = t.T_inverse * t.C;
    const Eigen::Index p0 = reduced_[at(t.theta)];
    S.middleCols<3>(t.w_reduced).noalias() -= A_VP.middleCols<4>(p0) * TinvC;
  }
  lu_.compute(S);
  // PartialPivLU does not report singularity: check the pivots (U's diagonal).
  for (Eigen::Index i = 0; i < nv; ++i) {
    const double pivot = lu_.matrixLU()(i, i);
    if (!(pivot != 0.0) || !std::isfinite(pivot)) return false;
  }
  return true;
}

void NewtonMatrixSolver::solve(double* x) const {
  // z_P = A_PP⁻¹ b_P
  for (std::size_t j = 0; j < position_.size(); ++j)
    z_P_(static_cast<Eigen::Index>(j)) = x[position_[j]];
  for (const ThetaBlock& t : thetas_) {
    const Eigen::Index p0 = reduced_[at(t.theta)];
    z_P_.segment<4>(p0) = t.T_inverse * z_P_.segment<4>(p0);
  }
  // x_V = S⁻¹ (b_V − A_VP z_P)
  for (std::size_t i = 0; i < velocity_.size(); ++i)
    x_V_(static_cast<Eigen::Index>(i)) = x[velocity_[i]];
  x_V_.noalias() -= A_VP * z_P_;
  rhs_V_ = x_V_;
  x_V_.noalias() = lu_.solve(rhs_V_);
  for (std::size_t i = 0; i < velocity_.size(); ++i)
    x[velocity_[i]] = x_V_(static_cast<Eigen::Index>(i));
  // x_P = z_P − A_PP⁻¹ A_PV x_V
  for (const ScalarPair& p : pairs_) {
    x[p.position] = z_P_(reduced_[at(p.position)]) - p.c * x_V_(p.velocity_reduced);
  }
  for (const ThetaBlock& t : thetas_) {
    const Eigen::Index p0 = reduced_[at(t.theta)];
    const Eigen::Vector4d x_theta =
        z_P_.segment<4>(p0) - t.T_inverse * (t.C * x_V_.segment<3>(t.w_reduced));
    for (int m = 0; m < 4; ++m) x[t.theta + m] = x_theta(m);
  }
  // x_W = (b_W − A_WP x_P − A_WV x_V) / A_WW
  for (int k = 0; k < integrals_; ++k) {
    double r = x[work_ + k];
    for (std::size_t j = 0; j < position_.size(); ++j)
      r -= A_WP(k, static_cast<Eigen::Index>(j)) * x[position_[j]];
    r -= A_WV.row(k).dot(x_V_);
    x[work_ + k] = r / A_WW(k);
  }
}

}  // namespace flexref::reference
