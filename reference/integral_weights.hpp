#pragma once
/// \file integral_weights.hpp
/// Error control of the integral components of a reference's y: the contacts' worn depths h and
/// the tracked works W_d, W_a, W_wear (reference/ode_form.hpp's layout), docs/wear.md "Fully
/// coupled reference" and docs/references.md "Integrals under the error test".
///
/// Why they need their own: a solver bounds each step's local error e_i by the tolerance
/// rtol |y_i| + atol of the component. The bodies' state forgets its past errors (the dynamics
/// damps or at worst carries them), but an integral y_i = ∫ r dt adds every step's error to its
/// value and never loses one: after N steps its error is up to N times the tolerance, and a
/// tolerance relative to the integral's whole value allows steps whose errors are far larger
/// than the step's own increment. On tube_support_impact at rtol 1e-10 (860 000 CVODE steps,
/// 3250 restarts at impacts) that left the wear work off by 2e-7 relative (2.3e-6 J), 2000 times
/// the tolerance, where the state was within a few tolerances.
///
/// Two measures bound the sum of the step errors by what the tolerance promises for each stretch
/// of integration between the solver's (re)starts (segment starts, contact events):
///
/// 1. The works are kept in y as increments since the last (re)start (IntegralBase; their value
///    is the base plus y's increment), so their relative tolerance is relative to what the
///    stretch added, and their round-off to its size.
/// 2. Their weights, and the depths', are multiplied by the steps n taken since that (re)start,
///        w_i = n / (rtol |y_i| + atol),
///    so that step k's error is at most (rtol |y_i(t_k)| + atol)/k: over a stretch of n steps
///    the errors of an increment that grows steadily add up to rtol |Δy_i| + atol ln n, the
///    error-per-unit-step criterion (each step's error bounded by the tolerance times its share
///    of the stretch), needing no estimate of the rate or of the next step. The tolerance stops
///    at 100 round-offs of the value, which cannot be undercut (SUNDIALS reports "too much
///    accuracy").
///
/// Across the M stretches of a run the errors still add: the bound is M (rtol |ΔW| + atol ln n)
/// for each work. Measured on tube_support_impact (CVODE, rtol 1e-10, 3250 restarts): the wear
/// work's error fell from 2.1e-7 to 1.4e-8 relative and the state's from 6e-10 to 1e-10 m, for
/// 24 % more CPU (docs/references.md). Counting the steps since t = 0 instead (the bound
/// rtol |W| ln M + atol ln N over the run) reached 1e-10 relative, but took 5.4 times the CPU:
/// the absolute floor atol/N then forces every restart's first steps down.
#include <span>
#include <vector>

namespace flexref::reference {

/// Components of y: `count` of them from `first`.
struct IntegralComponents {
  int first = 0;
  int count = 0;
};

/// Sets the weights of the integral components of y to 1/max((rtol |y_i| + atol)/n,
/// 100 ε |y_i|) with n = max(1, steps), the steps since the solver's last (re)start; the other
/// components of `weights` are left as they are.
void scale_integral_weights(const IntegralComponents& integrals, long steps, double rtol,
                            double atol, const double* y, std::span<double> weights);

/// The works in y as increments since the solver's last (re)start (see the file comment).
class IntegralBase {
 public:
  /// The works are `works.count` components of y from `works.first`.
  explicit IntegralBase(IntegralComponents works);

  /// At a segment start: the base ← `values` (the works so far), y's works ← 0.
  void start(std::span<const double> values, double* y);
  /// At a restart within the segment: the base ← base + y's works, y's works ← 0.
  void rebase(double* y);
  /// The works' values base + y's into `out` (works.count values).
  void values(const double* y, std::span<double> out) const;

 private:
  IntegralComponents works_;
  std::vector<double> base_;
};

}  // namespace flexref::reference
