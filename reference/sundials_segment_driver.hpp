#pragma once
/// \file sundials_segment_driver.hpp
/// The segment loop every SUNDIALS reference shares (docs/design/schemes.md, "Reference
/// integrators"): [0, T] split at the model's known load discontinuities (plan_segments), each
/// segment integrated without restart up to an exact stop (the solver's tstop) at its end, the
/// outputs it owns filled by the solver's own dense output (its NORMAL mode with tout = each
/// output time), and a restart at every located root of the switching functions (contact onset
/// and release), so that no step straddles a load switch or a contact event.
///
/// What differs between the solvers — the form they integrate (ODE or DAE), how they start,
/// restart and count — is behind SegmentSolver; the loop, the event record, the counters'
/// accumulation, the CPU clock and the failure report are here once. Boost.Odeint
/// (odeint_solver.cpp) keeps its own loop: it is the independent code path.
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "core/state.hpp"
#include "reference/reference_solver.hpp"
#include "reference/sundials_handle.hpp"

namespace flexref::reference::sundials {

/// Thrown by SegmentSolver::start_segment when no solution can start from the state (the loads
/// are not finite there); reported as a core::SolverError at the segment's start.
class StartError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One SUNDIALS integrator (CVODE, IDA, ARKODE) as the segment loop drives it. Implementations
/// own their SUNDIALS handles and callback data; every call may throw SundialsError.
class SegmentSolver {
 public:
  virtual ~SegmentSolver() = default;

  /// Starts `segment` at segment.start from `state` with the integrals tracked with the state
  /// (W_d and the model's extra integrals, OdeForm::integral_count() values): the first call
  /// initializes the solver, later ones re-initialize it; sets the stop time to segment.end and
  /// makes every callback evaluate the loads with t_segment = segment.t_segment.
  virtual void start_segment(const Segment& segment, const core::State& state,
                             std::span<const double> integrals) = 0;

  /// Where one call of the solver towards an output time ended.
  struct Advance {
    double t = 0.0;     ///< time reached (tout, or a root before it)
    bool root = false;  ///< stopped at a zero of a switching function
  };
  /// One call in the solver's NORMAL mode towards tout (≤ the stop time). `next` is the time
  /// the driver will ask for after tout (the next output, the segment end, or +inf): a solver
  /// that computes outputs itself can tell whether tout is the only one inside its step.
  virtual Advance advance(double tout, double next) = 0;

  /// Restarts at the root t just returned by advance (same segment, same stop time).
  virtual void restart_at_root(double t, const Segment& segment) = 0;

  /// The solution reached the output at t, `state` (unpack's): a state of the integration, where
  /// the solver's joints tracker moves (core/constraint_tracker.hpp). None by default (IDA's
  /// root function moves its own after every step and at the outputs).
  virtual void accept_output(double t, const core::State& state) {
    (void)t;
    (void)state;
  }

  /// The state at time t of the solution last returned by advance (θ normalized).
  virtual void unpack(double t, core::State& state) const = 0;
  /// The integrals of that solution: W_d, then the model's extra integrals (none when the model
  /// does not dissipate).
  virtual void integrals(std::span<double> out) const = 0;

  /// Adds the counters of the current run (the solvers reset them at every re-initialization).
  virtual void add_counters(SolverStats& stats) const = 0;

  /// For a failure report: the solver's current time (or `fallback` when it has none) and its
  /// steps since the last (re)initialization.
  virtual double current_time(double fallback) const = 0;
  virtual long current_steps() const = 0;
  /// `what` with the solver's own last message and what its callbacks recorded
  /// (sundials::failure_message).
  virtual std::string failure_message(const std::string& what) const = 0;
};

/// Builds the solver once the plan is known to have a segment (a run with only t = 0 outputs
/// creates no SUNDIALS handle).
using SegmentSolverFactory = std::function<std::unique_ptr<SegmentSolver>()>;

/// Integrates the model over the output times with the solver `make_solver` builds: validates
/// the options and output times (std::invalid_argument), fills the trajectory (and the
/// dissipated work when the model dissipates), the located event times and the counters, and
/// turns a SundialsError into a core::SolverError naming `solver_name`, the time and step where
/// the solver stopped, and why.
ReferenceRun integrate_segments(const core::Model& model, const std::vector<double>& output_times,
                                const SolverOptions& options, const std::string& solver_name,
                                const SegmentSolverFactory& make_solver);

}  // namespace flexref::reference::sundials
