#include "flexible/beam_model.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace flexref::flexible {
namespace {

// Dense eigen-solves of up to 2(E + 1) DOFs per family: 1000 elements take seconds.
constexpr int kMaxElements = 1000;
// Poisson's ratio of the default torsional stiffness (BeamParameters::GJ).
constexpr double kDefaultPoisson = 0.3;

// 5-point Gauss–Lobatto rule on [0, 1]: abscissae 0, (1 ∓ √(3/7))/2, 1/2, 1; weights 1/20,
// 49/180, 16/45, 49/180, 1/20; exact for polynomials of degree ≤ 7. Only the interior points
// are listed; the ends (weight 1/20) are the finite-element nodes.
const double kLobattoOffset = 0.5 * std::sqrt(3.0 / 7.0);
const std::array<double, 3> kInteriorAbscissa = {0.5 - kLobattoOffset, 0.5, 0.5 + kLobattoOffset};
constexpr std::array<double, 3> kInteriorWeight = {49.0 / 180.0, 16.0 / 45.0, 49.0 / 180.0};
constexpr double kEndWeight = 1.0 / 20.0;

struct FamilyProperties {
  double stiffness;  // EA, EI or GJ
  double mass;       // ρA or ρJ
  bool bending;      // Hermite (2 DOF per node: v, h·v') or linear (1 DOF per node)
  int rigid_modes;   // of the free-free beam
  int component;     // body axis of the displacement (−1: torsion, no displacement)
};

double torsional_stiffness(const BeamParameters& p) {
  return p.GJ.value_or((p.EI_y + p.EI_z) / (2.0 * (1.0 + kDefaultPoisson)));
}

double polar_mass(const BeamParameters& p) {
  return p.rho_J.value_or(p.rho_A * (p.EI_y + p.EI_z) / p.EA);
}

FamilyProperties properties(const BeamParameters& p, BeamModeFamily family) {
  switch (family) {
    case BeamModeFamily::kAxial:
      return {p.EA, p.rho_A, false, 1, 0};
    case BeamModeFamily::kBendingXY:
      return {p.EI_z, p.rho_A, true, 2, 1};
    case BeamModeFamily::kBendingXZ:
      return {p.EI_y, p.rho_A, true, 2, 2};
    case BeamModeFamily::kTorsion:
      return {torsional_stiffness(p), polar_mass(p), false, 1, -1};
  }
  throw std::invalid_argument("beam model: unknown mode family");
}

bool positive_finite(double x) { return std::isfinite(x) && x > 0.0; }

std::string number(double x) {
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

void require_valid(const BeamParameters& p) {
  const std::string problem = beam_parameters_problem(p);
  if (!problem.empty()) throw std::invalid_argument("beam model: " + problem);
}

struct FamilyMatrices {
  Eigen::MatrixXd K;
  Eigen::MatrixXd M;
};

// Global matrices of one family over all nodes (no boundary conditions), element length h.
// Bending DOFs per node: (v, h·v'), scaled so that the element matrices carry one power of h
// and the entries of K (and of M) have comparable sizes.
FamilyMatrices assemble(const FamilyProperties& f, int elements, double h) {
  const int dofs_per_node = f.bending ? 2 : 1;
  const int n = dofs_per_node * (elements + 1);
  FamilyMatrices out{Eigen::MatrixXd::Zero(n, n), Eigen::MatrixXd::Zero(n, n)};
  if (f.bending) {
    Eigen::Matrix4d k;
    k << 12, 6, -12, 6,   //
        6, 4, -6, 2,      //
        -12, -6, 12, -6,  //
        6, 2, -6, 4;
    Eigen::Matrix4d m;
    m << 156, 22, 54, -13,  //
        22, 4, 13, -3,      //
        54, 13, 156, -22,   //
        -13, -3, -22, 4;
    k *= f.stiffness / (h * h * h);  // EI/h³ (Hermite cubic, consistent stiffness)
    m *= f.mass * h / 420.0;         // ρA h/420 (consistent mass)
    for (Eigen::Index e = 0; e < elements; ++e) {
      out.K.block<4, 4>(2 * e, 2 * e) += k;
      out.M.block<4, 4>(2 * e, 2 * e) += m;
    }
  } else {
    Eigen::Matrix2d k;
    k << 1, -1, -1, 1;
    Eigen::Matrix2d m;
    m << 2, 1, 1, 2;
    k *= f.stiffness / h;   // EA/h
    m *= f.mass * h / 6.0;  // ρA h/6
    for (int e = 0; e < elements; ++e) {
      out.K.block<2, 2>(e, e) += k;
      out.M.block<2, 2>(e, e) += m;
    }
  }
  return out;
}

// The exact rigid-body modes of a free-free family, M-orthonormal (columns): a uniform
// translation (u = 1, v = 1, or θx = 1), and for bending also the rotation about the root
// (v = x, v' = 1, i.e. DOF h·v' = h).
Eigen::MatrixXd rigid_modes(const FamilyProperties& f, int elements, double h,
                            const Eigen::MatrixXd& M) {
  const Eigen::Index nodes = elements + 1;
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(M.rows(), f.bending ? 2 : 1);
  if (f.bending) {
    for (Eigen::Index j = 0; j < nodes; ++j) {
      r(2 * j, 0) = 1.0;
      r(2 * j, 1) = static_cast<double>(j) * h;
      r(2 * j + 1, 1) = h;
    }
  } else {
    r.col(0).setOnes();
  }
  // Modified Gram–Schmidt in the M inner product.
  for (Eigen::Index c = 0; c < r.cols(); ++c) {
    for (Eigen::Index b = 0; b < c; ++b) r.col(c) -= r.col(b) * r.col(b).dot(M * r.col(c));
    r.col(c) /= std::sqrt(r.col(c).dot(M * r.col(c)));
  }
  return r;
}

// Twice the strain energy of the field x (global DOFs of the family, as in assemble()),
// element by element from the strains: for linear elements k (u_b − u_a)²/h, for Hermite
// elements EI h ∫₀¹ κ² dξ = EI h (κ₀² + κ₀κ₁ + κ₁²)/3 with the curvature, linear in ξ, at the
// ends: h² κ₀ = 6 (v_b − v_a) − 4 s_a − 2 s_b, h² κ₁ = −6 (v_b − v_a) + 2 s_a + 4 s_b (s = h v').
// Equal to xᵀ K x, but without its cancellation: K x is a fourth difference of a smooth field
// and loses ε·λ_max/λ (1e-6 relative for the first mode at 200 elements), the strains lose
// only about ε/(βh)².
double strain_energy2(const FamilyProperties& f, const Eigen::VectorXd& x, int elements, double h) {
  double sum = 0.0;
  for (Eigen::Index e = 0; e < elements; ++e) {
    if (f.bending) {
      const double dv = x(2 * e + 2) - x(2 * e);
      const double s_a = x(2 * e + 1);
      const double s_b = x(2 * e + 3);
      const double k0 = 6.0 * dv - 4.0 * s_a - 2.0 * s_b;
      const double k1 = -6.0 * dv + 2.0 * s_a + 4.0 * s_b;
      sum += (k0 * k0 + k0 * k1 + k1 * k1) / 3.0;
    } else {
      const double du = x(e + 1) - x(e);
      sum += du * du;
    }
  }
  // Σ EI h (κ h²)²/h⁴ = EI/h³ Σ (h² κ)²; Σ k (Δu)²/h.
  return f.bending ? f.stiffness / (h * h * h) * sum : f.stiffness / h * sum;
}

// Hermite cubics on [0, 1]: v(ξ) = H1 v_a + H2 (h v'_a) + H3 v_b + H4 (h v'_b).
Eigen::Vector4d hermite(double xi) {
  const double xi2 = xi * xi;
  const double xi3 = xi2 * xi;
  return {1.0 - 3.0 * xi2 + 2.0 * xi3, xi - 2.0 * xi2 + xi3, 3.0 * xi2 - 2.0 * xi3, xi3 - xi2};
}

// Field of a mode at position ξ ∈ [0, 1] of element e.
double interpolate(const BeamMode& mode, int e, double xi, double h) {
  const auto a = static_cast<Eigen::Index>(e);
  if (mode.slope.size() == 0) return (1.0 - xi) * mode.value(a) + xi * mode.value(a + 1);
  const Eigen::Vector4d H = hermite(xi);
  return H(0) * mode.value(a) + H(1) * h * mode.slope(a) + H(2) * mode.value(a + 1) +
         H(3) * h * mode.slope(a + 1);
}

// d/dx of a bending mode's field at position ξ ∈ [0, 1] of element e (Hermite cubic).
double interpolate_slope(const BeamMode& mode, int e, double xi, double h) {
  const auto a = static_cast<Eigen::Index>(e);
  const double xi2 = xi * xi;
  const Eigen::Vector4d dH = {6.0 * xi2 - 6.0 * xi, 1.0 - 4.0 * xi + 3.0 * xi2,
                              6.0 * xi - 6.0 * xi2, 3.0 * xi2 - 2.0 * xi};
  return (dH(0) * mode.value(a) + dH(1) * h * mode.slope(a) + dH(2) * mode.value(a + 1) +
          dH(3) * h * mode.slope(a + 1)) /
         h;
}

// The unit-load geometric stiffness of a clamped-free beam along x
// (flexible/geometric_stiffness.hpp, docs/geometric_stiffening.md GS-13): with the material points
// k in order from the root and G_k = ∫ φ'ᵀφ' ds over the stretch between points k and k+1
// (transverse slopes, both planes), D_k = Σ_{j<k} G_j, so E_x = Σ_k m_k D_k = Σ_j (Σ_{k>j} m_k) G_j
// and F_xb = Σ_j (Σ_{k>j} m_k x_k,b) G_j: the outboard mass and first moment are the axial force of
// the unit fields. φ'ᵀφ' is a quartic on each stretch: 3-point Gauss–Legendre is exact.
GeometricStiffness beam_geometric_stiffness(const BeamParameters& p,
                                            const std::vector<BeamMode>& modes,
                                            const std::vector<double>& scales,
                                            const ModalData& data) {
  const auto n = static_cast<Eigen::Index>(modes.size());
  const int E = p.elements;
  const double h = p.length / E;
  const int N = data.node_count();
  // Outboard sums over the points k > j.
  std::vector<double> outboard_mass(static_cast<std::size_t>(N), 0.0);
  std::vector<Eigen::Vector3d> outboard_moment(static_cast<std::size_t>(N),
                                               Eigen::Vector3d::Zero());
  for (int j = N - 2; j >= 0; --j) {
    const auto u = static_cast<std::size_t>(j);
    outboard_mass[u] = outboard_mass[u + 1] + data.mass(j + 1);
    outboard_moment[u] = outboard_moment[u + 1] + data.mass(j + 1) * data.p_BoNode_B.col(j + 1);
  }
  GeometricStiffness g;
  for (auto& M : g.E) M = Eigen::MatrixXd::Zero(n, n);
  for (auto& M : g.F) M = Eigen::MatrixXd::Zero(n, n);
  const std::array<double, 5> xi = {0.0, kInteriorAbscissa[0], kInteriorAbscissa[1],
                                    kInteriorAbscissa[2], 1.0};
  const double t3 = std::sqrt(0.6);
  const std::array<double, 3> gauss_t = {-t3, 0.0, t3};
  const std::array<double, 3> gauss_w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  Eigen::MatrixXd G(n, n);
  Eigen::VectorXd slope_y(n), slope_z(n);
  for (int e = 0; e < E; ++e) {
    for (int i = 0; i < 4; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      const double mid = 0.5 * (xi[ui] + xi[ui + 1]);
      const double half = 0.5 * (xi[ui + 1] - xi[ui]);
      G.setZero();
      for (std::size_t m = 0; m < 3; ++m) {
        slope_y.setZero();
        slope_z.setZero();
        for (Eigen::Index k = 0; k < n; ++k) {
          const BeamMode& mode = modes[static_cast<std::size_t>(k)];
          if (mode.slope.size() == 0) continue;  // axial: no transverse slope
          const double v = scales[static_cast<std::size_t>(k)] *
                           interpolate_slope(mode, e, mid + half * gauss_t[m], h);
          (mode.family == BeamModeFamily::kBendingXY ? slope_y : slope_z)(k) = v;
        }
        const double w = h * half * gauss_w[m];  // dx = h dξ
        G.noalias() += w * (slope_y * slope_y.transpose() + slope_z * slope_z.transpose());
      }
      const auto j = static_cast<std::size_t>(4 * e + i);
      g.E[0] += outboard_mass[j] * G;
      for (int b = 0; b < 3; ++b) g.F[static_cast<std::size_t>(b)] += outboard_moment[j](b) * G;
    }
  }
  for (auto& M : g.E) M = 0.5 * (M + M.transpose()).eval();
  for (auto& M : g.F) M = 0.5 * (M + M.transpose()).eval();
  return g;
}

}  // namespace

std::string to_string(BeamModeFamily family) {
  switch (family) {
    case BeamModeFamily::kAxial:
      return "axial";
    case BeamModeFamily::kBendingXY:
      return "bending-xy";
    case BeamModeFamily::kBendingXZ:
      return "bending-xz";
    case BeamModeFamily::kTorsion:
      return "torsion";
  }
  return "unknown";
}

std::string beam_parameters_problem(const BeamParameters& p) {
  if (!p.origin.allFinite()) return "origin must be finite";
  if (!positive_finite(p.length)) return "length must be > 0, got " + number(p.length);
  if (p.elements < 1 || p.elements > kMaxElements) {
    return "elements must be between 1 and " + std::to_string(kMaxElements) + ", got " +
           std::to_string(p.elements);
  }
  const std::array<std::pair<const char*, double>, 4> required = {
      {{"EA", p.EA}, {"EI_y", p.EI_y}, {"EI_z", p.EI_z}, {"rho_A", p.rho_A}}};
  for (const auto& [name, value] : required) {
    if (!positive_finite(value)) return std::string(name) + " must be > 0, got " + number(value);
  }
  if (p.GJ && !positive_finite(*p.GJ)) return "GJ must be > 0, got " + number(*p.GJ);
  if (p.rho_J && !positive_finite(*p.rho_J)) return "rho_J must be > 0, got " + number(*p.rho_J);
  return {};
}

std::vector<BeamMode> solve_beam_family(const BeamParameters& p, BeamModeFamily family) {
  require_valid(p);
  const FamilyProperties f = properties(p, family);
  const int E = p.elements;
  const double h = p.length / E;
  const FamilyMatrices full = assemble(f, E, h);
  const int dofs_per_node = f.bending ? 2 : 1;
  // Clamped root: drop node 0's DOFs (u, or v and v'; all 6 DOF of the node are fixed). A
  // pinned tip drops the tip's value (u, v or θx), a clamped tip its slope too.
  const auto total = static_cast<int>(full.K.rows());
  const bool clamped_root = p.boundary != BeamBoundary::kFreeFree;
  const int tip_fixed = p.boundary == BeamBoundary::kClampedClamped  ? dofs_per_node
                        : p.boundary == BeamBoundary::kClampedPinned ? 1
                                                                     : 0;
  std::vector<Eigen::Index> kept;
  for (int d = clamped_root ? dofs_per_node : 0; d < total; ++d) {
    if (d >= total - dofs_per_node && d - (total - dofs_per_node) < tip_fixed) continue;
    kept.push_back(d);
  }
  const auto n = static_cast<Eigen::Index>(kept.size());
  const Eigen::MatrixXd K = full.K(kept, kept);
  const Eigen::MatrixXd M = full.M(kept, kept);
  // K φ = λ M φ with φᵀ M φ = 1 (Eigen's ABx_lx normalization); λ ascending.
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(K, M);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error("beam model: the " + to_string(family) + " eigen-solve failed");
  }
  const int skip = p.boundary == BeamBoundary::kFreeFree ? f.rigid_modes : 0;
  const Eigen::VectorXd& lambda = solver.eigenvalues();
  // The free-free rigid modes are the `skip` lowest: zero eigenvalues up to the solver's
  // rounding, ≈ ε·λ_max (λ_max ∝ E⁴ for bending: 1e-5 · λ_1 at 1000 elements), far below the
  // first elastic one. A sanity check of the separation, not of accuracy.
  if (skip > 0 && !(std::abs(lambda(skip - 1)) < 1e-3 * lambda(skip))) {
    throw std::logic_error("beam model: the free-free rigid modes are not separated");
  }
  const Eigen::MatrixXd rigid = p.boundary == BeamBoundary::kFreeFree
                                    ? rigid_modes(f, E, h, full.M)
                                    : Eigen::MatrixXd(full.K.rows(), 0);
  std::vector<BeamMode> modes;
  for (Eigen::Index i = skip; i < n; ++i) {
    BeamMode mode;
    mode.family = family;
    mode.order = static_cast<int>(i - skip + 1);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(full.K.rows());
    x(kept) = solver.eigenvectors().col(i);
    // The solver's elastic eigenvectors are M-orthogonal to the rigid modes only to about
    // ε·λ_max/λ_1 (1e-8 at 200 elements); project the exact rigid modes out, so that the
    // free-free modes have zero linear and angular momentum to rounding.
    for (Eigen::Index r = 0; r < rigid.cols(); ++r) {
      x -= rigid.col(r) * rigid.col(r).dot(full.M * x);
    }
    // Normalize: φᵀMφ = 1 (already so, up to rounding, before the projection).
    x /= std::sqrt(x.dot(full.M * x));
    // ω² as the Rayleigh quotient φᵀKφ/φᵀMφ from the strains: the same as the eigenvalue
    // up to rounding, but evaluated without the eigenvalue's cancellation (strain_energy2);
    // the error of φ enters it only quadratically.
    mode.omega = std::sqrt(strain_energy2(f, x, E, h));
    if (f.bending) {
      mode.value = Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<2>>(x.data(), E + 1);
      mode.slope =
          Eigen::Map<const Eigen::VectorXd, 0, Eigen::InnerStride<2>>(x.data() + 1, E + 1) / h;
    } else {
      mode.value = x;
    }
    // Sign: tip value positive; if the tip does not move (never for these beams, but cheap to
    // guard), the largest value positive.
    Eigen::Index largest = 0;
    mode.value.cwiseAbs().maxCoeff(&largest);
    const double tip = mode.value(E);
    const double reference =
        std::abs(tip) > 1e-8 * std::abs(mode.value(largest)) ? tip : mode.value(largest);
    if (reference < 0.0) {
      // 0 − x rather than −x: the clamped root's zeros stay +0 (tidy files).
      mode.value = (0.0 - mode.value.array()).matrix();
      mode.slope = (0.0 - mode.slope.array()).matrix();
    }
    modes.push_back(std::move(mode));
  }
  return modes;
}

std::vector<BeamMode> solve_beam_modes(const BeamParameters& p) {
  std::vector<BeamMode> modes;
  for (const BeamModeFamily family : {BeamModeFamily::kAxial, BeamModeFamily::kBendingXY,
                                      BeamModeFamily::kBendingXZ, BeamModeFamily::kTorsion}) {
    std::vector<BeamMode> some = solve_beam_family(p, family);
    modes.insert(modes.end(), some.begin(), some.end());
  }
  std::stable_sort(modes.begin(), modes.end(),
                   [](const BeamMode& a, const BeamMode& b) { return a.omega < b.omega; });
  return modes;
}

ModalData make_beam_modal_data(const BeamParameters& p, int n_modes, const BeamModeFilter& filter,
                               BeamModeNormalization normalization, bool geometric_stiffness) {
  require_valid(p);
  if (geometric_stiffness && p.boundary != BeamBoundary::kClampedFree) {
    throw std::invalid_argument(
        "beam model: geometric stiffening needs a clamped-free beam (the foreshortening is "
        "measured from the clamped root; docs/geometric_stiffening.md)");
  }
  std::vector<BeamMode> modes;
  const std::array<std::pair<BeamModeFamily, bool>, 3> families = {
      {{BeamModeFamily::kAxial, filter.axial},
       {BeamModeFamily::kBendingXY, filter.bending_xy},
       {BeamModeFamily::kBendingXZ, filter.bending_xz}}};
  for (const auto& [family, included] : families) {
    if (!included) continue;
    std::vector<BeamMode> some = solve_beam_family(p, family);
    modes.insert(modes.end(), some.begin(), some.end());
  }
  std::stable_sort(modes.begin(), modes.end(),
                   [](const BeamMode& a, const BeamMode& b) { return a.omega < b.omega; });
  if (n_modes < 1 || n_modes > static_cast<int>(modes.size())) {
    throw std::invalid_argument("beam model: " + std::to_string(n_modes) +
                                " modes requested, the selected families of this mesh have " +
                                std::to_string(modes.size()) + " (at least 1 is required)");
  }
  modes.resize(static_cast<std::size_t>(n_modes));

  const int E = p.elements;
  const double h = p.length / E;
  const int N = 4 * E + 1;  // E + 1 element ends and 3 interior points per element
  ModalData data;
  data.mass.resize(N);
  data.p_BoNode_B.resize(3, N);
  data.phi = Eigen::MatrixXd::Zero(3 * Eigen::Index{N}, n_modes);
  data.node_names.resize(static_cast<std::size_t>(N));
  const Eigen::Vector3d e_x = Eigen::Vector3d::UnitX();
  for (int j = 0; j <= E; ++j) {
    const int k = 4 * j;
    const int adjacent = (j == 0 || j == E) ? 1 : 2;
    data.mass(k) = adjacent * kEndWeight * p.rho_A * h;
    data.p_BoNode_B.col(k) = p.origin + (j * h) * e_x;
    data.node_names[static_cast<std::size_t>(k)] = "node" + std::to_string(j);
  }
  for (int e = 0; e < E; ++e) {
    for (int q = 0; q < 3; ++q) {
      const int k = 4 * e + q + 1;
      const auto uq = static_cast<std::size_t>(q);
      data.mass(k) = kInteriorWeight[uq] * p.rho_A * h;
      data.p_BoNode_B.col(k) = p.origin + ((e + kInteriorAbscissa[uq]) * h) * e_x;
      data.node_names[static_cast<std::size_t>(k)] =
          "e" + std::to_string(e) + "_q" + std::to_string(q + 1);
    }
  }
  data.stiffness.resize(n_modes);
  data.damping_ratio = Eigen::VectorXd::Zero(n_modes);
  std::vector<double> scales(static_cast<std::size_t>(n_modes), 1.0);
  for (int i = 0; i < n_modes; ++i) {
    const BeamMode& mode = modes[static_cast<std::size_t>(i)];
    const int c = properties(p, mode.family).component;
    const double scale =
        normalization == BeamModeNormalization::kUnitTipDisplacement ? 1.0 / mode.value(E) : 1.0;
    scales[static_cast<std::size_t>(i)] = scale;
    for (int j = 0; j <= E; ++j) data.phi(3 * (4 * j) + c, i) = scale * mode.value(j);
    for (int e = 0; e < E; ++e) {
      for (int q = 0; q < 3; ++q) {
        const int k = 4 * e + q + 1;
        data.phi(3 * k + c, i) =
            scale * interpolate(mode, e, kInteriorAbscissa[static_cast<std::size_t>(q)], h);
      }
    }
    // K_i = ω_i² μ_i with μ_i the nodal sum, so that diag(K) φ = ω² m_ff φ has the
    // finite-element frequencies (μ_i = 1 up to rounding for unit modal mass).
    double mu = 0.0;
    for (int k = 0; k < N; ++k) mu += data.mass(k) * data.mode_rows(k).col(i).squaredNorm();
    data.stiffness(i) = mode.omega * mode.omega * mu;
    data.mode_names.push_back(to_string(mode.family) + "-" + std::to_string(mode.order));
  }
  if (geometric_stiffness) data.geometric = beam_geometric_stiffness(p, modes, scales, data);
  data.validate();
  return data;
}

}  // namespace flexref::flexible
