#pragma once
/// \file sundials_handle.hpp
/// The SUNDIALS boundary (docs/design/style.md, after SUNDIALS' own C++ `sundials::Context`):
///  - RAII owners with custom deleters for every handle SUNDIALS hands out (context, vectors,
///    matrices, linear solvers, IDA, CVODE and ARKODE ERKStep memory);
///  - one `check(flag, "Function")` that turns a negative return into a SundialsError naming
///    the function and the flag (IDAGetReturnFlagName / CVodeGetReturnFlagName /
///    ERKStepGetReturnFlagName / ARKStepGetReturnFlagName);
///  - an error handler that records SUNDIALS' own message ("At t = 0.3, mxstep steps taken
///    before reaching tout.") instead of printing it, so the driver can put it into the
///    core::SolverError it throws;
///  - the segment plan the SUNDIALS drivers integrate: [0, T] split at the model's known load
///    discontinuities (docs/design/schemes.md, "Reference integrators": stop and restart at every
///    switch), with the output times each segment owns. The loop over it is
///    sundials_segment_driver.hpp.
/// Boost.Odeint (odeint_solver.cpp) plans its segments on its own: it is the independent code
/// path.
#include <arkode/arkode_arkstep.h>
#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <exception>
#include <limits>
#include <memory>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "reference/error_weights.hpp"
#include "reference/integral_weights.hpp"
#include "reference/serial_vector_ops.hpp"
#include "reference/step_clock.hpp"

namespace flexref::reference::sundials {

// ---------------------------------------------------------------------------------------------
// Owners

struct ContextDeleter {
  void operator()(SUNContext context) const noexcept { SUNContext_Free(&context); }
};
struct VectorDeleter {
  void operator()(N_Vector v) const noexcept { N_VDestroy(v); }
};
struct MatrixDeleter {
  void operator()(SUNMatrix m) const noexcept { SUNMatDestroy(m); }
};
struct LinearSolverDeleter {
  void operator()(SUNLinearSolver s) const noexcept { SUNLinSolFree(s); }
};
struct NonlinearSolverDeleter {
  void operator()(SUNNonlinearSolver s) const noexcept { SUNNonlinSolFree(s); }
};
struct IdaMemoryDeleter {
  void operator()(void* memory) const noexcept { IDAFree(&memory); }
};
struct CvodeMemoryDeleter {
  void operator()(void* memory) const noexcept { CVodeFree(&memory); }
};
struct ErkStepMemoryDeleter {
  void operator()(void* memory) const noexcept { ERKStepFree(&memory); }
};

using Context = std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter>;
using Vector = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;
using Matrix = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixDeleter>;
using LinearSolver = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverDeleter>;
using NonlinearSolver =
    std::unique_ptr<std::remove_pointer_t<SUNNonlinearSolver>, NonlinearSolverDeleter>;
using IdaMemory = std::unique_ptr<void, IdaMemoryDeleter>;
using CvodeMemory = std::unique_ptr<void, CvodeMemoryDeleter>;
using ErkStepMemory = std::unique_ptr<void, ErkStepMemoryDeleter>;
struct ArkStepMemoryDeleter {
  void operator()(void* memory) const noexcept { ARKStepFree(&memory); }
};
using ArkStepMemory = std::unique_ptr<void, ArkStepMemoryDeleter>;

// ---------------------------------------------------------------------------------------------
// Errors

/// A SUNDIALS call that returned a negative flag.
class SundialsError : public std::runtime_error {
 public:
  SundialsError(std::string function, int flag, const std::string& flag_name)
      : std::runtime_error(function + " returned " + flag_name),
        function_(std::move(function)),
        flag_(flag) {}
  const std::string& function() const { return function_; }
  int flag() const { return flag_; }

 private:
  std::string function_;
  int flag_;
};

/// The symbolic name of a flag returned by `function`: IDA, CVODE and ARKODE reuse the same
/// numbers for different meanings, and their linear-solver interfaces have a third table.
inline std::string flag_name(int flag, std::string_view function) {
  const bool linear_solver_interface = function.find("LinearSolver") != std::string_view::npos ||
                                       function.find("JacFn") != std::string_view::npos;
  char* name = nullptr;  // malloc'ed by SUNDIALS, freed here
  if (function.starts_with("IDA")) {
    name = linear_solver_interface ? IDAGetLinReturnFlagName(flag) : IDAGetReturnFlagName(flag);
  } else if (function.starts_with("CVode")) {
    name = linear_solver_interface ? CVodeGetLinReturnFlagName(flag) : CVodeGetReturnFlagName(flag);
  } else if (function.starts_with("ERKStep")) {
    name = ERKStepGetReturnFlagName(flag);
  } else if (function.starts_with("ARKStep")) {
    name = linear_solver_interface ? ARKStepGetLinReturnFlagName(flag)
                                   : ARKStepGetReturnFlagName(flag);
  }
  std::string text = name != nullptr ? std::string(name) : "flag " + std::to_string(flag);
  std::free(name);  // NOLINT(cppcoreguidelines-no-malloc): SUNDIALS allocates with malloc
  return text;
}

/// Throws SundialsError when `flag` is negative (a SUNDIALS error; positive flags are
/// successful returns such as IDA_TSTOP_RETURN or warnings).
inline void check(int flag, const char* function) {
  if (flag < 0) throw SundialsError(function, flag, flag_name(flag, function));
}

/// Throws SundialsError when a constructor returned null.
template <class Handle>
Handle check_created(Handle handle, const char* function) {
  if (handle == nullptr) throw SundialsError(function, 0, "a null handle (out of memory?)");
  return handle;
}

/// The last error SUNDIALS reported through its error handler.
struct ErrorLog {
  std::string message;
};

/// What a solver's callbacks leave behind for the failure message: the solver's own last error,
/// an exception a callback caught (callbacks must not throw through C), and the last time a
/// callback produced a non-finite value.
struct CallbackRecord {
  ErrorLog log;
  std::exception_ptr callback_error;
  double last_nonfinite_time = std::numeric_limits<double>::quiet_NaN();
  /// The error weights (integral_error_weights): the tolerances, the integral components of y,
  /// and how to count the solver's steps since its last (re)initialization.
  double rtol = 0.0;
  double atol = 0.0;
  /// When not empty, each component's own atol instead (IDA's multipliers: ida_solver.cpp).
  std::vector<double> atol_vector;
  IntegralComponents integrals;
  void* solver_memory = nullptr;
  long (*steps_since_init)(void* solver_memory) = nullptr;
  /// CVODE and IDA (their error-weight functions: step_error_weights): the rotation's weights,
  /// and the clock the solver's accepted steps are summed on.
  const ErrorWeights* error_weights = nullptr;
  StepClock* clock = nullptr;
};

/// The solvers' error-weight function (CVEwtFn, ARKEwtFn, IDAEwtFn; user_data a CallbackRecord
/// of type Data): w_i = 1/(rtol |y_i| + atol), as SUNDIALS' scalar tolerances give, with the
/// integral components' weights scaled by the steps since the solver's last (re)initialization
/// (reference/integral_weights.hpp). Returns −1 (the solver stops) where a weight is not
/// positive and finite.
template <typename Data>
int integral_error_weights(N_Vector y, N_Vector ewt, void* user_data) {
  const auto& d = static_cast<const CallbackRecord&>(*static_cast<Data*>(user_data));
  const sunindextype n = N_VGetLength_Serial(y);
  const double* yv = N_VGetArrayPointer(y);
  double* w = N_VGetArrayPointer(ewt);
  for (sunindextype i = 0; i < n; ++i) {
    const double atol = d.atol_vector.empty() ? d.atol : d.atol_vector[static_cast<std::size_t>(i)];
    w[i] = 1.0 / (d.rtol * std::abs(yv[i]) + atol);
    if (!(w[i] > 0.0) || !std::isfinite(w[i])) return -1;
  }
  const long steps = d.steps_since_init != nullptr ? d.steps_since_init(d.solver_memory) : 0;
  scale_integral_weights(d.integrals, steps, d.rtol, d.atol, yv,
                         std::span<double>(w, static_cast<std::size_t>(n)));
  return 0;
}

/// `what`, then the solver's message, the callback's exception and the last non-finite
/// evaluation, if any. `callback` names the function ("right-hand side", "residual").
inline std::string failure_message(const std::string& what, const CallbackRecord& record,
                                   const char* callback) {
  std::ostringstream out;
  out.precision(17);
  out << what;
  if (!record.log.message.empty()) out << " (" << record.log.message << ")";
  if (record.callback_error) {
    try {
      std::rethrow_exception(record.callback_error);
    } catch (const std::exception& e) {
      out << "; the " << callback << " threw: " << e.what();
    } catch (...) {
      out << "; the " << callback << " threw an unknown exception";
    }
  }
  if (!std::isnan(record.last_nonfinite_time)) {
    out << "; last non-finite " << callback << " at t = " << record.last_nonfinite_time;
  }
  return out.str();
}

/// Error handler for IDASetErrHandlerFn / CVodeSetErrHandlerFn / ERKStepSetErrHandlerFn (same
/// signature): keeps the
/// message of the last error and drops warnings (such as "t + h = t"), which either resolve
/// themselves or end in an error whose message is kept.
inline void record_error(int error_code, const char* module, const char* function, char* message,
                         void* log) {
  if (error_code >= 0 || log == nullptr) return;
  static_cast<ErrorLog*>(log)->message = std::string(module) + "/" + function + ": " + message;
}

// ---------------------------------------------------------------------------------------------
// Constructors

inline Context make_context() {
  SUNContext context = nullptr;
  check(SUNContext_Create(nullptr, &context), "SUNContext_Create");
  return Context(context);
}

/// A serial vector of length n, zero-filled, with the compiled vector operations
/// (serial_vector_ops.hpp; the integrators' clones of it inherit them).
inline Vector make_vector(int n, SUNContext context) {
  Vector v(check_created(N_VNew_Serial(n, context), "N_VNew_Serial"));
  use_compiled_serial_ops(v.get());
  N_VConst(0.0, v.get());
  return v;
}

inline Matrix make_dense_matrix(int n, SUNContext context) {
  return Matrix(check_created(SUNDenseMatrix(n, n, context), "SUNDenseMatrix"));
}

inline LinearSolver make_dense_linear_solver(N_Vector y, SUNMatrix a, SUNContext context) {
  return LinearSolver(check_created(SUNLinSol_Dense(y, a, context), "SUNLinSol_Dense"));
}

/// Fixed-point (functional) iteration with Anderson acceleration over `depth` earlier iterates
/// (0: plain fixed-point iteration).
inline NonlinearSolver make_fixed_point_solver(N_Vector y, int depth, SUNContext context) {
  return NonlinearSolver(
      check_created(SUNNonlinSol_FixedPoint(y, depth, context), "SUNNonlinSol_FixedPoint"));
}

/// Newton iteration (CVODE's default corrector), for a solver that switches to it.
inline NonlinearSolver make_newton_solver(N_Vector y, SUNContext context) {
  return NonlinearSolver(check_created(SUNNonlinSol_Newton(y, context), "SUNNonlinSol_Newton"));
}

/// Raw data of a serial vector.
inline double* data(N_Vector v) { return N_VGetArrayPointer(v); }

/// The weights of the step CVODE or IDA takes next from y, in their error-weight function
/// after it recorded the step just taken on d.clock: the rotation's per-step share
/// (error_weights.hpp), then the integral components' share of their stretch
/// (integral_weights.hpp).
inline void step_error_weights(const CallbackRecord& d, N_Vector y, N_Vector ewt) {
  d.error_weights->evaluate(data(y), d.clock->mean_step(), data(ewt));
  if (d.integrals.count > 0) {
    scale_integral_weights(
        d.integrals, d.steps_since_init(d.solver_memory), d.rtol, d.atol, data(y),
        std::span<double>(data(ewt), static_cast<std::size_t>(N_VGetLength_Serial(ewt))));
  }
}

/// True when the n entries at p are finite.
inline bool all_finite(const double* p, long n) {
  return std::all_of(p, p + n, [](double x) { return std::isfinite(x); });
}

// ---------------------------------------------------------------------------------------------
// Segments

/// Times closer than this to a segment boundary are taken as that boundary: a few ulp of t.
/// It is above SUNDIALS' "tout too close to t0" threshold 2·u·max(|t0|, |tout|) (u = unit
/// round-off) and far below any meaningful time difference.
inline double boundary_slack(double t) {
  return 8.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t));
}

/// Throws std::invalid_argument unless the output times are finite, non-negative and strictly
/// increasing. Integration starts at t = 0, where the model's initial state is given (the
/// time profiles of its loads use absolute times).
inline void validate_output_times(const std::vector<double>& output_times) {
  if (output_times.empty()) throw std::invalid_argument("no output times");
  for (std::size_t k = 0; k < output_times.size(); ++k) {
    const double t = output_times[k];
    if (!std::isfinite(t) || t < 0.0) {
      throw std::invalid_argument("output times must be finite and non-negative");
    }
    if (k > 0 && !(t > output_times[k - 1])) {
      throw std::invalid_argument("output times must be strictly increasing");
    }
  }
}

/// Throws std::invalid_argument unless rtol and atol are positive and finite and max_steps is
/// positive (SUNDIALS would fail later with a less helpful flag).
inline void validate_tolerances(double rtol, double atol, long max_steps) {
  if (!(rtol > 0.0) || !std::isfinite(rtol) || !(atol > 0.0) || !std::isfinite(atol)) {
    throw std::invalid_argument("tolerances must be positive and finite");
  }
  if (max_steps <= 0) throw std::invalid_argument("max_steps must be positive");
}

/// One interval between consecutive known load discontinuities, integrated without restart.
struct Segment {
  double start = 0.0;
  double end = 0.0;
  /// A time strictly inside (start, end); selects the active branch of piecewise loads.
  double t_segment = 0.0;
  /// Outputs [first_output, end_output) lie in (start, end] (within boundary_slack).
  std::size_t first_output = 0;
  std::size_t end_output = 0;
};

/// The plan: outputs [0, initial_outputs) are at t = 0 (the initial state); the segments cover
/// [0, T], T the last output time, split at the discontinuities inside (0, T).
struct SegmentPlan {
  std::size_t initial_outputs = 0;
  std::vector<Segment> segments;
};

inline SegmentPlan plan_segments(const std::vector<double>& discontinuities,
                                 const std::vector<double>& output_times) {
  validate_output_times(output_times);
  SegmentPlan plan;
  std::size_t k = 0;
  while (k < output_times.size() && output_times[k] <= boundary_slack(0.0)) ++k;
  plan.initial_outputs = k;
  const double t_end = output_times.back();
  if (t_end <= boundary_slack(0.0)) return plan;

  std::vector<double> bounds{0.0};
  for (double d : discontinuities) {
    if (d > bounds.back() + boundary_slack(d) && d < t_end - boundary_slack(t_end)) {
      bounds.push_back(d);
    }
  }
  bounds.push_back(t_end);
  for (std::size_t i = 0; i + 1 < bounds.size(); ++i) {
    Segment s;
    s.start = bounds[i];
    s.end = bounds[i + 1];
    s.t_segment = 0.5 * (s.start + s.end);
    s.first_output = k;
    while (k < output_times.size() && output_times[k] <= s.end + boundary_slack(s.end)) ++k;
    s.end_output = k;
    plan.segments.push_back(s);
  }
  return plan;
}

}  // namespace flexref::reference::sundials
