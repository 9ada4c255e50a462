#pragma once
/// \file certified_reference.hpp
/// A reference run with its error estimate (docs/design/schemes.md): the difference, in a named
/// metric, to a second run at 100× tighter tolerance and to a second, independent solver at
/// the same tolerance. The estimate is the larger of the two.
///
/// An exact solution has no tolerance: it is compared with two independent numerical solutions
/// at tight tolerance (Odeint RKF7(8) at rtol 1e-13 and CVODE at 1e-12), and its estimate is the
/// smaller difference — a bound on the exact solution's own error (elliptic functions, ~1e-13)
/// plus that of the better numerical solution.
#include <string>
#include <vector>

#include "core/model.hpp"
#include "reference/reference_solver.hpp"
#include "studies/study_record.hpp"
#include "studies/trajectory_table.hpp"

namespace flexref::studies {

struct ReferenceEstimate {
  std::string metric;
  std::string tighter_solver;  ///< "" when not run
  double tighter_rtol = 0.0;
  double vs_tighter = 0.0;  ///< metric(run, tighter run)
  std::string other_solver;
  double other_rtol = 0.0;
  double vs_other_solver = 0.0;  ///< metric(run, other solver)
  bool exact = false;            ///< the run is an exact solution (see above)
  double estimate() const {
    if (exact) return vs_tighter < vs_other_solver ? vs_tighter : vs_other_solver;
    return vs_tighter > vs_other_solver ? vs_tighter : vs_other_solver;
  }
};

struct CertifiedReference {
  reference::ReferenceRun run;
  TrajectoryTable table;
  ReferenceEstimate estimate;
};

/// The solver used to cross-check `solver`: cvode → odeint; ida, odeint, exact → cvode.
std::string cross_check_solver(const std::string& solver);

/// "auto" picks "exact" when the model has an exact solution, else "cvode".
std::string resolve_reference_solver(const std::string& solver, const core::Model& model);

/// The `[reference]` section a study records next to its results: solver, tolerance and the
/// error estimate with both of its checks.
void add_reference(StudyRecord& record, const CertifiedReference& reference);

/// The size of a solution in `metric`, the yardstick of its error estimate: the metric of the
/// table's first row (held over every time) against a body at rest at the world origin with the
/// identity rotation, with the rotation part taken as π (the largest geodesic angle). For
/// "rotation+points": π + the largest distance of a tracked point from the origin at t0.
double solution_scale(const TrajectoryTable& table, const std::string& metric);

/// Runs the reference and its two checks; throws like the solvers do (core::SolverError, also
/// when an estimate is not finite), and StudyRefused when the estimate exceeds
/// solution_scale(table, metric): an error larger than the scene itself certifies nothing
/// (e.g. a solution that diverges exponentially, spin_up_beam_6 under the coupled model,
/// where the solvers disagree by 1e34 m on a 10 m beam).
CertifiedReference certified_reference(const core::Model& model,
                                       const std::vector<double>& output_times,
                                       const std::string& solver,
                                       const reference::SolverOptions& options,
                                       const std::string& metric);

}  // namespace flexref::studies
