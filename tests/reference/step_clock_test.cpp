/// \file step_clock_test.cpp
/// reference/step_clock.hpp: the exact sum of a solver's steps against its rounded clock.
#include "reference/step_clock.hpp"

#include <catch2/catch.hpp>

namespace flexref::reference {
namespace {

/// A solver's clock as CVODE and IDA keep it: t ← fl(t + h) after every accepted step.
struct RoundedClock {
  double t = 0.0;
  long steps = 0;
  void step(double h) {
    t += h;
    ++steps;
  }
};

}  // namespace

TEST_CASE("the step clock sums a solver's steps exactly", "[step_clock]") {
  // 200 000 steps of h = 1e-5 from t = 0.25: fl(t + h) rounds every step, and with h held the
  // rounding errors add up (the bias the clock exists for). The exact elapsed time is
  // 200 000 × h in exact arithmetic: h is a double, 200 000 < 2^18, so the product needs at most
  // 53 + 18 bits and long double's 64-bit significand holds it to ~2^-64 relative (1e-20 s).
  const double t0 = 0.25, h = 1e-5;
  const long n = 200'000;
  StepClock clock;
  clock.start_run(t0);
  RoundedClock solver{t0, 0};
  for (long k = 0; k < n; ++k) {
    solver.step(h);
    clock.record(solver.steps, h, solver.t);
  }
  const long double exact =
      static_cast<long double>(t0) + static_cast<long double>(n) * static_cast<long double>(h);
  const long double drift = static_cast<long double>(solver.t) - exact;
  CAPTURE(static_cast<double>(drift), clock.offset());
  // The rounded clock must have drifted for this test to test anything: its 200 000 roundings
  // of ≤ ulp(2)/2 = 2.2e-16 each would add to ≤ 4.4e-11 s; they add to 6.2e-12 s.
  REQUIRE(std::abs(static_cast<double>(drift)) > 1e-13);
  // offset() = t_solver − Σ h to the compensated sum's accuracy (~1e-31 s) plus the reference's
  // (1e-20 s): 1e-18 s is 1e5 × both and 1e-6 × the drift.
  CHECK(std::abs(clock.offset() - static_cast<double>(drift)) <= 1e-18);
  CHECK(clock.run_steps() == n);
  // The mean step: Σ h / n = h up to the division's rounding (1e-16 relative).
  CHECK(clock.mean_step() == Approx(h).epsilon(1e-14));
}

TEST_CASE("the step clock adds each step once and restarts with the solver", "[step_clock]") {
  StepClock clock;
  clock.start_run(0.0);
  CHECK(clock.mean_step() == 0.0);  // before the first step
  clock.record(1, 0.5, 0.5);
  clock.record(1, 0.5, 0.5);  // the same count again (a second callback before the next step)
  CHECK(clock.run_steps() == 1);
  clock.record(2, 0.25, 0.75);
  CHECK(clock.run_steps() == 2);
  CHECK(clock.offset() == 0.0);  // 0.5 + 0.25 is exact in binary
  CHECK(clock.mean_step() == 0.375);

  // A re-initialization at t = 1 (after an event): the solver counts from 0 again, the run's
  // steps and mean go on.
  clock.restart(1.0);
  CHECK(clock.offset() == 0.0);
  clock.record(1, 1.0, 2.0);
  CHECK(clock.run_steps() == 3);
  CHECK(clock.mean_step() == Approx(2.0 / 3.0).epsilon(1e-15));  // 2 s over 3 steps

  // Steps the clock did not see one by one (the solver's count went from 1 to 4): it cannot know
  // their sum and takes the solver's time as exact (offset 0), counting them.
  clock.record(4, 0.5, 3.0);
  CHECK(clock.run_steps() == 6);
  CHECK(clock.offset() == 0.0);
}

}  // namespace flexref::reference
