/// \file arkode_solver.cpp
/// ARKODE's ERKStep with the Fehlberg 13-7-8 table (ARKODE_FEHLBERG_13_7_8: 13 stages, order 8
/// with an embedded order-7 error estimate) on the quasi-velocity ODE form
/// (reference/ode_form.hpp): the third SUNDIALS reference, explicit and of high order, for
/// smooth non-stiff scenes (docs/references.md, "ARKODE").
///
/// - Error control and step-size adaptivity are ARKODE's (its default PID controller, the step
///   adapted after every step: ERKStepSetFixedStepBounds(1, 1), see the constructor).
/// - The segment loop is sundials_segment_driver.hpp: an exact stop (tstop) at every known load
///   discontinuity, root finding (ERKStepRootInit) for contact onset and release with a restart
///   at each.
/// - ARKODE is stepped one step at a time (ARK_ONE_STEP), so that outputs and event states come
///   at the method's order: ARKODE's own dense output is a Hermite polynomial of degree ≤ 5
///   (ARK_INTERP_MAX_DEGREE), below the method's order 8. An output inside a step comes from
///   the order-8 continuous extension of the step (reference/continuous_extension.hpp), the
///   state at a located root from one Fehlberg step of exactly the right length from the step's
///   start; both by a second ERKStep instance with fixed steps. The output grid never shortens
///   the steps: the step sequence is the tolerance's (a tstop at every output would make it the
///   grid's, and the work-precision curve flat).
/// - In contact (a switching function not positive at a step's start) every step is checked
///   against two steps of half its length: the Fehlberg 13-7-8 error estimate compares only the
///   stages at the step's ends (b − b̃ is zero but for stages 1, 11, 12, 13) and accepts a step
///   across a whole stiff contact phase. A step whose halves disagree (ARKODE's WRMS error norm
///   > 1) is discarded and retried from its start with the order-8 controller's smaller step.
/// - No projection (ERKStep has none): |θ| is a first integral of the form, which is
///   homogeneous in θ; θ is renormalized at every restart.
/// - SolverOptions::max_steps bounds the steps between two consecutive output times (ARKODE's
///   mxstep meaning), reported as ARK_TOO_MUCH_WORK.
#include <memory>
#include <optional>
#include <vector>

#include "reference/arkode_esdirk_solver.hpp"
#include "reference/arkode_segment_solver.hpp"
#include "reference/method_choice.hpp"
#include "reference/reference_solver.hpp"
#include "reference/sundials_segment_driver.hpp"

namespace flexref::reference {
namespace {

namespace sun = sundials;
using arkode_detail::ArkodeSegmentSolver;

}  // namespace

ReferenceRun solve_arkode(const core::Model& model, const std::vector<double>& output_times,
                          const SolverOptions& options) {
  // One spectrum for the method and Baumgarte's rate, taken where either needs it.
  const double spacing = mean_output_spacing(output_times);
  std::optional<StiffnessSummary> summary;
  const auto summarized = [&]() -> const StiffnessSummary& {
    if (!summary) summary = summarize_stiffness(model, spacing);
    return *summary;
  };
  ArkodeMethodChoice choice{options.arkode_method, "chosen with --method"};
  if (options.arkode_method == ArkodeMethod::kAuto) choice = choose_arkode_method(summarized());
  if (choice.method == ArkodeMethod::kEsdirk) {
    ReferenceRun run = solve_arkode_esdirk(model, output_times, options);
    run.method_reason = choice.reason;
    return run;
  }
  // ERKStep has no projection: the joints' drift is damped instead (Baumgarte).
  const double stabilization =
      model.has_constraints() ? constraint_stabilization_rate(model, summarized(), spacing) : 0.0;
  ReferenceRun run = sun::integrate_segments(model, output_times, options, "arkode", [&] {
    return std::make_unique<ArkodeSegmentSolver>(model, options, stabilization);
  });
  run.method = "erk-fehlberg-13-7-8";
  run.method_reason = choice.reason;
  return run;
}

}  // namespace flexref::reference
