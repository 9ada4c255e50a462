/// Cost of one step of C1, C2, NMB and genalpha on book_toss (one free rigid body, a world
/// torque pulse; no output), of one step of the hybrid scheme on flexible_spinner, of one
/// genalpha step on Andrews' squeezer (7 bodies, 41 independent joint rows; no other scheme
/// steps ideal joints), and of one force evaluation for comparison. The book keeps tumbling
/// torque-free after the pulse, so stepping on past the scene's end is representative.
#include <benchmark/benchmark.h>

#include <string>

#include "core/model.hpp"
#include "lie/stepper.hpp"
#include "scene/scene_reader.hpp"
#include "tests/support/flexible_models.hpp"
#include "tests/support/test_problems.hpp"

namespace {

using flexref::core::Model;

void BM_SchemeStep(benchmark::State& state, const std::string& scheme) {
  const Model model = flexref::testing::book_toss();
  const auto stepper = flexref::lie::make_stepper(scheme, model, {});
  stepper->initialize(0.0, model.initial_state());
  const double h = 1e-3;  // h|W| = 0.01: inside every scheme's asymptotic range on book_toss
  for (auto _ : state) {
    const flexref::lie::StepStatus status = stepper->step(h);
    benchmark::DoNotOptimize(status.ok);
  }
  state.counters["force_evals_per_step"] = stepper->force_evaluations_per_step();
}
BENCHMARK_CAPTURE(BM_SchemeStep, c1, std::string("c1"));
BENCHMARK_CAPTURE(BM_SchemeStep, c2, std::string("c2"));
BENCHMARK_CAPTURE(BM_SchemeStep, nmb, std::string("nmb"));
BENCHMARK_CAPTURE(BM_SchemeStep, genalpha, std::string("genalpha"));

// genalpha on Andrews' squeezer at h = 1e-4 (its output step; order 2 from there,
// docs/schemes.md). The mechanism turns at ~1e3 rad/s after 3 ms: the benchmark restarts from
// the initial state every 300 steps (t = 0.03 s, the scene's horizon), outside the timing.
void BM_GenAlphaAndrews(benchmark::State& state) {
  const flexref::scene::Scene scene =
      flexref::scene::read_scene(FLEXREF_SOURCE_DIR "/scenes/andrews_squeezer.toml");
  const Model& model = *scene.model;
  const auto stepper = flexref::lie::make_stepper("genalpha", model, {});
  stepper->initialize(0.0, model.initial_state());
  int steps = 0;
  for (auto _ : state) {
    if (steps == 300) {
      state.PauseTiming();
      stepper->initialize(0.0, model.initial_state());
      steps = 0;
      state.ResumeTiming();
    }
    const flexref::lie::StepStatus status = stepper->step(1e-4);
    benchmark::DoNotOptimize(status.ok);
    ++steps;
  }
  state.counters["force_evals_per_step"] = stepper->force_evaluations_per_step();
}
BENCHMARK(BM_GenAlphaAndrews);

// The hybrid scheme on flexible_spinner (LTE model, 4 bending modes, 10 elements): rotation by
// the scheme, central differences for translation and modes. h = 1e-3 is below the explicit
// limit 2/ω_max = 0.05; the spinner keeps spinning and vibrating past the pulse.
void BM_HybridStep(benchmark::State& state, const std::string& scheme) {
  const Model model =
      flexref::testing::flexible_spinner_model(flexref::core::FlexibleFormulation::kLte);
  const auto stepper = flexref::lie::make_stepper(scheme, model, {});
  stepper->initialize(0.0, model.initial_state());
  const double h = 1e-3;
  for (auto _ : state) {
    const flexref::lie::StepStatus status = stepper->step(h);
    benchmark::DoNotOptimize(status.ok);
  }
  state.counters["force_evals_per_step"] = stepper->force_evaluations_per_step();
}
BENCHMARK_CAPTURE(BM_HybridStep, c1_flexible_spinner, std::string("c1"));
BENCHMARK_CAPTURE(BM_HybridStep, c2_flexible_spinner, std::string("c2"));
BENCHMARK_CAPTURE(BM_HybridStep, nmb_flexible_spinner, std::string("nmb"));

void BM_ForceEvaluation(benchmark::State& state) {
  const Model model = flexref::testing::book_toss();
  const flexref::core::State s = model.initial_state();
  flexref::core::Workspace ws = model.make_workspace();
  double t = 0.0;
  for (auto _ : state) {
    model.compute_wrenches(flexref::core::LoadContext{t, t}, s, ws);
    benchmark::DoNotOptimize(ws.wrenches[0].tau_Br_W.data());
    t = t < 0.09 ? t + 1e-3 : 0.0;  // inside the pulse: the sin² branch is evaluated
  }
}
BENCHMARK(BM_ForceEvaluation);

}  // namespace
