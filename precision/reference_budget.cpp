#include "precision/reference_budget.hpp"

#include <iomanip>
#include <sstream>

namespace flexref::precision {

void check_budget(const Budget& budget, double elapsed, double t0, double t, double t_end,
                  Precision precision) {
  if (!(budget.seconds > 0.0) || !(t > t0) || !(t_end > t0)) return;
  if (elapsed < 0.01 * budget.seconds) return;
  const double projected = budget.spent + budget.factor * elapsed * (t_end - t0) / (t - t0);
  if (!(projected > budget.seconds)) return;
  std::ostringstream out;
  out << "a " << to_string(precision) << "-precision reference with its estimate is projected to "
      << "take " << std::defaultfloat << std::setprecision(3) << projected
      << " s of wall time (at t = " << t << " s after " << budget.spent + elapsed
      << " s), over its budget of " << std::setprecision(6) << budget.seconds << " s";
  throw BudgetExceeded(out.str(), projected, budget.seconds, t);
}

}  // namespace flexref::precision
