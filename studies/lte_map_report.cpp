/// \file lte_map_report.cpp
/// What the lte-map reports (studies/lte_map_report.hpp): metric values, crossings, CSV, table.
#include "studies/lte_map_report.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <utility>

#include "studies/missing_value.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::studies {
namespace {

std::string percent(double x) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  s << std::setprecision(x < 0.1 ? 2 : 3) << 100.0 * x;
  return s.str();
}

}  // namespace

double lte_map_value(const LteMapPoint& p, bool classical, LteMapMetric metric) {
  switch (metric) {
    case LteMapMetric::kTip:
      return std::abs(classical ? p.classical_tip_error : p.tip_error);
    case LteMapMetric::kEnvelope:
      return std::abs(classical ? p.classical_envelope_error : p.envelope_error);
    case LteMapMetric::kFrequency:
      return std::abs(classical ? p.classical_frequency_shift : p.frequency_shift);
  }
  return kNaN;
}

std::vector<double> lte_map_crossings(const LteMapResult& result, double level, bool classical,
                                      LteMapMetric metric) {
  const std::size_t nx = result.options.spin_ratios.size();
  const std::size_t ny = result.options.inertia_ratios.size();
  std::vector<double> crossings(ny, kNaN);
  for (std::size_t j = 0; j < ny; ++j) {
    for (std::size_t i = 0; i + 1 < nx; ++i) {
      const LteMapPoint& pa = result.points[j * nx + i];
      const LteMapPoint& pb = result.points[j * nx + i + 1];
      const double a = lte_map_value(pa, classical, metric);
      const double b = lte_map_value(pb, classical, metric);
      if (!(a > 0.0) || !(b > 0.0)) continue;
      if ((a - level) * (b - level) > 0.0 || a == b) continue;
      const double f = std::log(level / a) / std::log(b / a);
      crossings[j] = pa.spin_ratio * std::pow(pb.spin_ratio / pa.spin_ratio, f);
      break;
    }
  }
  return crossings;
}

std::string lte_map_csv(const LteMapResult& result) {
  std::ostringstream s;
  s.precision(17);
  s << "spin_ratio,inertia_ratio,spin,omega1,hub_scale,load_scale,tip_error,envelope_error,"
       "frequency_shift,attitude_error,classical_tip_error,classical_envelope_error,"
       "classical_frequency_shift,max_deflection,truth_frequency,truth_estimate,lte_estimate,"
       "classical_estimate,resolved,classical_resolved,status\n";
  for (const LteMapPoint& p : result.points) {
    const std::string status = trajectory::csv_text(p.status);
    const auto n = [](double x) { return trajectory::csv_number(x); };
    s << n(p.spin_ratio) << ',' << n(p.inertia_ratio) << ',' << n(p.spin) << ',' << n(p.omega1)
      << ',' << n(p.hub_scale) << ',' << n(p.load_scale) << ',' << n(p.tip_error) << ','
      << n(p.envelope_error) << ',' << n(p.frequency_shift) << ',' << n(p.attitude_error) << ','
      << n(p.classical_tip_error) << ',' << n(p.classical_envelope_error) << ','
      << n(p.classical_frequency_shift) << ',' << n(p.max_deflection) << ',' << n(p.truth_frequency)
      << ',' << n(p.truth_estimate) << ',' << n(p.lte_estimate) << ',' << n(p.classical_estimate)
      << ',' << (p.resolved ? 1 : 0) << ',' << (p.classical_resolved ? 1 : 0) << ',' << status
      << '\n';
  }
  return s.str();
}

namespace {

void grid_table(std::ostringstream& s, const LteMapResult& result, bool classical) {
  const std::size_t nx = result.options.spin_ratios.size();
  const std::size_t ny = result.options.inertia_ratios.size();
  s << std::setw(10) << "y \\ x";
  for (std::size_t i = 0; i < nx; ++i) {
    std::ostringstream h;
    h << std::setprecision(3) << result.options.spin_ratios[i];
    s << std::setw(9) << h.str();
  }
  s << "\n";
  for (std::size_t j = 0; j < ny; ++j) {
    std::ostringstream h;
    h << std::setprecision(3) << result.options.inertia_ratios[j];
    s << std::setw(10) << h.str();
    for (std::size_t i = 0; i < nx; ++i) {
      const LteMapPoint& p = result.points[j * nx + i];
      const bool resolved = classical ? p.classical_resolved : p.resolved;
      s << std::setw(9)
        << (percent(classical ? p.classical_tip_error : p.tip_error) +
            (!p.status.starts_with("failed") && !resolved ? "*" : ""));
    }
    s << "\n";
  }
}

void crossing_lines(std::ostringstream& s, const LteMapResult& result, bool classical) {
  const std::size_t ny = result.options.inertia_ratios.size();
  const std::pair<LteMapMetric, const char*> metrics[] = {
      {LteMapMetric::kTip, "L-inf tip error"},
      {LteMapMetric::kEnvelope, "peak deflection"},
      {LteMapMetric::kFrequency, "frequency shift"}};
  for (const auto& [metric, name] : metrics) {
    for (const double level : {0.01, 0.05, 0.20}) {
      const std::vector<double> c = lte_map_crossings(result, level, classical, metric);
      s << "  " << name << ", " << percent(level) << " % line at Omega0/omega1 =";
      for (std::size_t j = 0; j < ny; ++j) {
        std::ostringstream v;
        v << std::setprecision(3);
        if (std::isfinite(c[j])) {
          v << c[j];
        } else {
          v << "-";
        }
        s << (j ? ", " : " ") << v.str() << " (y=" << std::setprecision(3)
          << result.options.inertia_ratios[j] << std::setprecision(4) << ")";
      }
      s << "\n";
    }
  }
}

}  // namespace

std::string format_lte_map_table(const LteMapResult& result) {
  const LteMapBase& b = result.base;
  const bool stiffened = result.options.stiffened_truth;
  std::ostringstream s;
  s << std::setprecision(4);
  s << "body '" << b.body << "', point '" << b.point << "': omega1 = " << b.omega1
    << " rad/s, scene Omega0/omega1 = " << b.spin_ratio
    << ", scene I_flex/I_rigid = " << b.inertia_ratio << "\n";
  const std::string truth =
      stiffened ? "the coupled model with geometric stiffening" : "the classical coupled model";
  s << "truth: " << truth << "; metrics over the horizon [0, " << result.options.end_time
    << "] s (frequency: its second half)\n";
  s << "LTE L-inf tip-deflection error relative to the truth, % (rows: I_flex/I_rigid, "
       "columns: Omega0/omega1; * = below 100x the reference error estimate)\n";
  grid_table(s, result, false);
  if (stiffened) {
    s << "classical coupled model (no stiffening): L-inf tip-deflection error relative to the "
         "truth, %\n";
    grid_table(s, result, true);
  }
  s << "where LTE holds:\n";
  crossing_lines(s, result, false);
  if (stiffened) {
    s << "where the classical coupled model holds:\n";
    crossing_lines(s, result, true);
  }
  for (const std::string& note : result.notes) s << "note: " << note << "\n";
  return s.str();
}

}  // namespace flexref::studies
