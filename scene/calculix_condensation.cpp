#include "scene/calculix_condensation.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <stdexcept>
#include <string>

namespace flexref::scene {
namespace {

/// A(rows, cols) of a sparse matrix; `position` maps a row or column of A to its place in the
/// list, −1 when not selected.
Eigen::SparseMatrix<double> select(const Eigen::SparseMatrix<double>& A,
                                   const std::vector<int>& row_position, int n_rows,
                                   const std::vector<int>& col_position, int n_cols) {
  std::vector<Eigen::Triplet<double>> entries;
  for (int c = 0; c < A.outerSize(); ++c) {
    const int j = col_position[static_cast<std::size_t>(c)];
    if (j < 0) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
      const int i = row_position[static_cast<std::size_t>(it.row())];
      if (i >= 0) entries.emplace_back(i, j, it.value());
    }
  }
  Eigen::SparseMatrix<double> out(n_rows, n_cols);
  out.setFromTriplets(entries.begin(), entries.end());
  return out;
}

std::vector<int> positions(const std::vector<int>& list, int size) {
  std::vector<int> out(static_cast<std::size_t>(size), -1);
  for (std::size_t i = 0; i < list.size(); ++i)
    out[static_cast<std::size_t>(list[i])] = static_cast<int>(i);
  return out;
}

}  // namespace

CalculixCondensation::CalculixCondensation(const CalculixDofMap& map,
                                           const Eigen::SparseMatrix<double>& K,
                                           const Eigen::SparseMatrix<double>& M)
    : map_(&map), K_(&K), M_(&M) {
  for (int r = 0; r < rows(); ++r) {
    const CalculixRow kind = map.kind[static_cast<std::size_t>(r)];
    (kind == CalculixRow::kNode ? known_ : unknown_).push_back(r);
    if (kind == CalculixRow::kCondensed) condensed_.push_back(r);
  }
}

Eigen::MatrixXd CalculixCondensation::from_nodes(const Eigen::MatrixXd& at_nodes) const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(rows(), at_nodes.cols());
  for (const int r : known_) {
    const auto ur = static_cast<std::size_t>(r);
    out.row(r) = at_nodes.row(3 * map_->node[ur] + map_->direction[ur]);
  }
  return out;
}

Eigen::MatrixXd CalculixCondensation::static_fields(const Eigen::MatrixXd& at_nodes) const {
  Eigen::MatrixXd out = from_nodes(at_nodes);
  if (unknown_.empty()) return out;
  const std::vector<int> u = positions(unknown_, rows());
  const std::vector<int> o = positions(known_, rows());
  const auto nu = static_cast<int>(unknown_.size());
  const auto no = static_cast<int>(known_.size());
  const Eigen::SparseMatrix<double> K_uu = select(*K_, u, nu, u, nu);
  const Eigen::SparseMatrix<double> K_uo = select(*K_, u, nu, o, no);
  Eigen::MatrixXd f_o(no, out.cols());
  for (int i = 0; i < no; ++i) f_o.row(i) = out.row(known_[static_cast<std::size_t>(i)]);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(K_uu);
  if (solver.info() != Eigen::Success) {
    throw std::invalid_argument(
        "the stiffness matrix is singular on the " + std::to_string(nu) +
        " rows the .frd does not show (a degree of freedom without stiffness)");
  }
  const Eigen::MatrixXd rhs = -(K_uo * f_o);
  const Eigen::MatrixXd f_u = solver.solve(rhs);
  for (int i = 0; i < nu; ++i) out.row(unknown_[static_cast<std::size_t>(i)]) = f_u.row(i);
  return out;
}

Eigen::VectorXd CalculixCondensation::mode(const Eigen::VectorXd& at_nodes, double lambda) const {
  Eigen::VectorXd out = from_nodes(at_nodes);
  if (condensed_.empty()) return out;
  const std::vector<int> c = positions(condensed_, rows());
  const std::vector<int> o = positions(known_, rows());
  const auto nc = static_cast<int>(condensed_.size());
  const auto no = static_cast<int>(known_.size());
  const Eigen::SparseMatrix<double> A_cc =
      select(*K_, c, nc, c, nc) - lambda * select(*M_, c, nc, c, nc);
  const Eigen::SparseMatrix<double> A_co =
      select(*K_, c, nc, o, no) - lambda * select(*M_, c, nc, o, no);
  Eigen::VectorXd phi_o(no);
  for (int i = 0; i < no; ++i) phi_o(i) = out(known_[static_cast<std::size_t>(i)]);
  Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
  solver.compute(A_cc);
  if (solver.info() != Eigen::Success) {
    throw std::invalid_argument("K - lambda M is singular on the " + std::to_string(nc) +
                                " condensed rows at lambda = " + std::to_string(lambda));
  }
  const Eigen::VectorXd rhs = -(A_co * phi_o);
  const Eigen::VectorXd phi_c = solver.solve(rhs);
  for (int i = 0; i < nc; ++i) out(condensed_[static_cast<std::size_t>(i)]) = phi_c(i);
  return out;
}

}  // namespace flexref::scene
