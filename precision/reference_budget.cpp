#include "precision/reference_budget.hpp"

#include <iomanip>
#include <sstream>

namespace flexref::precision {

double RateWindow::projected_run(double elapsed, double t, double t_end) {
  if (elapsed >= 2.0 * pending_.elapsed) {
    mark_ = pending_;
    pending_ = {elapsed, t};
  }
  // Several checks at one simulated time (event location): the average rate since t0.
  const Sample from = t > mark_.t ? mark_ : Sample{0.0, t0_};
  const double rate = (elapsed - from.elapsed) / (t - from.t);
  return elapsed + (t_end > t ? (t_end - t) * rate : 0.0);
}

void check_budget(const Budget& budget, RateWindow& window, double elapsed, double t, double t_end,
                  Precision precision) {
  const double t0 = window.t0();
  if (!(budget.seconds > 0.0) || !(t > t0) || !(t_end > t0)) return;
  if (elapsed < 0.01 * budget.seconds) return;
  const double projected = budget.spent + budget.factor * window.projected_run(elapsed, t, t_end);
  if (!(projected > budget.seconds)) return;
  std::ostringstream out;
  out << "a " << to_string(precision) << "-precision reference with its estimate is projected to "
      << "take " << std::defaultfloat << std::setprecision(3) << projected
      << " s of wall time (at t = " << t << " s after " << budget.spent + elapsed
      << " s), over its budget of " << std::setprecision(6) << budget.seconds << " s";
  throw BudgetExceeded(out.str(), projected, budget.seconds, t);
}

}  // namespace flexref::precision
