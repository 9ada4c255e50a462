#include "scene/calculix_import.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/error.hpp"
#include "scene/calculix_condensation.hpp"
#include "scene/calculix_dof_map.hpp"

namespace flexref::scene {
namespace {

constexpr double kRadPerCycle = 2.0 * std::numbers::pi;  // ω = 2π f
/// .dat eigenvalues and .frd 1PGK values both carry 7 significant digits (rounding ≤ 5e-7
/// relative each).
constexpr double kDatTolerance = 1e-6;

/// The rows of the .frd's nodes of a matrix, reordered so that row 3k + a is direction a of
/// .frd node k (rows the .frd does not show — bubble amplitudes, constrained expansions — left
/// out, and nodes without rows left empty).
Eigen::SparseMatrix<double> node_ordered(const CalculixDofMap& map,
                                         const Eigen::SparseMatrix<double>& A, int n_nodes) {
  const auto target = [&](Eigen::Index row) {
    const auto r = static_cast<std::size_t>(row);
    return map.kind[r] == CalculixRow::kNode ? 3 * map.node[r] + map.direction[r] : -1;
  };
  std::vector<Eigen::Triplet<double>> entries;
  for (int c = 0; c < A.outerSize(); ++c) {
    const int j = target(c);
    if (j < 0) continue;
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
      const int i = target(it.row());
      if (i >= 0) entries.emplace_back(i, j, it.value());
    }
  }
  Eigen::SparseMatrix<double> out(3 * n_nodes, 3 * n_nodes);
  out.setFromTriplets(entries.begin(), entries.end());
  return out;
}

/// The diagonal of M0 per .frd node, the starting point of the nodal masses. A node whose rows
/// are condensed (an expansion tied by ccx's constraints) has none: it takes the mean diagonal
/// of the other nodes of its owner, or of all nodes; the matching of the invariants then moves
/// it like any other.
Eigen::VectorXd node_diagonal(const Eigen::SparseMatrix<double>& M0, const CalculixDofMap& map) {
  const Eigen::Index n_nodes = M0.rows();
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n_nodes + static_cast<Eigen::Index>(map.added.size()));
  d.head(n_nodes) = M0.diagonal();
  std::map<int, std::pair<double, int>> by_owner;
  double sum = 0.0;
  int count = 0;
  for (Eigen::Index k = 0; k < n_nodes; ++k) {
    if (!(d(k) > 0.0)) continue;
    auto& [owner_sum, owner_count] = by_owner[map.owner[static_cast<std::size_t>(k)]];
    owner_sum += d(k);
    ++owner_count;
    sum += d(k);
    ++count;
  }
  for (Eigen::Index k = 0; k < n_nodes; ++k) {
    if (d(k) > 0.0 || count == 0) continue;
    const auto it = by_owner.find(map.owner[static_cast<std::size_t>(k)]);
    d(k) = it != by_owner.end() ? it->second.first / it->second.second : sum / count;
  }
  // An added shell or beam node starts with 2/3 of its expansion's mass, which keeps 1/3: the
  // split of a section's mass between its centre and its boundary that has its second moment
  // (t²/12 = (1/3)(t/2)²).
  std::map<int, std::vector<Eigen::Index>> expansion;
  for (const CalculixAddedNode& a : map.added) expansion[a.number];
  for (Eigen::Index k = 0; k < n_nodes; ++k) {
    const auto it = expansion.find(map.owner[static_cast<std::size_t>(k)]);
    if (it != expansion.end()) it->second.push_back(k);
  }
  for (std::size_t j = 0; j < map.added.size(); ++j) {
    double total = 0.0;
    for (const Eigen::Index k : expansion.at(map.added[j].number)) {
      total += d(k);
      d(k) /= 3.0;
    }
    d(n_nodes + static_cast<Eigen::Index>(j)) = 2.0 * total / 3.0;
  }
  return d;
}

/// m, s0 and J0 of the projection RᵀMR of the mass matrix on the six rigid fields R
/// (translations e_a, rotations e_b × x): its blocks are m I, C_ab = e_a·(e_b × s0) and
/// I0 = tr(J0) I − J0.
MassProperties rigid_projection(const Eigen::MatrixXd& RtMR) {
  MassProperties p;
  p.mass = RtMR.topLeftCorner<3, 3>().trace() / 3.0;
  const Eigen::Matrix3d C = RtMR.topRightCorner<3, 3>();
  p.s0 = 0.5 * Eigen::Vector3d(C(1, 2) - C(2, 1), C(2, 0) - C(0, 2), C(0, 1) - C(1, 0));
  const Eigen::Matrix3d I0 =
      0.5 * (RtMR.bottomRightCorner<3, 3>() + RtMR.bottomRightCorner<3, 3>().transpose());
  p.J0 = 0.5 * I0.trace() * Eigen::Matrix3d::Identity() - I0;
  return p;
}

/// L (3N×9): the linear fields x_a e_b at the nodes, column 3a + b.
Eigen::MatrixXd linear_fields(const Eigen::Matrix3Xd& x) {
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(3 * x.cols(), 9);
  for (Eigen::Index k = 0; k < x.cols(); ++k) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) L(3 * k + b, 3 * a + b) = x(a, k);
    }
  }
  return L;
}

Eigen::VectorXd flatten(const Eigen::Matrix3Xd& shape) {
  return Eigen::Map<const Eigen::VectorXd>(shape.data(), shape.size());
}

/// R (3N×6): translations e_a and linearized rotations e_b × x at every node.
Eigen::MatrixXd rigid_fields(const Eigen::Matrix3Xd& x) {
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(3 * x.cols(), 6);
  for (Eigen::Index k = 0; k < x.cols(); ++k) {
    R.block<3, 3>(3 * k, 0).setIdentity();
    for (int b = 0; b < 3; ++b) {
      R.block<3, 1>(3 * k, 3 + b) = Eigen::Vector3d::Unit(b).cross(x.col(k));
    }
  }
  return R;
}

void check_dat(const CalculixModes& frd, const std::vector<CalculixEigenvalueTable>& dat,
               std::size_t step_index) {
  const CalculixFrequencyStep& step = frd.steps[step_index];
  if (dat.size() != frd.steps.size()) {
    throw core::InputError(frd.file, 0, "",
                           "the .dat file lists " + std::to_string(dat.size()) +
                               " eigenvalue table(s), the .frd holds the modes of " +
                               std::to_string(frd.steps.size()) +
                               " frequency step(s): not the same run (or *NODE FILE missing "
                               "in a step)");
  }
  const CalculixEigenvalueTable& table = dat[step_index];
  if (table.eigenvalues.size() != step.modes.size()) {
    throw core::InputError(frd.file, step.modes.back().line, "",
                           "wrong mode count: the .dat's eigenvalue table (line " +
                               std::to_string(table.line) + ") lists " +
                               std::to_string(table.eigenvalues.size()) +
                               " modes, the .frd holds " + std::to_string(step.modes.size()) +
                               " mode shapes of step " + std::to_string(step.step));
  }
  double scale = 0.0;
  for (const CalculixMode& m : step.modes) scale = std::max(scale, std::abs(m.eigenvalue));
  for (std::size_t i = 0; i < step.modes.size(); ++i) {
    const double a = table.eigenvalues[i];
    const double b = step.modes[i].eigenvalue;
    // Rigid-body eigenvalues are rounding noise of order 1e-12 λ_max (ccx writes 0 to the .frd
    // for a negative one): compared in absolute terms below 1e-9 λ_max.
    if (std::abs(a - b) > kDatTolerance * std::max(std::abs(a), std::abs(b)) + 1e-9 * scale) {
      std::ostringstream msg;
      msg << "mode " << step.modes[i].number << ": eigenvalue " << b << " in the .frd, " << a
          << " in the .dat (line " << table.line << "'s table): not the same run";
      throw core::InputError(frd.file, step.modes[i].line, "", msg.str());
    }
  }
}

std::string number(double x, int precision = 6) {
  std::ostringstream s;
  s.precision(precision);
  s << x;
  return s.str();
}

}  // namespace

CalculixImport import_calculix_modes(const CalculixModes& frd, const CalculixMatrices& matrices,
                                     const std::vector<CalculixEigenvalueTable>* dat,
                                     const CalculixImportOptions& options,
                                     const CalculixDeck* deck) {
  if (options.frequency_step < 1 || options.frequency_step > static_cast<int>(frd.steps.size())) {
    throw core::InputError(frd.file, 0, "",
                           "frequency step " + std::to_string(options.frequency_step) +
                               " requested; the file holds " + std::to_string(frd.steps.size()) +
                               " frequency step(s)");
  }
  if (!(options.frequency_tolerance > 0.0) || !(options.rigid_tolerance > 0.0)) {
    throw std::invalid_argument("import-modes: tolerances must be positive");
  }
  const auto step_index = static_cast<std::size_t>(options.frequency_step - 1);
  if (dat != nullptr) check_dat(frd, *dat, step_index);
  const CalculixFrequencyStep& step = frd.steps[step_index];
  const Eigen::Matrix3Xd& x = frd.positions;
  const auto n_nodes = static_cast<int>(x.cols());

  CalculixImport result;
  result.frequency_step = step.step;
  result.total_nodes = n_nodes;  // the .frd's; shell and beam nodes added below
  result.frequency_tolerance = options.frequency_tolerance;

  // 1–2: the rows of the matrices at the .frd's nodes (and those it does not show); the scalar
  // mass matrix of the nodes.
  const CalculixDofMap map = map_calculix_dofs(frd, matrices, deck);
  result.dof_map = map;
  const Eigen::SparseMatrix<double>& M = matrices.mass;
  const Eigen::SparseMatrix<double>& K = matrices.stiffness;
  const Eigen::SparseMatrix<double> M0 =
      scalar_mass_matrix(node_ordered(map, M, n_nodes), result.anisotropy);
  if (!(result.anisotropy <= kAnisotropyTolerance)) {
    throw core::InputError(matrices.mass_file, 0, "",
                           "the mass matrix is not the same in the three directions (defect " +
                               number(result.anisotropy) +
                               "): only solid elements (C3D...) are read");
  }
  const auto condensation = [&]() {
    try {
      return CalculixCondensation(map, K, M);
    } catch (const std::invalid_argument& e) {
      throw core::InputError(matrices.stiffness_file, 0, "", e.what());
    }
  }();

  // Rigid fields at every row. They carry no force in the free solid: K R = 0 must hold at the
  // .frd's nodes with their positions (else the rows are not those nodes), and the rows of
  // nodes ccx adds inside elements must stay at rest (bubble amplitudes; a node of another mesh
  // would move with the solid).
  const Eigen::MatrixXd R_nodes = rigid_fields(x);
  const Eigen::MatrixXd R = [&]() {
    try {
      return condensation.static_fields(R_nodes);
    } catch (const std::invalid_argument& e) {
      throw core::InputError(matrices.stiffness_file, 0, "", e.what());
    }
  }();
  {
    const double scale = R.cwiseAbs().maxCoeff();
    double internal = 0.0;
    for (const int r : map.internal) internal = std::max(internal, R.row(r).cwiseAbs().maxCoeff());
    if (internal > kInternalRigidTolerance * scale) {
      std::vector<int> moving;
      for (const int r : map.internal) {
        const int id = matrices.dof_node[static_cast<std::size_t>(r)];
        if (R.row(r).cwiseAbs().maxCoeff() > kInternalRigidTolerance * scale &&
            (moving.empty() || moving.back() != id)) {
          moving.push_back(id);
        }
      }
      std::string first;
      for (std::size_t i = 0; i < moving.size() && i < 5; ++i) {
        first += (i ? ", " : "") + std::to_string(moving[i]);
      }
      throw core::InputError(
          matrices.dof_file, 0, "",
          "the matrices and the modes come from different meshes: " +
              std::to_string(moving.size()) + " nodes of the matrices that are not in " + frd.file +
              " (" + first + (moving.size() > 5 ? ", …" : "") +
              ") move with the solid's rigid motions (up to " + number(internal / scale) +
              " of the nodes' motion), so they are not bubble amplitudes of incompatible-mode "
              "elements (those stay at rest) but nodes of another mesh; " +
              frd.file + " has " + std::to_string(n_nodes) + " nodes, the matrices " +
              std::to_string(matrices.dof_node.size()) + " rows");
    }
    double K_max = 0.0;
    for (int c = 0; c < K.outerSize(); ++c) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) {
        K_max = std::max(K_max, std::abs(it.value()));
      }
    }
    result.rigid_force = (K * R).cwiseAbs().maxCoeff() / (K_max * scale);
    if (!(result.rigid_force <= kRigidForceTolerance)) {
      throw core::InputError(
          matrices.dof_file, 0, "",
          "a rigid motion of the nodes at their positions in " + frd.file +
              " is not free with the stiffness matrix " + matrices.stiffness_file +
              " (largest force " + number(result.rigid_force) +
              " of max|K| max|R|): the rows of the matrices are not those nodes (different "
              "meshes, or the deck's shell or beam nodes are not this model's)");
    }
  }
  const Eigen::MatrixXd MR = M * R;
  const Eigen::MatrixXd RtMR = R.transpose() * MR;
  const Eigen::LDLT<Eigen::MatrixXd> rigid_mass(RtMR);

  // 3: the modes at every row; rigid-body modes.
  const auto eigenvalue = [](const CalculixMode& mode) {
    return mode.frequency_hz > 0.0 ? std::pow(kRadPerCycle * mode.frequency_hz, 2)
                                   : mode.eigenvalue;
  };
  std::vector<Eigen::VectorXd> rows_of_mode;
  std::vector<const CalculixMode*> elastic;
  std::vector<Eigen::VectorXd> elastic_rows;
  Eigen::MatrixXd rigid_span(condensation.rows(),
                             0);  // exact rigid motions nearest the rigid modes
  Eigen::MatrixXd rigid_span_nodes(3 * n_nodes, 0);
  for (const CalculixMode& mode : step.modes) {
    Eigen::VectorXd phi;
    try {
      phi = condensation.mode(flatten(mode.shape), eigenvalue(mode));
    } catch (const std::invalid_argument& e) {
      throw core::InputError(frd.file, mode.line, "",
                             "mode " + std::to_string(mode.number) +
                                 ": cannot recover the rows the .frd does not show: " + e.what());
    }
    const double norm2 = phi.dot(M * phi);
    if (!(norm2 > 0.0)) {
      throw core::InputError(frd.file, mode.line, "",
                             "mode " + std::to_string(mode.number) +
                                 " has no kinetic energy with the mass matrix (zero shape)");
    }
    const Eigen::VectorXd c = rigid_mass.solve(MR.transpose() * phi);
    const double rigid_part = c.dot(MR.transpose() * phi);
    const double distance = std::sqrt(std::max(0.0, 1.0 - rigid_part / norm2));
    if (distance < options.rigid_tolerance) {
      result.rigid_modes.push_back({mode.number, mode.eigenvalue, distance});
      rigid_span.conservativeResize(Eigen::NoChange, rigid_span.cols() + 1);
      rigid_span.col(rigid_span.cols() - 1) = R * c;
      rigid_span_nodes.conservativeResize(Eigen::NoChange, rigid_span_nodes.cols() + 1);
      rigid_span_nodes.col(rigid_span_nodes.cols() - 1) = R_nodes * c;
    } else {
      elastic.push_back(&mode);
      elastic_rows.push_back(std::move(phi));
    }
  }
  if (elastic.empty()) {
    throw core::InputError(frd.file, step.modes.back().line, "",
                           "step " + std::to_string(step.step) +
                               " has no elastic mode (all are rigid-body modes): request more "
                               "modes in *FREQUENCY");
  }

  // Mode selection (1-based among the elastic modes).
  std::vector<const CalculixMode*> kept;
  if (options.modes.empty()) {
    kept = elastic;
  } else {
    for (const int i : options.modes) {
      if (i < 1 || i > static_cast<int>(elastic.size())) {
        throw core::InputError(
            frd.file, step.modes.back().line, "",
            "wrong mode count: elastic mode " + std::to_string(i) + " selected, but step " +
                std::to_string(step.step) + " has " + std::to_string(elastic.size()) +
                " elastic modes (ccx modes " + std::to_string(elastic.front()->number) + "-" +
                std::to_string(elastic.back()->number) + ", after " +
                std::to_string(result.rigid_modes.size()) + " rigid-body modes)");
      }
      kept.push_back(elastic[static_cast<std::size_t>(i - 1)]);
    }
  }
  const auto n_modes = static_cast<int>(kept.size());

  // Exact M-orthogonality to the rigid motions spanned by the rigid modes, at every row and at
  // the nodes alike (the correction is a rigid motion).
  Eigen::MatrixXd phi_rows(condensation.rows(), n_modes);
  Eigen::MatrixXd phi(3 * n_nodes, n_modes);
  for (int i = 0; i < n_modes; ++i) {
    const auto k = static_cast<std::size_t>(
        std::find(elastic.begin(), elastic.end(), kept[static_cast<std::size_t>(i)]) -
        elastic.begin());
    phi_rows.col(i) = elastic_rows[k];
    phi.col(i) = flatten(kept[static_cast<std::size_t>(i)]->shape);
  }
  if (rigid_span.cols() > 0) {
    const Eigen::MatrixXd MS = M * rigid_span;
    const Eigen::MatrixXd coefficients =
        (rigid_span.transpose() * MS).ldlt().solve(MS.transpose() * phi_rows);
    const Eigen::MatrixXd correction = rigid_span * coefficients;
    for (int i = 0; i < n_modes; ++i) {
      const double size = std::sqrt(phi_rows.col(i).dot(M * phi_rows.col(i)));
      const double change = std::sqrt(correction.col(i).dot(M * correction.col(i)));
      result.rigid_orthogonalization = std::max(result.rigid_orthogonalization, change / size);
    }
    phi_rows -= correction;
    phi -= rigid_span_nodes * coefficients;
  }

  // 4: Rayleigh quotients against ccx's eigenvalues.
  const Eigen::MatrixXd Mphi = M * phi_rows;
  const Eigen::MatrixXd Kphi = K * phi_rows;
  std::vector<double> lambda(static_cast<std::size_t>(n_modes));
  std::vector<double> consistent(static_cast<std::size_t>(n_modes));
  for (int i = 0; i < n_modes; ++i) {
    const CalculixMode& mode = *kept[static_cast<std::size_t>(i)];
    const auto ui = static_cast<std::size_t>(i);
    lambda[ui] = eigenvalue(mode);
    consistent[ui] = phi_rows.col(i).dot(Mphi.col(i));
    CalculixModeCheck check;
    check.ccx_mode = mode.number;
    check.omega_ccx = std::sqrt(std::max(lambda[ui], 0.0));
    check.consistent_modal_mass = consistent[ui];
    check.rayleigh_difference =
        phi_rows.col(i).dot(Kphi.col(i)) / (consistent[ui] * lambda[ui]) - 1.0;
    if (!(std::abs(consistent[ui] - 1.0) <= kModalMassTolerance)) {
      throw core::InputError(frd.file, mode.line, "",
                             "mode " + std::to_string(mode.number) + " has the modal mass " +
                                 number(consistent[ui], 9) + " with the mass matrix " +
                                 matrices.mass_file +
                                 "; ccx scales its modes to 1 with its own mass matrix: the "
                                 "matrices and the modes come from different models");
    }
    if (!(lambda[ui] > 0.0) || !(std::abs(check.rayleigh_difference) <= kRayleighTolerance)) {
      throw core::InputError(
          frd.file, mode.line, "",
          "mode " + std::to_string(mode.number) + ": its strain energy with the stiffness matrix " +
              matrices.stiffness_file +
              " gives omega^2 = " + number(phi_rows.col(i).dot(Kphi.col(i)) / consistent[ui]) +
              ", ccx's eigenvalue is " + number(lambda[ui]) + " (relative difference " +
              number(check.rayleigh_difference) + " > " + number(kRayleighTolerance) +
              "): the matrices and the modes come from different models (or the modes are "
              "those of a prestressed step, whose stiffness includes a geometric stiffness the "
              "stored matrices lack: docs/calculix.md)");
    }
    result.modes.push_back(check);
  }

  // 5: nodal masses on the kept nodes: the .frd's and the shell or beam nodes added back, which
  // move as ccx defines them from their expansions.
  const auto n_added = static_cast<int>(map.added.size());
  const int n_body = n_nodes + n_added;
  Eigen::Matrix3Xd x_body(3, n_body);
  x_body.leftCols(n_nodes) = x;
  Eigen::MatrixXd phi_body = Eigen::MatrixXd::Zero(3 * n_body, n_modes);
  phi_body.topRows(3 * n_nodes) = phi;
  std::vector<int> body_numbers(frd.node_ids.begin(), frd.node_ids.end());
  std::vector<std::string> body_names = map.names;
  for (int j = 0; j < n_added; ++j) {
    const CalculixAddedNode& a = map.added[static_cast<std::size_t>(j)];
    x_body.col(n_nodes + j) = a.position;
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
      phi_body.middleRows<3>(3 * (n_nodes + j)) += a.weights[i] * phi.middleRows<3>(3 * a.nodes[i]);
    }
    body_numbers.push_back(a.number);
    body_names.push_back("n" + std::to_string(a.number));
  }
  std::vector<int> kept_nodes;
  if (options.nodes.empty()) {
    for (int k = 0; k < n_body; ++k) kept_nodes.push_back(k);
  } else {
    std::map<int, int> node_index;
    for (int k = 0; k < n_body; ++k)
      node_index.emplace(body_numbers[static_cast<std::size_t>(k)], k);
    for (const auto& [lo, hi] : options.nodes) {
      const auto first = node_index.lower_bound(lo);
      const auto last = node_index.upper_bound(hi);
      if (first == last) {
        throw core::InputError(frd.file, 0, "",
                               lo == hi
                                   ? "selected node " + std::to_string(lo) + " is not in the mesh"
                                   : "the selected range " + std::to_string(lo) + "-" +
                                         std::to_string(hi) + " holds no node of the mesh");
      }
      for (auto it = first; it != last; ++it) kept_nodes.push_back(it->second);
    }
    std::sort(kept_nodes.begin(), kept_nodes.end());
    kept_nodes.erase(std::unique(kept_nodes.begin(), kept_nodes.end()), kept_nodes.end());
  }
  const auto n_kept = static_cast<int>(kept_nodes.size());
  Eigen::Matrix3Xd x_kept(3, n_kept);
  Eigen::MatrixXd phi_kept(3 * n_kept, n_modes);
  for (int j = 0; j < n_kept; ++j) {
    const int k = kept_nodes[static_cast<std::size_t>(j)];
    x_kept.col(j) = x_body.col(k);
    phi_kept.middleRows<3>(3 * j) = phi_body.middleRows<3>(3 * k);
  }
  // The solid's invariants: projections of the mass matrix on the fields at every row (exact:
  // the rows the .frd does not show carry their share of the inertia). P_ab, reported only,
  // from the rows of the nodes.
  LinearInvariants solid = consistent_invariants(M0, x, phi);
  solid.rigid = rigid_projection(RtMR);
  solid.S = MR.leftCols<3>().transpose() * phi_rows;
  const Eigen::MatrixXd L = condensation.static_fields(linear_fields(x));
  solid.X = L.transpose() * Mphi;
  solid.m_ff = phi_rows.transpose() * Mphi;
  solid.m_ff = 0.5 * (solid.m_ff + solid.m_ff.transpose()).eval();
  result.solid = solid.rigid;
  Eigen::VectorXd masses;
  try {
    const Eigen::VectorXd hrz = diagonal_scaled_masses(node_diagonal(M0, map), result.solid.mass);
    const Eigen::VectorXd initial =
        options.nodes.empty() ? hrz : masses_on_nearest(hrz, x_body, kept_nodes);
    std::string why;
    for (const InvariantSelection& selection : invariant_selections()) {
      try {
        masses = selection.modal_masses
                     ? invariant_matched_masses(initial, x_kept, phi_kept, solid, selection)
                     : moment_matched_masses(initial, x_kept, result.solid);
        result.mass_model = selection.describe();
        break;
      } catch (const std::invalid_argument& e) {
        if (!selection.modal_masses) throw;
        if (why.empty()) why = e.what();
      }
    }
    if (result.mass_model != invariant_selections().front().describe()) {
      result.notes.push_back("the nodal masses match " + result.mass_model + ", not all of " +
                             invariant_selections().front().describe() + " (" + why + ")");
    }
  } catch (const std::invalid_argument& e) {
    throw core::InputError(matrices.mass_file, 0, "",
                           std::string("cannot lump the mass on the ") + std::to_string(n_kept) +
                               " kept nodes: " + e.what());
  }
  result.body = nodal_mass_properties(masses, x_kept);
  result.invariant_difference =
      relative_difference(solid, nodal_invariants(masses, x_kept, phi_kept));
  result.mass_difference = result.invariant_difference.rigid;
  if (!(result.mass_difference.max() <= kMassPropertyTolerance)) {
    throw core::InputError(matrices.mass_file, 0, "",
                           "the nodal masses reproduce the solid's mass properties only to " +
                               number(result.mass_difference.max()) + " (> " +
                               number(kMassPropertyTolerance) + ")");
  }

  // 6: the modal data.
  flexible::ModalData& data = result.data;
  data.mass = masses;
  data.p_BoNode_B = x_kept;
  data.phi.resize(3 * n_kept, n_modes);
  data.stiffness.resize(n_modes);
  data.damping_ratio = Eigen::VectorXd::Zero(n_modes);
  for (int i = 0; i < n_modes; ++i) {
    data.phi.col(i) = phi_kept.col(i);
    double mu = 0.0;
    for (int j = 0; j < n_kept; ++j) mu += masses(j) * data.phi.block<3, 1>(3 * j, i).squaredNorm();
    if (!(mu > 0.0)) {
      throw core::InputError(frd.file, kept[static_cast<std::size_t>(i)]->line, "",
                             "mode " + std::to_string(kept[static_cast<std::size_t>(i)]->number) +
                                 " does not move any kept node");
    }
    data.phi.col(i) /= std::sqrt(mu);
    // Strain energy of the scaled shape: λ φᵀMφ/μ.
    data.stiffness(i) =
        lambda[static_cast<std::size_t>(i)] * consistent[static_cast<std::size_t>(i)] / mu;
    data.mode_names.push_back("ccx-mode-" +
                              std::to_string(kept[static_cast<std::size_t>(i)]->number));
  }
  for (const int k : kept_nodes) data.node_names.push_back(body_names[static_cast<std::size_t>(k)]);
  try {
    data.validate();
  } catch (const std::invalid_argument& e) {
    throw core::InputError(frd.file, 0, "",
                           std::string("the imported modal data is not usable: ") + e.what() +
                               " (select fewer modes or keep more nodes)");
  }

  // 7: self-check.
  const Eigen::VectorXd omega_body = flexible::natural_frequencies(data);
  std::vector<double> omega_ccx;
  for (const CalculixModeCheck& m : result.modes) omega_ccx.push_back(m.omega_ccx);
  std::sort(omega_ccx.begin(), omega_ccx.end());
  for (int i = 0; i < n_modes; ++i) {
    CalculixModeCheck& m = result.modes[static_cast<std::size_t>(i)];
    m.omega_body = omega_body(i);
    m.difference = omega_body(i) / omega_ccx[static_cast<std::size_t>(i)] - 1.0;
    result.max_difference = std::max(result.max_difference, std::abs(m.difference));
  }
  result.self_check_passed = result.max_difference <= options.frequency_tolerance;
  if (!options.nodes.empty()) {
    result.notes.push_back("the body keeps " + std::to_string(n_kept) + " of the mesh's " +
                           std::to_string(n_nodes) +
                           " nodes: their masses carry the whole solid's inertia");
  }
  return result;
}

}  // namespace flexref::scene
