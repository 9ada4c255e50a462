#pragma once
/// \file method_choice.hpp
/// CVODE's method for a model (docs/references.md, "CVODE: Adams or BDF"). Adams–Moulton of
/// orders up to 12 needs fewer steps than BDF (orders ≤ 5) wherever accuracy, not stability,
/// sets the step — measured on every bundled scene without contact, flexible ones and a
/// double pendulum on stiff, lightly damped joints (2.6e3 rad/s) included. Its stability
/// region is bounded on the negative real axis, so BDF (with the projection of θ) is chosen
/// where a mode decays much faster than anything the solution must resolve:
///  - a contact (switching functions): penalty contacts are stiff, dissipative and non-smooth
///    at their force clamp, and engage only later in the run where the initial state shows
///    nothing (measured: BDF 1e4× more accurate per rtol on pendulum_on_sliding_support,
///    cheaper on sliding_block and top_on_plane);
///  - a heavily damped fast mode in the spectrum of the ODE Jacobian J at the initial state
///    (difference quotients, the loads of the first segment): the fastest decay rate
///    σ = max(−Re λ) exceeds kStiffnessRatio times every rate the solution must resolve — the
///    magnitudes |λ| of the modes damped less than critically ratio 1/√2 (|Re λ| ≤ |Im λ|) and
///    the bodies' angular speeds.
#include <string>

#include "core/model.hpp"
#include "reference/reference_solver.hpp"

namespace flexref::reference {

/// σ beyond this multiple of the resolved rates makes the model stiff.
inline constexpr double kStiffnessRatio = 10.0;

/// The spectrum summary the choice is made from (rates in 1/s).
struct StiffnessSummary {
  int switching_functions = 0;
  double fastest_rate = 0.0;   ///< max |λ| of J
  double fastest_decay = 0.0;  ///< σ = max(−Re λ), 0 when no mode decays
  double resolved_rate = 0.0;  ///< max |λ| over modes with |Re λ| ≤ |Im λ|, and max |ω̄(0)|
  bool stiff() const;
};

StiffnessSummary summarize_stiffness(const core::Model& model);

struct CvodeMethodChoice {
  CvodeMethod method = CvodeMethod::kAdams;
  std::string reason;  ///< for the metadata: the element or the rates behind the choice
};

CvodeMethodChoice choose_cvode_method(const core::Model& model);

}  // namespace flexref::reference
