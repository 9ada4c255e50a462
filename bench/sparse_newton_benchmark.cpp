/// Cost of the implicit solvers' Newton matrices on issue 52's chain of N rods on ideal spherical
/// joints (scripts/scenes/make_chain.py; docs/performance.md, "Constrained systems at scale",
/// "IDA's and genalpha's Newton matrices"), N = 8 … 256, at the chain's consistent initial state:
///
/// - BM_DaeResidual: one residual of IDA's DAE form (the model's evaluation: loads, the joints'
///   rows, Jᵀλ on the rows' bodies).
/// - BM_IdaColouredMatrix: IDA's Newton matrix by coloured difference quotients
///   (reference/dae_coloured_jacobian.hpp), counters: residuals per matrix, nonzeros.
/// - BM_IdaDenseMatrix (N ≤ 64): the same matrix as IDA forms it without a pattern, one
///   residual per column, and its dense LU (Eigen's PartialPivLU, the work of SUNDIALS' dense
///   solver).
/// - BM_IdaKluFactor: KLU's refactorization of the coloured matrix (lie/sparse_lu.hpp, the
///   library SUNLinSol_KLU calls), its ordering done once outside the loop.
/// - BM_GenAlphaStep: genalpha steps at h = 1e-3 s (each: a residual per Newton iteration, the
///   iteration matrix reassembled only where the iteration contracts slowly); BM_GenAlphaMatrix:
///   one assembly of its iteration matrix (lie/genalpha_newton.hpp) and KLU's refactorization.
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <sstream>
#include <vector>

#include "lie/genalpha_newton.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/sparse_lu.hpp"
#include "lie/stepper.hpp"
#include "reference/dae_coloured_jacobian.hpp"
#include "reference/dae_form.hpp"
#include "scene/scene_reader.hpp"

namespace {

namespace ref = flexref::reference;

/// make_chain.py's scene text (the same numbers).
std::string chain_text(int n) {
  const double length = 0.2, mass = 0.1, spin = 2.0, side = length / 20;
  std::ostringstream t;
  t.precision(17);
  t << "[scene]\nname = \"chain\"\nend_time = 0.5\noutput_step = 0.01\n"
       "gravity = [0.0, 0.0, -9.81]\n";
  for (int k = 0; k < n; ++k) {
    t << "[[body]]\nname = \"rod" << k << "\"\nmass = " << mass << "\ninertia = ["
      << mass * side * side / 6 << ", " << mass * length * length / 12 << ", "
      << mass * length * length / 12 << "]\ncenter_of_mass = [" << length / 2
      << ", 0.0, 0.0]\nposition = [" << k * length << ", 0.0, 0.0]\nvelocity = [0.0, "
      << spin * k * length << ", 0.0]\nangular_velocity = [0.0, 0.0, " << spin << "]\n";
  }
  for (int k = 0; k < n; ++k) {
    t << "[[joint]]\nname = \"j" << k
      << "\"\nmodel = \"ideal\"\nkind = \"spherical\"\nbody_a = \"rod" << k
      << "\"\npoint_a = [0.0, 0.0, 0.0]\nbody_b = \""
      << (k == 0 ? std::string("ground") : "rod" + std::to_string(k - 1)) << "\"\npoint_b = ["
      << (k == 0 ? 0.0 : length) << ", 0.0, 0.0]\n";
  }
  return t.str();
}

/// The chain's DAE form at its consistent initial values, with IDA-like weights (rtol 1e-8).
struct DaePoint {
  flexref::scene::Scene scene;
  std::unique_ptr<ref::DaeForm> form;
  ref::DaeForm::Scratch scratch;
  std::vector<double> y, yp, r, ewt, work;
};

DaePoint dae_point(int n) {
  DaePoint p{flexref::scene::parse_scene(chain_text(n), "chain"), nullptr, {}, {}, {}, {}, {}, {}};
  p.form = std::make_unique<ref::DaeForm>(*p.scene.model);
  p.scratch = p.form->make_scratch();
  const auto size = static_cast<std::size_t>(p.form->size());
  for (std::vector<double>* v : {&p.y, &p.yp, &p.r, &p.ewt, &p.work}) v->assign(size, 0.0);
  p.form->initial_values({0.0, 0.0}, p.scene.model->initial_state(), p.y.data(), p.yp.data());
  for (std::size_t k = 0; k < size; ++k) p.ewt[k] = 1.0 / (1e-8 * std::abs(p.y[k]) + 1e-8);
  p.form->residual({0.0, 0.0}, p.y.data(), p.yp.data(), p.r.data(), p.scratch);
  return p;
}

constexpr double kStep = 1e-3;
constexpr double kCj = 2.0 / kStep;

void BM_DaeResidual(benchmark::State& st) {
  DaePoint p = dae_point(static_cast<int>(st.range(0)));
  for (auto _ : st) {
    p.form->residual({0.0, 0.0}, p.y.data(), p.yp.data(), p.work.data(), p.scratch);
    benchmark::DoNotOptimize(p.work.data());
  }
  st.counters["size"] = p.form->size();
}

/// The coloured matrix into CSC arrays (sunindextype, as SUNDIALS' sparse matrix holds them).
struct CscMatrix {
  std::vector<sunindextype> start, rows;
  std::vector<double> values;
  std::vector<int> start_int, rows_int;  ///< the same, for KLU's int interface
};

CscMatrix coloured_matrix(const ref::DaeColouredJacobian& coloured, DaePoint& p) {
  CscMatrix m;
  m.start.resize(static_cast<std::size_t>(p.form->size()) + 1);
  m.rows.resize(static_cast<std::size_t>(coloured.nonzeros()));
  m.values.resize(m.rows.size());
  coloured.evaluate({0.0, 0.0}, kCj, kStep, p.y.data(), p.yp.data(), p.r.data(), p.ewt.data(),
                    p.work.data(), p.scratch, m.start.data(), m.rows.data(), m.values.data());
  m.start_int.assign(m.start.begin(), m.start.end());
  m.rows_int.assign(m.rows.begin(), m.rows.end());
  return m;
}

void BM_IdaColouredMatrix(benchmark::State& st) {
  DaePoint p = dae_point(static_cast<int>(st.range(0)));
  const ref::DaeColouredJacobian coloured(*p.form);
  CscMatrix m = coloured_matrix(coloured, p);
  for (auto _ : st) {
    coloured.evaluate({0.0, 0.0}, kCj, kStep, p.y.data(), p.yp.data(), p.r.data(), p.ewt.data(),
                      p.work.data(), p.scratch, m.start.data(), m.rows.data(), m.values.data());
    benchmark::DoNotOptimize(m.values.data());
  }
  st.counters["residuals"] = coloured.group_count();
  st.counters["nonzeros"] = static_cast<double>(coloured.nonzeros());
  st.counters["size"] = p.form->size();
}

void BM_IdaKluFactor(benchmark::State& st) {
  DaePoint p = dae_point(static_cast<int>(st.range(0)));
  const ref::DaeColouredJacobian coloured(*p.form);
  CscMatrix m = coloured_matrix(coloured, p);
  flexref::lie::SparseLu lu;
  lu.analyze(p.form->size(), m.start_int.data(), m.rows_int.data());
  if (!lu.factor(m.values.data())) st.SkipWithError("KLU: singular");
  for (auto _ : st) benchmark::DoNotOptimize(lu.factor(m.values.data()));
}

void BM_IdaDenseMatrix(benchmark::State& st) {
  DaePoint p = dae_point(static_cast<int>(st.range(0)));
  const int n = p.form->size();
  Eigen::MatrixXd G(n, n);
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(n);
  const double srur = std::sqrt(std::numeric_limits<double>::epsilon());
  for (auto _ : st) {
    for (int j = 0; j < n; ++j) {
      const auto sj = static_cast<std::size_t>(j);
      const double yj = p.y[sj], ypj = p.yp[sj];
      double inc = std::max(srur * std::max(std::abs(yj), std::abs(kStep * ypj)), 1.0 / p.ewt[sj]);
      if (kStep * ypj < 0.0) inc = -inc;
      inc = (yj + inc) - yj;
      p.y[sj] += inc;
      p.yp[sj] += kCj * inc;
      p.form->residual({0.0, 0.0}, p.y.data(), p.yp.data(), p.work.data(), p.scratch);
      for (int i = 0; i < n; ++i) {
        G(i, j) =
            (1.0 / inc) * (p.work[static_cast<std::size_t>(i)] - p.r[static_cast<std::size_t>(i)]);
      }
      p.y[sj] = yj;
      p.yp[sj] = ypj;
    }
    lu.compute(G);
    benchmark::DoNotOptimize(lu.matrixLU().data());
  }
  st.counters["residuals"] = n;
}

void BM_GenAlphaStep(benchmark::State& st) {
  const flexref::scene::Scene scene =
      flexref::scene::parse_scene(chain_text(static_cast<int>(st.range(0))), "chain");
  const auto stepper = flexref::lie::make_stepper("genalpha", *scene.model, {});
  stepper->initialize(0.0, scene.model->initial_state());
  long steps = 0;
  for (auto _ : st) {
    if (!stepper->step(kStep).ok) st.SkipWithError("genalpha failed");
    // A run of 0.5 s, as the table, then from the start again (outside the timing).
    if (++steps % 500 == 0) {
      st.PauseTiming();
      stepper->initialize(0.0, scene.model->initial_state());
      st.ResumeTiming();
    }
  }
  st.counters["evaluations_per_step"] = stepper->force_evaluations_per_step();
}

void BM_GenAlphaMatrix(benchmark::State& st) {
  const flexref::scene::Scene scene =
      flexref::scene::parse_scene(chain_text(static_cast<int>(st.range(0))), "chain");
  const flexref::core::Model& model = *scene.model;
  flexref::lie::detail::GenAlphaSystem system(model,
                                              flexref::lie::GenAlphaParameters::from_rho_inf(0.9));
  flexref::core::Workspace ws = model.make_workspace();
  flexref::core::Accelerations acc = model.make_accelerations();
  const flexref::core::State state = model.initial_state();
  model.compute_accelerations({0.0, 0.0}, state, ws, acc);
  Eigen::VectorXd vdot(system.body_unknowns());
  system.stack_accelerations(acc, vdot);
  system.begin_step(0.0, kStep, state, vdot, vdot);
  Eigen::VectorXd z(system.size()), r(system.size());
  const Eigen::VectorXd lambda = model.joint_multipliers(ws).on_rows(system.active_rows()) *
                                 (system.parameters().beta * kStep * kStep);
  system.predictor(lambda, z);
  system.residual(z, r);
  Eigen::SparseMatrix<double> S;
  system.make_iteration_matrix(S);
  flexref::lie::SparseLu lu;
  lu.analyze(static_cast<int>(S.rows()), S.outerIndexPtr(), S.innerIndexPtr());
  system.iteration_matrix(z, S);
  if (!lu.factor(S.valuePtr())) st.SkipWithError("KLU: singular");
  for (auto _ : st) {
    system.iteration_matrix(z, S);
    benchmark::DoNotOptimize(lu.factor(S.valuePtr()));
  }
  st.counters["evaluations"] = system.matrix_evaluations();
  st.counters["nonzeros"] = static_cast<double>(S.nonZeros());
}

}  // namespace

BENCHMARK(BM_DaeResidual)->RangeMultiplier(2)->Range(8, 256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IdaColouredMatrix)->RangeMultiplier(2)->Range(8, 256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IdaKluFactor)->RangeMultiplier(2)->Range(8, 256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IdaDenseMatrix)->RangeMultiplier(2)->Range(8, 64)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GenAlphaMatrix)->RangeMultiplier(2)->Range(8, 256)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GenAlphaStep)->RangeMultiplier(2)->Range(8, 256)->Unit(benchmark::kMicrosecond);
