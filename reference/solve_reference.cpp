#include "reference/solve_reference.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/joint_check.hpp"
#include "reference/exact_solution.hpp"
#include "reference/reduced_cvode.hpp"
#include "reference/solve_progress.hpp"

namespace flexref::reference {

std::vector<std::string> reference_solver_names() {
  return {"ida", "cvode", "arkode", "odeint", "exact"};
}

namespace {

bool finite(const core::State& state) {
  for (const core::BodyState& b : state) {
    if (!b.p_WBr.allFinite() || !b.theta_WB.allFinite() || !b.v_WBr.allFinite() ||
        !b.w_WB_B.allFinite() || !b.q_f.allFinite() || !b.qd_f.allFinite()) {
      return false;
    }
  }
  return true;
}

ReferenceRun dispatch(const std::string& solver, const core::Model& model,
                      const std::vector<double>& output_times, const SolverOptions& options) {
  if (options.coordinates == Coordinates::kJoint && solver != "cvode") {
    throw std::invalid_argument("joint coordinates: only cvode integrates them (" + solver +
                                " integrates the maximal form)");
  }
  if (solver == "ida") return solve_ida(model, output_times, options);
  if (solver == "cvode") return solve_cvode_in_coordinates(model, output_times, options);
  if (solver == "arkode") return solve_arkode(model, output_times, options);
  if (solver == "odeint") return solve_odeint(model, output_times, options);
  if (solver == "exact") return solve_exact(model, output_times);
  throw std::invalid_argument("unknown reference solver '" + solver +
                              "' (ida, cvode, arkode, odeint, exact)");
}

}  // namespace

void check_finite(const ReferenceRun& run, const core::Model& model) {
  const core::Trajectory& trajectory = run.trajectory;
  if (trajectory.states.size() != trajectory.times.size()) {
    throw core::SolverError(
        run.solver, trajectory.times.empty() ? 0.0 : trajectory.times.back(), -1,
        "returned " + std::to_string(trajectory.states.size()) + " states for " +
            std::to_string(trajectory.times.size()) + " output times");
  }
  core::Workspace ws = model.make_workspace();
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    const core::State& state = trajectory.states[k];
    std::string why;
    if (!finite(state)) {
      why = "the state at this output time is not finite (inf or NaN)";
    } else {
      const double kinetic = model.kinetic_energy(state);
      const double potential = model.potential_energy(core::LoadContext{t, t}, state, ws);
      if (!std::isfinite(kinetic) || !std::isfinite(potential)) {
        std::ostringstream out;
        out << "the energy at this output time is not finite (kinetic " << kinetic
            << " J, potential " << potential << " J)";
        why = out.str();
      } else if (k < trajectory.dissipated_work.size() &&
                 !std::isfinite(trajectory.dissipated_work[k])) {
        why = "the dissipated work at this output time is not finite";
      }
    }
    if (!why.empty()) {
      throw core::SolverError(run.solver, t, -1,
                              why + ": the solution overflowed double precision or diverged");
    }
  }
}

void check_joints(const ReferenceRun& run, const core::Model& model) {
  if (!model.has_constraints()) return;
  const double bound = core::joint_violation_bound(
      run.options.rtol, run.options.absolute_tolerance(), model.joint_length_scale());
  if (const std::optional<core::JointBreach> breach =
          core::find_joint_breach(model, run.trajectory, bound)) {
    throw core::SolverError(run.solver, breach->t, -1, breach->describe());
  }
}

ReferenceRun solve_reference(const std::string& solver, const core::Model& model,
                             const std::vector<double>& output_times,
                             const SolverOptions& options) {
  if (options.progress != nullptr && !output_times.empty()) {
    options.progress->start_solve(output_times.front(), output_times.back());
  }
  ReferenceRun run = dispatch(solver, model, output_times, options);
  // A finished solve has reached the end (the exact solution reports no time on its way).
  if (options.progress != nullptr && !output_times.empty()) {
    options.progress->reached(output_times.back());
  }
  // The progress channel belongs to the caller's progress line, which may end before the run.
  run.options.progress = nullptr;
  check_finite(run, model);
  check_joints(run, model);
  return run;
}

}  // namespace flexref::reference
