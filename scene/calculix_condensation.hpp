#pragma once
/// \file calculix_condensation.hpp
/// Values at every row of ccx's matrices of fields that the .frd gives at its nodes
/// (docs/calculix.md, "Internal and expanded nodes"): rows of .frd nodes take the nodal value,
/// held rows (calculix_dof_map.hpp) are zero, and the condensed rows — the degrees of freedom
/// the .frd does not show — are solved from their own rows of the equations of motion:
///  - a mode with eigenvalue λ: (K − λM)_cc φ_c = −(K − λM)_co φ_o, the eigen-equation's own
///    rows, exact for an eigenvector (dynamic condensation; static/Guyan condensation, λ = 0,
///    would miss its inertia: φᵀMφ off by up to 5e-2 on a C3D8I bar, against 1e-6 here);
///  - a field of the free solid at rest (rigid motions, linear fields): K_uu f_u = −K_uo f_o
///    over the condensed and held rows u (static condensation). Rigid motions carry no force,
///    so this is exact at every row, and gives the held rows' value too; the bubble amplitudes
///    of incompatible modes vanish on linear fields (the patch test), so it returns 0 there.
/// Node-ordered vectors have 3N rows, 3k + a being direction a of .frd node k.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "scene/calculix_dof_map.hpp"

namespace flexref::scene {

class CalculixCondensation {
 public:
  /// `K`, `M`: ccx's stiffness and mass matrices (rows as in `map`). Throws
  /// std::invalid_argument when K has no stiffness on the condensed and held rows.
  CalculixCondensation(const CalculixDofMap& map, const Eigen::SparseMatrix<double>& K,
                       const Eigen::SparseMatrix<double>& M);

  int rows() const { return static_cast<int>(map_->kind.size()); }
  /// Fields of the solid at rest (columns), node-ordered → at every row.
  Eigen::MatrixXd static_fields(const Eigen::MatrixXd& at_nodes) const;
  /// A mode with eigenvalue λ, node-ordered → at every row. Throws std::invalid_argument when
  /// (K − λM) is singular on the condensed rows (λ at an eigenvalue of the condensed part).
  Eigen::VectorXd mode(const Eigen::VectorXd& at_nodes, double lambda) const;

 private:
  /// The rows of the .frd's nodes taken from a node-ordered vector (others 0).
  Eigen::MatrixXd from_nodes(const Eigen::MatrixXd& at_nodes) const;

  const CalculixDofMap* map_;
  const Eigen::SparseMatrix<double>* K_;
  const Eigen::SparseMatrix<double>* M_;
  std::vector<int> known_;      ///< rows of .frd nodes
  std::vector<int> unknown_;    ///< condensed and held rows
  std::vector<int> condensed_;  ///< condensed rows
};

}  // namespace flexref::scene
