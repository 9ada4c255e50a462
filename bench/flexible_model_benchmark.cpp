/// Cost of one evaluation of the flexible models (docs/performance.md, "Flexible bodies"), on
/// flexible_spinner (tests/support/flexible_models.hpp: a free rigid hub carrying a clamped-free
/// beam, n bending modes of both planes, the world torque pulse) at a generic state (deformed,
/// vibrating, tumbling, inside the pulse):
///
///   BM_CoupledRhs/n/elements   OdeForm::rhs of the coupled model: loads, the inertia terms
///                              (M blocks, Qv) and the structured solve (Schur complement of the
///                              rigid rows against the constant factor of m_ff)
///   BM_LteRhs/n/elements       the same for the LTE model (inertia terms at q_f = 0; 6×6 rigid
///                              Cholesky and the constant modal mass's solve)
///   BM_InertiaTerms/n/elements evaluate_inertia_terms alone (12 n×n matrix–vector products)
///   BM_StructuredSolve/n/e     solve_coupled alone (free body: 6×6 Schur complement)
///   BM_DenseCholesky/n/e       for comparison, what the structured solve replaces: the
///                              Cholesky factorization and solve of the dense (6+n)² M
///   BM_MassAndQvByNodes/n/e    M and Qv as the O(N n²) direct nodal sums, for comparison
///   BM_OdeJacobian/n/elements  StructuredJacobian::evaluate (reference/structured_jacobian.hpp):
///   the dense
///                              ∂f/∂y of the ODE form, structured
///   BM_DifferenceJacobian/n/e  for comparison, what CVODE's dense linear solver does without
///                              a Jacobian function: one right-hand side per column of y
///                              (forward differences, cvLsDenseDQJac)
///
/// The invariants are computed once when the model is built, so nothing but the by-nodes sums
/// should depend on the element count. Counter allocs_per_eval: heap allocations of one
/// evaluation (counted once, outside the timed loop; must be 0 for the first four).
#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "core/body.hpp"
#include "core/model.hpp"
#include "flexible/flexible_dynamics.hpp"
#include "flexible/inertia_terms.hpp"
#include "flexible/mass_matrix_solve.hpp"
#include "reference/ode_form.hpp"
#include "reference/structured_jacobian.hpp"
#include "rotation/euler_parameters.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/flexible_models.hpp"

namespace reference = flexref::reference;

namespace {

using flexref::core::FlexibleFormulation;
using flexref::core::Model;
using flexref::reference::OdeForm;

/// A generic state: tilted and tumbling hub, deformed and vibrating beam.
flexref::core::State generic_state(const Model& model) {
  flexref::core::State s = model.initial_state();
  const Eigen::Index n = model.body(0).mode_count();
  s[0].theta_WB = Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized();
  s[0].w_WB_B = Eigen::Vector3d(0.3, -0.2, 1.1);
  s[0].v_WBr = Eigen::Vector3d(0.01, -0.02, 0.005);
  s[0].q_f.resize(n);
  s[0].qd_f.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double k = static_cast<double>(i + 1);
    s[0].q_f[i] = 0.02 / (k * k) * (i % 3 == 0 ? -1.0 : 1.0);
    s[0].qd_f[i] = 0.1 / k * (i % 2 == 0 ? 1.0 : -1.0);
  }
  return s;
}

void BM_Rhs(benchmark::State& state, FlexibleFormulation formulation, bool stiffened = false) {
  const int modes = static_cast<int>(state.range(0));
  const int elements = static_cast<int>(state.range(1));
  const Model model =
      flexref::testing::flexible_spinner_model(formulation, modes, elements, 5.0, stiffened);
  const reference::OdeForm form(model);
  reference::OdeForm::Scratch scratch = form.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(form.size()));
  std::vector<double> ydot(y.size());
  form.pack(generic_state(model), y.data());
  const flexref::core::LoadContext context{0.25, 0.25};  // inside the torque pulse
  form.rhs(context, y.data(), ydot.data(), scratch);     // warm-up
  const long allocations = flexref::testing::count_allocations(
      [&] { form.rhs(context, y.data(), ydot.data(), scratch); });
  for (auto _ : state) {
    form.rhs(context, y.data(), ydot.data(), scratch);
    benchmark::DoNotOptimize(ydot.data());
    benchmark::ClobberMemory();
  }
  state.counters["modes"] = modes;
  state.counters["nodes"] =
      static_cast<double>(model.body(0).description().flexible->modal.p_BoNode_B.cols());
  state.counters["allocs_per_eval"] = static_cast<double>(allocations);
}

void BM_CoupledRhs(benchmark::State& state) { BM_Rhs(state, FlexibleFormulation::kCoupled); }
void BM_LteRhs(benchmark::State& state) { BM_Rhs(state, FlexibleFormulation::kLte); }
/// The coupled model with geometric stiffening (docs/geometric_stiffening.md).
void BM_StiffenedRhs(benchmark::State& state) {
  BM_Rhs(state, FlexibleFormulation::kCoupled, true);
}

/// n = 4, 16, 64, 128 on 40 elements; 20 vs 200 elements at n = 8.
void ModeAndElementArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"n", "elements"});
  for (int n : {4, 16, 64, 128}) b->Args({n, 40});
  for (int e : {20, 200}) b->Args({8, e});
}
BENCHMARK(BM_CoupledRhs)->Apply(ModeAndElementArgs);
BENCHMARK(BM_LteRhs)->Apply(ModeAndElementArgs);
BENCHMARK(BM_StiffenedRhs)->Apply(ModeAndElementArgs);

/// The body, its state and attitude at the generic state of a spinner with n modes.
struct BodyAtState {
  explicit BodyAtState(benchmark::State& state)
      : model(flexref::testing::flexible_spinner_model(FlexibleFormulation::kCoupled,
                                                       static_cast<int>(state.range(0)),
                                                       static_cast<int>(state.range(1)))),
        s(generic_state(model)[0]),
        R_WB(flexref::rotation::rotation_matrix(s.theta_WB)) {}
  const flexref::core::Body& body() const { return model.body(0); }
  int modes() const { return model.body(0).mode_count(); }
  Model model;
  flexref::core::BodyState s;
  Eigen::Matrix3d R_WB;
};

template <typename F>
void time_evaluation(benchmark::State& state, int modes, F&& evaluate) {
  evaluate();
  const long allocations = flexref::testing::count_allocations(evaluate);
  for (auto _ : state) {
    evaluate();
    benchmark::ClobberMemory();
  }
  state.counters["modes"] = modes;
  state.counters["allocs_per_eval"] = static_cast<double>(allocations);
}

void BM_InertiaTerms(benchmark::State& state) {
  const BodyAtState b(state);
  flexref::flexible::InertiaTerms terms = flexref::flexible::make_inertia_terms(b.modes());
  time_evaluation(state, b.modes(), [&] {
    flexref::flexible::evaluate_inertia_terms(b.body().invariants(), b.R_WB, b.s.q_f, b.s.w_WB_B,
                                              b.s.qd_f, terms);
    benchmark::DoNotOptimize(terms.Qv.data());
  });
}

void BM_StructuredSolve(benchmark::State& state) {
  const BodyAtState b(state);
  const int n = b.modes();
  flexref::flexible::InertiaTerms terms = flexref::flexible::make_inertia_terms(n);
  flexref::flexible::evaluate_inertia_terms(b.body().invariants(), b.R_WB, b.s.q_f, b.s.w_WB_B,
                                            b.s.qd_f, terms);
  flexref::flexible::MassSolveScratch scratch = flexref::flexible::make_mass_solve_scratch(n);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(6 + n, -1.0, 1.0);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(6 + n);
  time_evaluation(state, n, [&] {
    flexref::flexible::solve_coupled(b.body().modal_mass(), terms, 0, rhs, scratch, x);
    benchmark::DoNotOptimize(x.data());
  });
}

void BM_DenseCholesky(benchmark::State& state) {
  const BodyAtState b(state);
  const int n = b.modes();
  Eigen::MatrixXd M(6 + n, 6 + n);
  flexref::flexible::flexible_mass_matrix(b.body().invariants(), b.R_WB, b.s.q_f, M);
  Eigen::LLT<Eigen::MatrixXd> llt(6 + n);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(6 + n, -1.0, 1.0);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(6 + n);
  time_evaluation(state, n, [&] {
    llt.compute(M);
    x = llt.solve(rhs);
    benchmark::DoNotOptimize(x.data());
  });
}

void BM_MassAndQvByNodes(benchmark::State& state) {
  const BodyAtState b(state);
  const int n = b.modes();
  Eigen::MatrixXd M(6 + n, 6 + n);
  Eigen::VectorXd Qv(6 + n);
  const flexref::flexible::ModalData& data = b.body().description().flexible->modal;
  time_evaluation(state, n, [&] {
    flexref::flexible::flexible_mass_matrix_by_nodes(data, b.R_WB, b.s.q_f, M);
    flexref::flexible::flexible_quadratic_velocity_by_nodes(data, b.R_WB, b.s.q_f, b.s.w_WB_B,
                                                            b.s.qd_f, Qv);
    benchmark::DoNotOptimize(M.data());
    benchmark::DoNotOptimize(Qv.data());
  });
}

void BM_OdeJacobian(benchmark::State& state) {
  const BodyAtState b(state);
  const OdeForm form(b.model);
  const reference::StructuredJacobian jacobian(form);
  reference::StructuredJacobian::Scratch scratch = jacobian.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(form.size()));
  form.pack(generic_state(b.model), y.data());
  Eigen::MatrixXd J(form.size(), form.size());
  const flexref::core::LoadContext context{0.25, 0.25};
  time_evaluation(state, b.modes(), [&] {
    jacobian.evaluate(context, y.data(), J, scratch);
    benchmark::DoNotOptimize(J.data());
  });
}

void BM_DifferenceJacobian(benchmark::State& state) {
  const BodyAtState b(state);
  const OdeForm form(b.model);
  OdeForm::Scratch scratch = form.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(form.size()));
  form.pack(generic_state(b.model), y.data());
  std::vector<double> f0(y.size());
  Eigen::MatrixXd J(form.size(), form.size());
  const flexref::core::LoadContext context{0.25, 0.25};
  time_evaluation(state, b.modes(), [&] {
    form.rhs(context, y.data(), f0.data(), scratch);
    for (int c = 0; c < form.size(); ++c) {
      const double y_c = y[static_cast<std::size_t>(c)];
      const double h = 1.5e-8 * std::max(1.0, std::abs(y_c));
      y[static_cast<std::size_t>(c)] = y_c + h;
      form.rhs(context, y.data(), J.col(c).data(), scratch);
      y[static_cast<std::size_t>(c)] = y_c;
      for (int r = 0; r < form.size(); ++r)
        J(r, c) = (J(r, c) - f0[static_cast<std::size_t>(r)]) / h;
    }
    benchmark::DoNotOptimize(J.data());
  });
}

BENCHMARK(BM_InertiaTerms)->Apply(ModeAndElementArgs);
BENCHMARK(BM_StructuredSolve)->Apply(ModeAndElementArgs);
BENCHMARK(BM_DenseCholesky)->Apply(ModeAndElementArgs);
BENCHMARK(BM_MassAndQvByNodes)->Apply(ModeAndElementArgs);
BENCHMARK(BM_OdeJacobian)->Apply(ModeAndElementArgs);
BENCHMARK(BM_DifferenceJacobian)->Apply(ModeAndElementArgs);

}  // namespace
