/// \file wear_jump_study_test.cpp
/// Label `study` (long: ~14 min on two busy cores): issue 48's targets for the multi-scale wear
/// scheme on scenes/tube_support_wear.toml against its fully coupled reference (docs/wear.md,
/// "What it found on the tube"), with the options of the two studies docs/wear.md reports:
///   - the slow-time orders (windows settled by a 0.2 s transient, jumps 10 to 1.25 s, rtol
///     1e-9): Euler 1 and Heun 2 within 0.3, AB2's 10 s jump named unstable;
///   - the speed-up (the cheap windows, 0.05 s of transient, rtol 1e-8): a level within 1 % of
///     the reference while simulating at most a hundredth of its dynamics.
/// Prints both tables.
#include <catch2/catch.hpp>
#include <cstdio>
#include <string>

#include "scene/scene_reader.hpp"
#include "studies/parallel.hpp"
#include "studies/wear_jump.hpp"

namespace flexref::studies {
namespace {

const std::string kTubeWear = "scenes/tube_support_wear.toml";

const WearJumpFit& tube_fit(const WearJumpResult& r, const std::string& slow) {
  for (const WearJumpFit& f : r.fits) {
    if (f.slow == slow) return f;
  }
  FAIL("no fit for " << slow);
  return r.fits.front();
}

}  // namespace

TEST_CASE("tube_support_wear: wear-jump observes Euler's order 1 and Heun's order 2", "[wear]") {
  const scene::Scene scene = scene::read_scene(kTubeWear);
  WearJumpOptions o;
  o.jump_counts = {8, 16, 32, 64};
  o.base.window = 0.025;
  o.base.transient = 0.2;
  o.base.until = scene.end_time;
  o.base.rtol = 1e-9;
  o.base.output_step = 0.01;  // as the command line: the scene's output step
  o.jobs = default_jobs();
  const WearJumpResult r = run_wear_jump(scene.spec, o);
  std::printf("%s", format_wear_jump(r).c_str());
  // The target: the claimed order within 0.3 (measured 0.98 and 1.92; the fits use
  // the distances between levels, whose shared limit, 4e-5 from the reference, cancels).
  const WearJumpFit& euler = tube_fit(r, "euler");
  const WearJumpFit& heun = tube_fit(r, "heun");
  CHECK(euler.observed == Approx(1.0).margin(0.3));
  CHECK(heun.observed == Approx(2.0).margin(0.3));
  // Both integrators converge to the same limit, the averaged dynamics: their Richardson
  // limits' errors against the reference agree to the extrapolation's accuracy (at most a
  // quarter of the finest level's slow-time error, tests/studies/wear_cycle_jump_test.cpp;
  // Euler's finest distance is 1.1e-3, so 3e-4), and stay below 1e-4 (measured 3.6e-5 and
  // 4.6e-5: the averaging error of this scene at its acceleration factor).
  CHECK(std::abs(euler.limit_error - heun.limit_error) < 3e-4);
  CHECK(heun.limit_error < 1e-4);
  // AB2 with 10 s jumps is beyond its stability limit (the slow system decays at λ ≈ −0.15
  // 1/s: λD = −1.5 against AB2's −1), and named so.
  for (const WearJumpRow& row : r.rows) {
    if (row.slow == "ab2" && row.jumps == 8) CHECK(row.status == "unstable");
  }
}

TEST_CASE("tube_support_wear: wear-jump is within 1 % of the reference at a 100x speed-up",
          "[wear]") {
  const scene::Scene scene = scene::read_scene(kTubeWear);
  WearJumpOptions o;
  o.jump_counts = {8, 16, 32, 64};
  o.base.window = 0.025;
  o.base.transient = 0.05;
  o.base.until = scene.end_time;
  o.base.rtol = 1e-8;
  o.base.output_step = 0.01;
  o.jobs = default_jobs();
  const WearJumpResult r = run_wear_jump(scene.spec, o);
  std::printf("%s", format_wear_jump(r).c_str());
  // The speed-up in simulated dynamics (the CPU ratio is measured, not asserted: the windows
  // cost the reference's CPU per simulated second, docs/wear.md): 80 s against ≤ 0.8 s.
  bool reached = false;
  for (const WearJumpRow& row : r.rows) {
    const double simulated = o.base.until / row.fast_time;
    std::printf("%s %d jumps: error %.3g, %.0fx less dynamics, CPU speed-up %.0f, %s\n",
                row.slow.c_str(), row.jumps, row.error, simulated, row.speedup, row.status.c_str());
    reached = reached || (row.status == "ok" && row.error <= 0.01 && simulated >= 100.0);
  }
  CHECK(reached);
}

}  // namespace flexref::studies
