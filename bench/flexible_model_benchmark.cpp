/// Cost of one evaluation of the flexible models (docs/performance.md, "Flexible bodies"), on
/// flexible_spinner (tests/support/flexible_models.hpp: a free rigid hub carrying a clamped-free
/// beam, n bending modes of both planes, the world torque pulse) at a generic state (deformed,
/// vibrating, tumbling, inside the pulse):
///
///   BM_CoupledRhs/n/elements   OdeForm::rhs of the coupled model: loads, M(θ, q_f), Qv, the
///                              Cholesky factorization of the (6+n)² unknown rows and the solve
///   BM_LteRhs/n/elements       the same for the LTE model (M at q_f = 0; 6×6 rigid Cholesky and
///                              the constant modal mass's solve)
///   BM_MassAndQv/n/elements    flexible_mass_matrix + flexible_quadratic_velocity alone
///   BM_MassAndQvByNodes/n/e    the same as the O(N n²) direct nodal sums, for comparison
///
/// The invariants are computed once when the model is built, so nothing but the by-nodes sums
/// should depend on the element count. Counter allocs_per_eval: heap allocations of one
/// evaluation (counted once, outside the timed loop; must be 0 for the first three).
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <vector>

#include "core/body.hpp"
#include "core/model.hpp"
#include "flexible/flexible_dynamics.hpp"
#include "reference/ode_form.hpp"
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

void BM_Rhs(benchmark::State& state, FlexibleFormulation formulation) {
  const int modes = static_cast<int>(state.range(0));
  const int elements = static_cast<int>(state.range(1));
  const Model model = flexref::testing::flexible_spinner_model(formulation, modes, elements);
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

/// n = 4, 16, 64 on 40 elements; 20 vs 200 elements at n = 8.
void ModeAndElementArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"n", "elements"});
  for (int n : {4, 16, 64}) b->Args({n, 40});
  for (int e : {20, 200}) b->Args({8, e});
}
BENCHMARK(BM_CoupledRhs)->Apply(ModeAndElementArgs);
BENCHMARK(BM_LteRhs)->Apply(ModeAndElementArgs);

template <bool kByNodes>
void BM_MassAndQvImpl(benchmark::State& state) {
  const int modes = static_cast<int>(state.range(0));
  const int elements = static_cast<int>(state.range(1));
  const Model model =
      flexref::testing::flexible_spinner_model(FlexibleFormulation::kCoupled, modes, elements);
  const flexref::core::Body& body = model.body(0);
  const flexref::core::BodyState s = generic_state(model)[0];
  const Eigen::Matrix3d R_WB = flexref::rotation::rotation_matrix(s.theta_WB);
  Eigen::MatrixXd M(6 + modes, 6 + modes);
  Eigen::VectorXd Qv(6 + modes);
  const auto evaluate = [&] {
    if constexpr (kByNodes) {
      const flexref::flexible::ModalData& data = body.description().flexible->modal;
      flexref::flexible::flexible_mass_matrix_by_nodes(data, R_WB, s.q_f, M);
      flexref::flexible::flexible_quadratic_velocity_by_nodes(data, R_WB, s.q_f, s.w_WB_B, s.qd_f,
                                                              Qv);
    } else {
      flexref::flexible::flexible_mass_matrix(body.invariants(), R_WB, s.q_f, M);
      flexref::flexible::flexible_quadratic_velocity(body.invariants(), R_WB, s.q_f, s.w_WB_B,
                                                     s.qd_f, Qv);
    }
  };
  evaluate();
  const long allocations = flexref::testing::count_allocations(evaluate);
  for (auto _ : state) {
    evaluate();
    benchmark::DoNotOptimize(M.data());
    benchmark::DoNotOptimize(Qv.data());
    benchmark::ClobberMemory();
  }
  state.counters["modes"] = modes;
  state.counters["allocs_per_eval"] = static_cast<double>(allocations);
}

void BM_MassAndQv(benchmark::State& state) { BM_MassAndQvImpl<false>(state); }
void BM_MassAndQvByNodes(benchmark::State& state) { BM_MassAndQvImpl<true>(state); }
BENCHMARK(BM_MassAndQv)->Apply(ModeAndElementArgs);
BENCHMARK(BM_MassAndQvByNodes)->Apply(ModeAndElementArgs);

}  // namespace
