/// Cost of one evaluation at(t) of the exact solutions in double (reference/exact_*.hpp): the
/// asymmetric torque-free body near its separatrix (book_toss's inertia after a pulse-like
/// perturbation: one AGM, one R_F, one R_J) and the bundled heavy top (one AGM, two R_F, two
/// R_J). The guard that writing them generic in the scalar type leaves double's speed alone.
#include <benchmark/benchmark.h>

#include <Eigen/Core>

#include "reference/exact_heavy_top.hpp"
#include "reference/exact_torque_free.hpp"

namespace {

namespace reference = flexref::reference;

void BM_TorqueFreeAt(benchmark::State& state) {
  // book_toss's J = diag(1, 2, 2.8) spun about the middle axis with a small transverse rate:
  // the elliptic regime close to the separatrix (k' ~ 1e-2), the expensive case.
  const reference::TorqueFreeExact exact(Eigen::Vector3d(1.0, 2.0, 2.8),
                                         Eigen::Vector4d(1.0, 0.0, 0.0, 0.0),
                                         Eigen::Vector3d(0.05, 10.0, 0.08));
  double t = 0.0;
  for (auto _ : state) {
    const reference::RigidAttitude a = exact.at(t);
    benchmark::DoNotOptimize(a.theta.data());
    benchmark::DoNotOptimize(a.w_B.data());
    t += 1e-3;
    if (t > 10.0) t = 0.0;
  }
}
BENCHMARK(BM_TorqueFreeAt);

void BM_HeavyTopAt(benchmark::State& state) {
  // scenes/heavy_top.toml: m = 15 kg, l = 1 m, J about the pivot: J⊥ = 0.234375 + 15,
  // J_a = 0.46875, spin 150 rad/s about the body y axis, axis initially horizontal.
  const reference::HeavyTopExact exact(
      15.0, 1.0, Eigen::Vector3d::UnitY(), 15.234375, 0.46875, Eigen::Vector3d(0.0, 0.0, -9.81),
      Eigen::Vector4d(1.0, 0.0, 0.0, 0.0), Eigen::Vector3d(0.0, 150.0, -4.61538));
  double t = 0.0;
  for (auto _ : state) {
    const reference::RigidAttitude a = exact.at(t);
    benchmark::DoNotOptimize(a.theta.data());
    benchmark::DoNotOptimize(a.w_B.data());
    t += 1e-3;
    if (t > 2.0) t = 0.0;
  }
}
BENCHMARK(BM_HeavyTopAt);

}  // namespace
