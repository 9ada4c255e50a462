#include "trajectory/accuracy_check.hpp"

#include <sstream>
#include <stdexcept>

namespace flexref::trajectory {

void check_accuracy_check_rtol(const std::string& study, double rtol, double estimate_factor) {
  const double check = accuracy_check_rtol(rtol, estimate_factor);
  // The same relative slack as the solvers' tolerance floor: 1e-14 / 10 / 10 is 1e-16 exactly
  // only to rounding.
  if (check >= kTightestRtol * (1.0 - 1e-12)) return;
  std::ostringstream out;
  out.precision(3);
  out << study << ": the accuracy check reruns at rtol / estimate factor = " << rtol << " / "
      << estimate_factor << " = " << check << ", below " << kTightestRtol
      << ", where double precision round-off dominates (the check would be no more accurate "
         "than the run): raise --rtol or lower --estimate-factor";
  throw std::invalid_argument(out.str());
}

}  // namespace flexref::trajectory
