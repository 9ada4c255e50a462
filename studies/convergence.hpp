#pragma once
/// \file convergence.hpp
/// The `converge` study (docs/design/studies.md): each scheme at steps h0, h0/2, …, its error
/// against a certified reference in a named metric, pairwise and least-squares observed
/// orders. Levels whose error is not at least 100× the reference's estimated error are
/// "uncertified" and left out of the fit; levels at round-off stop the refinement; both are
/// said in the table.
#include <functional>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "lie/stepper.hpp"
#include "studies/certified_reference.hpp"
#include "studies/trajectory_contract.hpp"

namespace flexref::studies {

/// One level of an integrator outside the method registry: its trajectory under the contract
/// (docs/external.md) and the CPU time it took (NaN when unknown, e.g. a run made earlier).
struct ExternalLevel {
  RunData run;
  double cpu_seconds = 0.0;
};

/// An integrator outside the method registry (another program, runs already made): studied
/// like a registered scheme, its errors measured under the trajectory contract.
struct ExternalMethod {
  std::string label;      ///< its name in tables (letters, digits, '_', '-')
  int claimed_order = 0;  ///< 0: no claim
  /// The steps of its levels; empty: the study's h0, h0/2, … (`levels` of them).
  std::vector<double> steps;
  /// Produces the level with step h (level 0 is the coarsest); throws to fail that level only.
  std::function<ExternalLevel(double h, int level)> run;
  /// Where the run of level `level` keeps its output file (empty: nothing kept, as for runs
  /// made earlier). A level run on another MPI rank sends the file's bytes to rank 0, which
  /// writes them here, so the study folder is the same for any number of ranks (docs/mpi.md).
  std::function<std::string(int level)> kept_file;
};

/// On a rank other than 0: the bytes of `method`'s kept file of `level`, to send to rank 0;
/// empty on rank 0 or when the method keeps nothing.
std::string kept_file_bytes(const ExternalMethod& method, int level);
/// On rank 0: writes `bytes` received from another rank to method.kept_file(level) (nothing
/// when `bytes` is empty). Throws io::OutputError when the file cannot be written.
void restore_kept_file(const ExternalMethod& method, int level, const std::string& bytes);

struct ConvergenceOptions {
  std::vector<std::string> schemes = lie::scheme_names();
  double h0 = 1e-2;
  int levels = 6;
  std::string metric = "rotation+points";
  std::string reference_solver = "auto";
  double reference_rtol = 1e-12;
  int jobs = 1;
  bool progress = false;                 ///< progress line on stderr
  std::vector<ExternalMethod> external;  ///< studied after the schemes
};

struct ConvergenceLevel {
  std::string scheme;
  double h = 0.0;
  long steps = 0;
  double error = 0.0;
  double order = 0.0;  ///< pairwise order against the previous level (NaN for the first)
  double cpu_seconds = 0.0;
  std::string status;  ///< "ok", "uncertified", "round-off", or "failed: why"
};

struct SchemeSummary {
  std::string scheme;
  int claimed_order = 0;
  double fitted_order = 0.0;  ///< least squares over the "ok" levels (NaN if < 2)
  int fitted_levels = 0;
};

struct ConvergenceResult {
  ConvergenceOptions options;
  CertifiedReference reference;
  std::vector<ConvergenceLevel> levels;
  std::vector<SchemeSummary> summaries;
  std::vector<std::string> notes;
};

ConvergenceResult run_convergence(const core::Model& model, const std::vector<double>& output_times,
                                  const ConvergenceOptions& options);

/// The analysis of one method's levels (coarsest first, error and status "ok" or "failed: …"
/// set): a level whose error is at round-off stops the refinement, a level not
/// kCertificationFactor× above the reference's estimated error is "uncertified"; pairwise orders
/// are filled in and the least-squares order fitted over the "ok" levels. Notes (round-off,
/// orders still changing) are appended to `notes`.
SchemeSummary summarize_levels(const std::string& method, int claimed_order,
                               std::vector<ConvergenceLevel>& levels, double reference_estimate,
                               std::vector<std::string>& notes);

/// The terminal table (errors, pairwise orders, fitted orders, notes).
std::string format_convergence_table(const ConvergenceResult& result);
/// CSV: scheme,h,steps,error,order,cpu_seconds,status.
std::string convergence_csv(const ConvergenceResult& result);

}  // namespace flexref::studies
