#include "scene/nodal_mass_lumping.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace flexref::scene {
namespace {

using RowFunction = std::function<void(Eigen::Index k, Eigen::Ref<Eigen::VectorXd> a)>;

/// Nodes per block of the Gram-matrix accumulation (a matrix product per block).
constexpr Eigen::Index kBlock = 256;

/// The ten moment functions (1, y, y_a y_b for a ≤ b) at y.
void moment_row(const Eigen::Vector3d& y, Eigen::Ref<Eigen::VectorXd> a) {
  a(0) = 1.0;
  a.segment<3>(1) = y;
  a(4) = y(0) * y(0);
  a(5) = y(0) * y(1);
  a(6) = y(0) * y(2);
  a(7) = y(1) * y(1);
  a(8) = y(1) * y(2);
  a(9) = y(2) * y(2);
}

/// The same moments of a distribution with properties p in coordinates y = (x − c)/ℓ.
Eigen::VectorXd moment_target(const MassProperties& p, const Eigen::Vector3d& c, double l) {
  const Eigen::Vector3d s = (p.s0 - p.mass * c) / l;
  const Eigen::Matrix3d J =
      (p.J0 - p.s0 * c.transpose() - c * p.s0.transpose() + p.mass * c * c.transpose()) / (l * l);
  Eigen::VectorXd b(10);
  b << p.mass, s(0), s(1), s(2), J(0, 0), J(0, 1), J(0, 2), J(1, 1), J(1, 2), J(2, 2);
  return b;
}

/// Centre and size of the initial distribution: the coordinates of the constraint rows.
void frame_of(const Eigen::VectorXd& m, const Eigen::Matrix3Xd& x, Eigen::Vector3d& c, double& l) {
  c = x * m / m.sum();
  l = 0.0;
  for (Eigen::Index k = 0; k < x.cols(); ++k) l = std::max(l, (x.col(k) - c).norm());
  if (!(l > 0.0)) l = 1.0;
}

/// min Σ (m − m⁰)²/m⁰ subject to Σ_k m_k a_k = b (a_k from `rows`), see the header.
Eigen::VectorXd matched(const Eigen::VectorXd& initial, Eigen::Index c, const RowFunction& rows,
                        const Eigen::VectorXd& b, const Eigen::Matrix3Xd& x) {
  const Eigen::Index n = initial.size();
  if (!(initial.minCoeff() > 0.0)) {
    throw std::invalid_argument("the initial masses must be positive");
  }
  const auto accumulate = [&](const Eigen::VectorXd& m, const Eigen::VectorXd* weights,
                              Eigen::MatrixXd* G) {
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(c);
    Eigen::MatrixXd A(c, kBlock);
    for (Eigen::Index start = 0; start < n; start += kBlock) {
      const Eigen::Index size = std::min(kBlock, n - start);
      for (Eigen::Index j = 0; j < size; ++j) rows(start + j, A.col(j));
      sum += A.leftCols(size) * m.segment(start, size);
      if (G != nullptr) {
        const auto block = A.leftCols(size);
        G->noalias() += block * weights->segment(start, size).asDiagonal() * block.transpose();
      }
    }
    return sum;
  };
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(c, c);
  const Eigen::VectorXd residual0 = b - accumulate(initial, &initial, &G);
  // Row scale: Cauchy–Schwarz bound of |Σ m a_i| = √(G_ii Σ m).
  const Eigen::VectorXd scale = (G.diagonal() * initial.sum()).cwiseSqrt();
  Eigen::VectorXd d(c);
  for (Eigen::Index i = 0; i < c; ++i) d(i) = G(i, i) > 0.0 ? 1.0 / std::sqrt(G(i, i)) : 0.0;
  const Eigen::MatrixXd Gs = d.asDiagonal() * G * d.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Gs);
  // Pseudo-inverse: dependent rows (e.g. moments that a symmetric mesh's modes share) have
  // eigenvalues at rounding level of the unit-diagonal Gs.
  const double cut = 1e-15 * eig.eigenvalues().cwiseAbs().maxCoeff() * static_cast<double>(c);
  Eigen::VectorXd inverse = eig.eigenvalues();
  for (Eigen::Index i = 0; i < c; ++i) inverse(i) = inverse(i) > cut ? 1.0 / inverse(i) : 0.0;
  const auto solve = [&](const Eigen::VectorXd& r) -> Eigen::VectorXd {
    return d.asDiagonal() *
           (eig.eigenvectors() *
            (inverse.asDiagonal() * (eig.eigenvectors().transpose() * (d.asDiagonal() * r))));
  };
  Eigen::VectorXd m = initial;
  Eigen::VectorXd residual = residual0;
  Eigen::VectorXd a(c);
  for (int round = 0; round < 2; ++round) {  // the second round removes the first's rounding
    const Eigen::VectorXd lambda = solve(residual);
    for (Eigen::Index k = 0; k < n; ++k) {
      rows(k, a);
      m(k) += initial(k) * a.dot(lambda);
    }
    residual = b - accumulate(m, nullptr, nullptr);
  }
  for (Eigen::Index i = 0; i < c; ++i) {
    // Met to rounding of an ill-conditioned system (smooth mode shapes sampled at the nodes make
    // the modal rows nearly dependent): 1e-8 of the row's scale, a hundred times below the
    // .frd's own 6-digit rounding of the shapes behind the targets.
    const double tolerance = 1e-8 * std::max(scale(i), std::abs(b(i)));
    if (!(std::abs(residual(i)) <= tolerance)) {
      std::ostringstream msg;
      msg << "the " << c << " constraints cannot all be met by " << n
          << " nodal masses (constraint " << i << " is left with a relative residual "
          << std::abs(residual(i)) / std::max(scale(i), std::abs(b(i)))
          << "): more constraints than the nodes can carry";
      throw std::invalid_argument(msg.str());
    }
  }
  Eigen::Index worst = 0;
  if (!(m.minCoeff(&worst) > 0.0)) {
    std::ostringstream msg;
    msg << "matching the constraints would give the node at (" << x(0, worst) << ", " << x(1, worst)
        << ", " << x(2, worst) << ") the mass " << m(worst) << " <= 0";
    throw std::invalid_argument(msg.str());
  }
  return m;
}

double frobenius_sum(const std::array<Eigen::MatrixXd, 9>& a,
                     const std::array<Eigen::MatrixXd, 9>& b) {
  double s = 0.0;
  for (std::size_t i = 0; i < 9; ++i) s += (a[i] - b[i]).squaredNorm();
  return std::sqrt(s);
}

}  // namespace

Eigen::Matrix3d MassProperties::I0() const { return J0.trace() * Eigen::Matrix3d::Identity() - J0; }

double MassPropertyDifference::max() const { return std::max({mass, first_moment, inertia}); }

MassPropertyDifference relative_difference(const MassProperties& a, const MassProperties& b) {
  MassPropertyDifference d;
  d.mass = std::abs(b.mass - a.mass) / a.mass;
  const double gyration = std::sqrt(a.J0.trace() / a.mass);
  d.first_moment = (b.s0 - a.s0).norm() / (a.mass * gyration);
  d.inertia = (b.I0() - a.I0()).norm() / a.I0().norm();
  return d;
}

double InvariantDifference::max_linear() const { return std::max({rigid.max(), S, X, m_ff}); }

InvariantDifference relative_difference(const LinearInvariants& a, const LinearInvariants& b) {
  InvariantDifference d;
  d.rigid = relative_difference(a.rigid, b.rigid);
  const double modal = a.m_ff.trace();
  d.S = (b.S - a.S).norm() / std::sqrt(a.rigid.mass * modal);
  d.X = (b.X - a.X).norm() / std::sqrt(a.rigid.J0.trace() * modal);
  d.m_ff = (b.m_ff - a.m_ff).norm() / modal;
  d.P = frobenius_sum(a.P, b.P) / modal;
  return d;
}

MassProperties nodal_mass_properties(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& x) {
  MassProperties p;
  for (Eigen::Index k = 0; k < mass.size(); ++k) {
    p.mass += mass(k);
    p.s0 += mass(k) * x.col(k);
    p.J0 += mass(k) * x.col(k) * x.col(k).transpose();
  }
  return p;
}

LinearInvariants nodal_invariants(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& x,
                                  const Eigen::MatrixXd& phi) {
  const Eigen::Index n = phi.cols();
  LinearInvariants v;
  v.rigid = nodal_mass_properties(mass, x);
  v.S = Eigen::MatrixXd::Zero(3, n);
  v.X = Eigen::MatrixXd::Zero(9, n);
  v.m_ff = Eigen::MatrixXd::Zero(n, n);
  for (auto& P : v.P) P = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index k = 0; k < mass.size(); ++k) {
    const auto rows = phi.middleRows<3>(3 * k);
    v.S += mass(k) * rows;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        v.X.row(3 * a + b) += mass(k) * x(a, k) * rows.row(b);
        v.P[static_cast<std::size_t>(3 * a + b)] += mass(k) * rows.row(a).transpose() * rows.row(b);
      }
    }
  }
  v.m_ff = v.P[0] + v.P[4] + v.P[8];
  return v;
}

Eigen::SparseMatrix<double> scalar_mass_matrix(const Eigen::SparseMatrix<double>& M,
                                               double& anisotropy) {
  const Eigen::Index n = M.rows() / 3;
  std::vector<Eigen::Triplet<double>> entries;
  double largest = 0.0;
  for (int c = 0; c < M.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(M, c); it; ++it) {
      largest = std::max(largest, std::abs(it.value()));
      if (it.row() % 3 == 0 && it.col() % 3 == 0) {
        entries.emplace_back(it.row() / 3, it.col() / 3, it.value());
      }
    }
  }
  Eigen::SparseMatrix<double> M0(n, n);
  M0.setFromTriplets(entries.begin(), entries.end());
  // M − M0 ⊗ I₃ entry by entry.
  double defect = 0.0;
  for (int c = 0; c < M.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(M, c); it; ++it) {
      const double expected =
          it.row() % 3 == it.col() % 3 ? M0.coeff(it.row() / 3, it.col() / 3) : 0.0;
      defect = std::max(defect, std::abs(it.value() - expected));
    }
  }
  for (int c = 0; c < M0.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(M0, c); it; ++it) {
      for (int a = 1; a < 3; ++a) {
        defect =
            std::max(defect, std::abs(M.coeff(3 * it.row() + a, 3 * it.col() + a) - it.value()));
      }
    }
  }
  anisotropy = largest > 0.0 ? defect / largest : 0.0;
  return M0;
}

LinearInvariants consistent_invariants(const Eigen::SparseMatrix<double>& M0,
                                       const Eigen::Matrix3Xd& x, const Eigen::MatrixXd& phi) {
  const Eigen::Index N = x.cols();
  const Eigen::Index n = phi.cols();
  // Direction rows of Φ as N×n matrices, and the positions as N×3.
  std::array<Eigen::MatrixXd, 3> Phi;
  for (int a = 0; a < 3; ++a) {
    Phi[static_cast<std::size_t>(a)].resize(N, n);
    for (Eigen::Index k = 0; k < N; ++k) {
      Phi[static_cast<std::size_t>(a)].row(k) = phi.row(3 * k + a);
    }
  }
  const Eigen::MatrixXd X = x.transpose();
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(N);
  const Eigen::VectorXd M0_1 = M0 * ones;
  const Eigen::MatrixXd M0_X = M0 * X;
  LinearInvariants v;
  v.rigid.mass = ones.dot(M0_1);
  v.rigid.s0 = X.transpose() * M0_1;
  v.rigid.J0 = X.transpose() * M0_X;
  v.rigid.J0 = 0.5 * (v.rigid.J0 + v.rigid.J0.transpose()).eval();
  v.S.resize(3, n);
  v.X.resize(9, n);
  for (int b = 0; b < 3; ++b) {
    const Eigen::MatrixXd M0_Phi = M0 * Phi[static_cast<std::size_t>(b)];
    v.S.row(b) = M0_1.transpose() * Phi[static_cast<std::size_t>(b)];
    for (int a = 0; a < 3; ++a) {
      v.X.row(3 * a + b) = X.col(a).transpose() * M0_Phi;
      v.P[static_cast<std::size_t>(3 * a + b)] =
          Phi[static_cast<std::size_t>(a)].transpose() * M0_Phi;
    }
  }
  v.m_ff = v.P[0] + v.P[4] + v.P[8];
  v.m_ff = 0.5 * (v.m_ff + v.m_ff.transpose()).eval();
  return v;
}

Eigen::VectorXd diagonal_scaled_masses(const Eigen::VectorXd& M0_diagonal, double total_mass) {
  const Eigen::VectorXd& m = M0_diagonal;
  if (!(m.minCoeff() > 0.0)) {
    throw std::invalid_argument(
        "the mass matrix has a node without mass on its diagonal (an unattached node?)");
  }
  return m * (total_mass / m.sum());
}

Eigen::VectorXd masses_on_nearest(const Eigen::VectorXd& mass, const Eigen::Matrix3Xd& x,
                                  const std::vector<int>& kept) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(kept.size()));
  for (Eigen::Index k = 0; k < x.cols(); ++k) {
    std::size_t best = 0;
    double best_distance = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < kept.size(); ++j) {
      const double d = (x.col(kept[j]) - x.col(k)).squaredNorm();
      if (d < best_distance) {
        best_distance = d;
        best = j;
      }
    }
    out(static_cast<Eigen::Index>(best)) += mass(k);
  }
  return out;
}

Eigen::VectorXd moment_matched_masses(const Eigen::VectorXd& initial, const Eigen::Matrix3Xd& x,
                                      const MassProperties& target) {
  if (x.cols() != initial.size() || initial.size() == 0) {
    throw std::invalid_argument("moment_matched_masses: sizes");
  }
  if (initial.size() < 4) {
    throw std::invalid_argument("fewer than four nodes cannot carry a solid's inertia");
  }
  Eigen::Vector3d c;
  double l = 0.0;
  frame_of(initial, x, c, l);
  // Nodes on a plane or a line have no second moment across it: no masses can match a solid's.
  Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
  for (Eigen::Index k = 0; k < x.cols(); ++k) {
    const Eigen::Vector3d y = (x.col(k) - c) / l;
    spread += initial(k) * y * y.transpose();
  }
  if (!(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(spread).eigenvalues()(0) >
        1e-12 * initial.sum())) {
    throw std::invalid_argument(
        "the kept nodes lie on one plane (or line): they cannot carry the solid's second "
        "moments; keep nodes off that plane");
  }
  try {
    return matched(
        initial, 10,
        [&](Eigen::Index k, Eigen::Ref<Eigen::VectorXd> a) { moment_row((x.col(k) - c) / l, a); },
        moment_target(target, c, l), x);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(
        std::string("the kept nodes cannot carry the solid's mass, first and second moments "
                    "with positive masses (") +
        e.what() + "); keep more nodes, spread through the solid");
  }
}

std::string InvariantSelection::describe() const {
  std::string out = "m, s0, J0";
  if (full_modal_mass) {
    out += ", m_ff";
  } else if (modal_masses) {
    out += ", diag(m_ff)";
  }
  if (first_moment) out += ", S";
  if (position_moment) out += ", X";
  return out;
}

std::vector<InvariantSelection> invariant_selections() {
  return {{true, true, true, true},
          {true, false, true, true},
          {true, false, true, false},
          {true, false, false, false},
          {false, false, false, false}};
}

Eigen::VectorXd invariant_matched_masses(const Eigen::VectorXd& initial, const Eigen::Matrix3Xd& x,
                                         const Eigen::MatrixXd& phi, const LinearInvariants& target,
                                         const InvariantSelection& selection) {
  const Eigen::Index N = initial.size();
  const Eigen::Index n = phi.cols();
  if (x.cols() != N || phi.rows() != 3 * N) {
    throw std::invalid_argument("invariant_matched_masses: sizes");
  }
  if (N < 4) throw std::invalid_argument("fewer than four nodes cannot carry a solid's inertia");
  const bool any_modal = selection.modal_masses || selection.full_modal_mass;
  const Eigen::Index n_mass = selection.full_modal_mass ? n * (n + 1) / 2 : (any_modal ? n : 0);
  const Eigen::Index c =
      10 + n_mass + (selection.first_moment ? 3 * n : 0) + (selection.position_moment ? 9 * n : 0);
  if (c >= N) {
    throw std::invalid_argument(std::to_string(c) + " constraints need more than the " +
                                std::to_string(N) + " nodes");
  }
  Eigen::Vector3d centre;
  double l = 0.0;
  frame_of(initial, x, centre, l);
  // Shapes scaled to O(1) entries: Φ ~ 1/√(modal mass) per unit q.
  const double sigma = std::sqrt(target.m_ff.trace() > 0.0
                                     ? initial.sum() * static_cast<double>(n) / target.m_ff.trace()
                                     : 1.0);
  const auto pairs = [&](Eigen::Index i) { return selection.full_modal_mass ? n : i + 1; };
  const auto rows = [&](Eigen::Index k, Eigen::Ref<Eigen::VectorXd> a) {
    const Eigen::Vector3d y = (x.col(k) - centre) / l;
    moment_row(y, a.head(10));
    const auto f = phi.middleRows<3>(3 * k);
    Eigen::Index r = 10;
    if (any_modal) {
      for (Eigen::Index i = 0; i < n; ++i) {
        for (Eigen::Index j = i; j < pairs(i); ++j) a(r++) = sigma * sigma * f.col(i).dot(f.col(j));
      }
    }
    for (int b = 0; selection.first_moment && b < 3; ++b) {
      a.segment(r, n) = sigma * f.row(b).transpose();
      r += n;
    }
    for (int ai = 0; selection.position_moment && ai < 3; ++ai) {
      for (int b = 0; b < 3; ++b) {
        a.segment(r, n) = sigma * y(ai) * f.row(b).transpose();
        r += n;
      }
    }
  };
  Eigen::VectorXd b(c);
  b.head(10) = moment_target(target.rigid, centre, l);
  Eigen::Index r = 10;
  if (any_modal) {
    for (Eigen::Index i = 0; i < n; ++i) {
      for (Eigen::Index j = i; j < pairs(i); ++j) b(r++) = sigma * sigma * target.m_ff(i, j);
    }
  }
  for (int bi = 0; selection.first_moment && bi < 3; ++bi) {
    b.segment(r, n) = sigma * target.S.row(bi).transpose();
    r += n;
  }
  for (int ai = 0; selection.position_moment && ai < 3; ++ai) {
    for (int bi = 0; bi < 3; ++bi) {
      // Σ m y_a Φ_b = (X_ab − c_a S_b)/ℓ.
      b.segment(r, n) =
          sigma * (target.X.row(3 * ai + bi) - centre(ai) * target.S.row(bi)).transpose() / l;
      r += n;
    }
  }
  return matched(initial, c, rows, b, x);
}

}  // namespace flexref::scene
