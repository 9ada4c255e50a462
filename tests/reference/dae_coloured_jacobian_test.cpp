#include "reference/dae_coloured_jacobian.hpp"

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "reference/ida_work_completion.hpp"
#include "reference/reference_solver.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/chain_scene.hpp"
#include "tests/support/joint_kind_scenes.hpp"

namespace flexref {
namespace {

using reference::DaeForm;

/// A DAE form's y, y', F at a generic point near the consistent initial values (every state
/// entry moved by up to 1e-3, the multipliers by up to 1e-3 of their size, so that no residual
/// row vanishes by symmetry), IDA-like error weights (rtol = atol = 1e-8) and a step h.
struct ColouredJacobianPoint {
  std::vector<double> y, yp, r, ewt, work;
  double h = 1e-3;
  double c_j = 2.0 / 1e-3;
};

ColouredJacobianPoint coloured_point(const DaeForm& form, DaeForm::Scratch& scratch) {
  const auto n = static_cast<std::size_t>(form.size());
  ColouredJacobianPoint p{std::vector<double>(n), std::vector<double>(n), std::vector<double>(n),
                          std::vector<double>(n), std::vector<double>(n)};
  const core::Model& model = form.model();
  form.initial_values({0.0, 0.0}, model.initial_state(), p.y.data(), p.yp.data());
  for (std::size_t k = 0; k < n; ++k) {
    p.y[k] += 1e-3 * std::sin(1.0 + static_cast<double>(k)) * std::max(1.0, std::abs(p.y[k]));
    p.ewt[k] = 1.0 / (1e-8 * std::abs(p.y[k]) + 1e-8);
  }
  form.residual({0.0, 0.0}, p.y.data(), p.yp.data(), p.r.data(), scratch);
  return p;
}

/// IDA's dense difference quotient (idaLsDenseDQJac, SUNDIALS 6.4): column by column, the
/// increments of dae_coloured_jacobian.hpp.
Eigen::MatrixXd dense_quotients(const DaeForm& form, ColouredJacobianPoint& p,
                                DaeForm::Scratch& scratch) {
  const int n = form.size();
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, n);
  const double srur = std::sqrt(std::numeric_limits<double>::epsilon());
  for (int j = 0; j < n; ++j) {
    const auto sj = static_cast<std::size_t>(j);
    const double yj = p.y[sj], ypj = p.yp[sj];
    double inc = std::max(srur * std::max(std::abs(yj), std::abs(p.h * ypj)), 1.0 / p.ewt[sj]);
    if (p.h * ypj < 0.0) inc = -inc;
    inc = (yj + inc) - yj;
    p.y[sj] += inc;
    p.yp[sj] += p.c_j * inc;
    form.residual({0.0, 0.0}, p.y.data(), p.yp.data(), p.work.data(), scratch);
    for (int i = 0; i < n; ++i) {
      G(i, j) =
          (1.0 / inc) * (p.work[static_cast<std::size_t>(i)] - p.r[static_cast<std::size_t>(i)]);
    }
    p.y[sj] = yj;
    p.yp[sj] = ypj;
  }
  return G;
}

Eigen::MatrixXd coloured_quotients(const reference::DaeColouredJacobian& coloured,
                                   const DaeForm& form, ColouredJacobianPoint& p,
                                   DaeForm::Scratch& scratch) {
  const int n = form.size();
  std::vector<sunindextype> start(static_cast<std::size_t>(n) + 1);
  std::vector<sunindextype> rows(static_cast<std::size_t>(coloured.nonzeros()));
  std::vector<double> values(rows.size());
  REQUIRE(coloured.evaluate({0.0, 0.0}, p.c_j, p.h, p.y.data(), p.yp.data(), p.r.data(),
                            p.ewt.data(), p.work.data(), scratch, start.data(), rows.data(),
                            values.data()));
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < n; ++c) {
    for (auto q = start[static_cast<std::size_t>(c)]; q < start[static_cast<std::size_t>(c) + 1];
         ++q) {
      G(rows[static_cast<std::size_t>(q)], c) = values[static_cast<std::size_t>(q)];
    }
  }
  return G;
}

/// Entries where the coloured matrix G and IDA's dense quotient D disagree, the works' rows
/// (`works` of them from `first_work`; their diagonal alone is kept, checked apart) aside:
/// `missed`, an entry the pattern leaves out though the dense quotient is not exactly 0 (the
/// residual reads it), and `differ`, any entry not equal bit for bit. An entry the pattern leaves
/// out must be one the residual does not read, whose dense quotient is exactly 0 (F_r does not
/// change when y_c moves); where the pattern has it, the same quotient: F_r at a point where the
/// group's other columns moved too, which row r does not read, so the same operations on the same
/// operands (no tolerance is needed, none is given).
struct PatternMismatch {
  int missed = 0;
  int differ = 0;
};

PatternMismatch compare_with_dense(const Eigen::MatrixXd& G, const Eigen::MatrixXd& D,
                                   int first_work, int works) {
  PatternMismatch out;
  for (Eigen::Index c = 0; c < G.cols(); ++c) {
    for (Eigen::Index r = 0; r < G.rows(); ++r) {
      if (r >= first_work && r < first_work + works) continue;
      if (G(r, c) == 0.0 && D(r, c) != 0.0) ++out.missed;
      if (G(r, c) != D(r, c)) ++out.differ;
    }
  }
  return out;
}

}  // namespace

TEST_CASE("coloured Newton matrix of the DAE form is IDA's dense difference quotient", "[core]") {
  // 7 rods on spherical joints and a damper-spring from rod 1 to rod 5: bodies no joint couples
  // (a pattern built from the joints alone misses their blocks) and a tracked work W_d.
  const scene::Scene scene = scene::parse_scene(testing::chain_scene_text(7, 0.5, 1, 5), "chain");
  const DaeForm form(*scene.model);
  REQUIRE(form.work_index() >= 0);
  REQUIRE(form.multiplier_count() == 21);
  DaeForm::Scratch scratch = form.make_scratch();
  ColouredJacobianPoint p = coloured_point(form, scratch);
  const reference::DaeColouredJacobian coloured(form);
  const std::vector<double> y0 = p.y, yp0 = p.yp;
  const Eigen::MatrixXd G = coloured_quotients(coloured, form, p, scratch);
  // y and y' restored bit for bit.
  CHECK(p.y == y0);
  CHECK(p.yp == yp0);
  const Eigen::MatrixXd D = dense_quotients(form, p, scratch);
  const int n = form.size();
  const int w = form.work_index();
  // The work's row: its diagonal alone, below.
  REQUIRE(form.integral_count() == 1);
  const PatternMismatch mismatch = compare_with_dense(G, D, w, 1);
  CHECK(mismatch.missed == 0);
  CHECK(mismatch.differ == 0);
  // The works: nothing reads W (its dense column is zero off the diagonal, so G is block lower
  // triangular), and its row keeps ∂F_W/∂W + c_j ∂F_W/∂W' = c_j alone (the dense row reads the
  // state: the coupling dae_coloured_jacobian.hpp leaves out).
  CHECK(G(w, w) == p.c_j);
  // The dense diagonal is c_j up to the rounding of (W + inc) − W over inc: 4 ulp of c_j.
  CHECK(std::abs(D(w, w) - p.c_j) <= 4.0 * std::numeric_limits<double>::epsilon() * p.c_j);
  CHECK(D.col(w).cwiseAbs().sum() - std::abs(D(w, w)) == 0.0);
  CHECK(D.row(w).cwiseAbs().sum() - std::abs(D(w, w)) > 0.0);

  // The linear solve with the works completed (ida_work_completion.hpp) is the dense matrix's:
  // x_s from the same state block, x_W = (b_W − G_Ws x_s)/c_j with G_Ws x_s by one directional
  // quotient instead of the dense row's column quotients (their agreement derived below).
  // Without the completion x_W is b_W/c_j,
  // off by the whole G_Ws x_s term: with b_W = 0, x_W is that term alone and the lagged one 0.
  Eigen::VectorXd b(n);
  for (int k = 0; k < n; ++k) b(k) = std::cos(0.5 + k);
  b(w) = 0.0;  // x_W is then the coupling term alone: −G_Ws x_s / c_j
  const Eigen::VectorXd x_dense = D.partialPivLu().solve(b);
  Eigen::VectorXd x = G.partialPivLu().solve(b);
  const double lagged = x(w);
  reference::IdaWorkCompletion completion(form);
  completion.remember(0.0, 0.0, p.y.data(), p.yp.data(), p.r.data());
  completion.set_matrix(p.c_j, p.ewt.data());
  bool completed = false;
  CHECK(testing::count_allocations([&] { completed = completion.complete(x.data(), scratch); }) ==
        0);
  CHECK(completed);
  // Their agreement: both quotients of F_W = W' − P(y) are set by rounding, each evaluation of
  // F_W off by ~2 ε |P| (P = W' − F_W at these values), divided by the increment: the
  // directional one's, σ (its x_s has unit weighted norm), and each column's inc_j, weighted by
  // |x_j| in the dense row's sum. Twice that (two evaluations each) over c_j bounds x_W's.
  const double eps = std::numeric_limits<double>::epsilon();
  double weighted = 0.0, over_increments = 0.0;
  for (int k = 0; k < n; ++k) {
    if (k == w) continue;
    const auto sk = static_cast<std::size_t>(k);
    weighted += (x(k) * p.ewt[sk]) * (x(k) * p.ewt[sk]);
    const double inc = std::max(
        std::sqrt(eps) * std::max(std::abs(p.y[sk]), std::abs(p.h * p.yp[sk])), 1.0 / p.ewt[sk]);
    over_increments += std::abs(x_dense(k)) / inc;
  }
  const double over_sigma = std::sqrt(weighted / static_cast<double>(n));  // 1/σ
  const double power =
      std::abs(p.yp[static_cast<std::size_t>(w)] - p.r[static_cast<std::size_t>(w)]);
  const double agreement = 4.0 * (2.0 * eps * power) * (over_sigma + over_increments) / p.c_j;
  INFO("x_W " << x(w) << ", dense " << x_dense(w) << ", agreement " << agreement);
  CHECK(std::abs(x(w) - x_dense(w)) <= agreement);
  CHECK(agreement < 1e-2 * std::abs(x_dense(w)));
  CHECK(lagged == 0.0);
  CHECK(std::abs(x_dense(w)) > 0.0);
  // The state's entries are the dense solve's (the same block, up to the LU's rounding).
  CHECK((x - x_dense).head(w).cwiseAbs().maxCoeff() <=
        1e-9 * x_dense.head(w).cwiseAbs().maxCoeff());
}

TEST_CASE("the joints' pattern holds for every joint kind, flexible bodies and drives", "[core]") {
  // The pattern lays out the joints' terms by what the GGL residual reads: a body's equations
  // read the other end's pose (p, θ, q_f) through J and no velocity of it, λ only in the
  // velocity-level rows, μ only in the position-level ones, and Φ's row no velocity. Every
  // joint kind's rows (one scene each, two bodies where the kind joins bodies: the Hooke joint,
  // the weld), the bundled mechanisms (revolute loops with a drive, a prismatic support, the
  // Bricard linkage's redundant row, flexible rods) and a chain with a spring: an entry the
  // residual reads and the pattern leaves out is caught as in the test above.
  std::vector<std::pair<std::string, std::string>> scenes;
  for (const testing::JointKindScene& s : testing::joint_kind_scenes()) {
    scenes.emplace_back(s.kind, s.toml);
  }
  for (const char* path :
       {"scenes/four_bar.toml", "scenes/slider_crank.toml", "scenes/slider_crank_flexible.toml",
        "scenes/andrews_squeezer.toml", "scenes/bricard.toml", "scenes/double_pendulum_ideal.toml",
        "scenes/heavy_top_spherical.toml"}) {
    std::ifstream file(path);
    REQUIRE(file);
    std::stringstream text;
    text << file.rdbuf();
    scenes.emplace_back(path, text.str());
  }
  for (const auto& [name, text] : scenes) {
    CAPTURE(name);
    const scene::Scene scene = scene::parse_scene(text, name);
    const DaeForm form(*scene.model);
    REQUIRE(form.multiplier_count() > 0);
    DaeForm::Scratch scratch = form.make_scratch();
    ColouredJacobianPoint p = coloured_point(form, scratch);
    const reference::DaeColouredJacobian coloured(form);
    const Eigen::MatrixXd G = coloured_quotients(coloured, form, p, scratch);
    const Eigen::MatrixXd D = dense_quotients(form, p, scratch);
    const PatternMismatch mismatch = compare_with_dense(
        G, D, form.work_index(), form.work_index() >= 0 ? form.integral_count() : 0);
    CHECK(mismatch.missed == 0);
    CHECK(mismatch.differ == 0);
  }
}

TEST_CASE("the coloured Newton matrix allocates nothing", "[core][allocation]") {
  const scene::Scene scene = scene::parse_scene(testing::chain_scene_text(7, 0.5, 1, 5), "chain");
  const DaeForm form(*scene.model);
  DaeForm::Scratch scratch = form.make_scratch();
  ColouredJacobianPoint p = coloured_point(form, scratch);
  const reference::DaeColouredJacobian coloured(form);
  std::vector<sunindextype> start(static_cast<std::size_t>(form.size()) + 1);
  std::vector<sunindextype> rows(static_cast<std::size_t>(coloured.nonzeros()));
  std::vector<double> values(rows.size());
  const long allocations = testing::count_allocations([&] {
    coloured.evaluate({0.0, 0.0}, p.c_j, p.h, p.y.data(), p.yp.data(), p.r.data(), p.ewt.data(),
                      p.work.data(), scratch, start.data(), rows.data(), values.data());
  });
  CHECK(allocations == 0);
}

TEST_CASE("a chain's coloured Newton matrix costs as many residuals whatever its length",
          "[core]") {
  // Each rod's block reads its two neighbours' (a distance-2 colouring of a path needs three
  // colours), so the groups do not grow with the chain: a rod's 13 columns and its joint's 6
  // multipliers, three rods apart, 3 × 19 at most.
  const scene::Scene small = scene::parse_scene(testing::chain_scene_text(8), "chain_8");
  const scene::Scene large = scene::parse_scene(testing::chain_scene_text(32), "chain_32");
  const DaeForm form_small(*small.model), form_large(*large.model);
  const reference::DaeColouredJacobian coloured_small(form_small), coloured_large(form_large);
  CHECK(coloured_large.group_count() == coloured_small.group_count());
  CHECK(coloured_large.group_count() <= 3 * 19);
  // The pattern grows linearly: nonzeros per column bounded.
  CHECK(coloured_large.nonzeros() < 60L * form_large.size());
  // And it is the GGL residual's (dae_coloured_jacobian.cpp): per rod inside the chain, its 13
  // rows read its own 13 columns (169; a spherical joint's point rows read each rod's own pose
  // alone, so no neighbour's), its two joints' λ in its 6 velocity rows and μ in its 7 pose rows
  // (2 × 3 × 13 = 78); per joint, λ's 3 rows read both rods' blocks (78), μ's both poses (42),
  // and the 6 multipliers their diagonal: 373 per rod and joint at most (the chain's ends have
  // fewer). Joint-coupled blocks in full (the rods' velocities too) gave 825, the neighbours'
  // poses 555.
  CHECK(coloured_large.nonzeros() <= 373L * large.model->num_bodies());
}

TEST_CASE("IDA's sparse Newton matrix solves a chain as accurately as the dense one", "[core]") {
  // Both at rtol 1e-8 against a dense solve at 1e-11 (its error ~1e-3 of theirs): the Newton
  // matrix changes only the rounding of the corrections, so the sparse path's error must be of
  // the dense path's size. A factor 3 between errors of the same tolerance allows for the step
  // sequences differing (the error of a BDF solve varies by such factors between neighbouring
  // step sequences), and 1e-8 m (the tolerance on the 1.4 m chain's positions) for an error
  // that happens to vanish.
  const scene::Scene scene = scene::parse_scene(testing::chain_scene_text(7, 0.05, 1, 5), "chain");
  const std::vector<double> times{0.0, 0.025, 0.05};
  reference::SolverOptions options;
  options.rtol = 1e-11;
  options.newton_matrix = reference::NewtonMatrix::kDense;
  const reference::ReferenceRun truth = reference::solve_ida(*scene.model, times, options);
  options.rtol = 1e-8;
  const reference::ReferenceRun dense = reference::solve_ida(*scene.model, times, options);
  options.newton_matrix = reference::NewtonMatrix::kSparse;
  const reference::ReferenceRun sparse = reference::solve_ida(*scene.model, times, options);
  CHECK(dense.jacobian == "difference quotients, dense LU");
  CHECK(sparse.jacobian == "coloured difference quotients, sparse LU (KLU)");
  const auto error = [&](const reference::ReferenceRun& run) {
    double e = 0.0;
    const core::State& a = run.trajectory.states.back();
    const core::State& b = truth.trajectory.states.back();
    for (std::size_t k = 0; k < a.size(); ++k) e = std::max(e, (a[k].p_WBr - b[k].p_WBr).norm());
    return e;
  };
  CHECK(error(sparse) <= 3.0 * error(dense) + 1e-8);
  // And it costs fewer residuals: a group per colour instead of one per column.
  CHECK(sparse.stats.rhs_evaluations < dense.stats.rhs_evaluations);
}

}  // namespace flexref
