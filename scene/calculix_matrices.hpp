#pragma once
/// \file calculix_matrices.hpp
/// Reads the stiffness and mass matrices that CalculiX stores for a step
/// `*FREQUENCY, SOLVER=MATRIXSTORAGE` (docs/calculix.md, "Files"): `JOB.sti` and `JOB.mas`
/// hold the upper triangle as "row column value" lines (1-based, 14 significant digits), and
/// `JOB.dof` names the degree of freedom of each row as "node.direction". The matrices are
/// those of the active degrees of freedom of that step: a step without boundary conditions
/// (`*BOUNDARY, OP=NEW`) gives the matrices of the free solid, whose rigid-body projection is
/// the solid's mass, first moment and inertia.
///
/// Every problem is a core::InputError naming the file and the line: a missing file (with the
/// deck keyword that writes it), a malformed line, an index outside the .dof list, an entry
/// given twice, a direction other than 1–3 (only solid elements are read). A node may be named
/// by several rows of the same direction: ccx names the rows of the solid nodes it expands a
/// shell or beam node into by that node (calculix_dof_map.hpp).
#include <Eigen/SparseCore>
#include <string>
#include <vector>

namespace flexref::scene {

struct CalculixMatrices {
  std::string dof_file;
  std::string mass_file;
  std::string stiffness_file;
  /// Per matrix row: the ccx node number and the direction 0, 1, 2 (x, y, z).
  std::vector<int> dof_node;
  std::vector<int> dof_direction;
  Eigen::SparseMatrix<double> mass;       ///< consistent mass matrix, symmetric (both triangles)
  Eigen::SparseMatrix<double> stiffness;  ///< stiffness matrix, symmetric (both triangles)
};

/// Reads `<base>.dof`, `<base>.mas` and `<base>.sti` (base: the job name with its folder,
/// without an extension). Throws core::InputError.
CalculixMatrices read_calculix_matrices(const std::string& base);

/// The degree-of-freedom list of a .dof file; throws core::InputError.
void read_calculix_dofs(const std::string& path, std::vector<int>& node,
                        std::vector<int>& direction);

/// A symmetric matrix of dimension `size` from a .sti or .mas file (upper or lower triangle
/// stored; both triangles returned). Throws core::InputError.
Eigen::SparseMatrix<double> read_calculix_matrix(const std::string& path, int size);

}  // namespace flexref::scene
