/// \file ida_solver_test.cpp
/// IDA-specific checks (reference/ida_solver.cpp); the checks every reference solver shares
/// are in solver_conformance_test.cpp.
#include <catch2/catch.hpp>

#include "core/model.hpp"
#include "core/output_times.hpp"
#include "reference/reference_solver.hpp"
#include "tests/support/solver_options.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::reference {
namespace {

using testing::with_rtol;

}  // namespace

TEST_CASE("ida restarts at a load switch at tight tolerance", "[ida]") {
  // Regression: with the former index-2 DAE form, in a trial configuration (a tighter Newton
  // test, IDA's default Jacobian reuse) IDA stalled at rtol 1e-13 right after the restart at
  // t = 0.1, with h ~ 1e-18 until mxstep: its first step after a restart is ∝ rtol, where that
  // iteration matrix (condition ~ 1/h²) was hardest to converge. The implicit form's matrix is
  // c_j blockdiag(I, M) − ∂f/∂y, well conditioned; the restart must still get through with no
  // convergence failure; 1e5 steps per output interval is ample (the run takes ~1e3).
  const core::Model model = testing::book_toss();
  SolverOptions options = with_rtol(1e-13);
  options.max_steps = 100'000;
  const ReferenceRun run = solve_ida(model, core::output_times(1.0, 0.01), options);
  CHECK(run.trajectory.states.size() == 101);
  CHECK(run.stats.nonlinear_failures == 0);
}

}  // namespace flexref::reference
