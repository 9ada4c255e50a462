#include "trajectory/error_metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <stdexcept>

#include "rotation/euler_parameters.hpp"
#include "trajectory/column_layout.hpp"
#include "trajectory/error_metrics_tpl.hpp"

namespace flexref::trajectory {
namespace detail {

std::vector<Item> find_items(const TrajectoryTable& table) {
  const ColumnLayout layout = ColumnLayout::parse(table.columns);
  // Every name before a first dot, in the order of its first column (unknown columns too: the
  // order of the quantities follows the table's).
  std::vector<std::string> owners;
  for (const Column& c : layout.columns()) {
    if (c.owner.empty()) continue;
    if (std::find(owners.begin(), owners.end(), c.owner) == owners.end()) owners.push_back(c.owner);
  }
  std::vector<Item> items;
  auto add = [&](Item item, const std::string& name, const char* kind, const char* unit) {
    item.quantity.name = name;
    item.quantity.unit = unit;
    item.quantity.kind = kind;
    for (std::size_t i : item.columns) item.quantity.columns.push_back(table.columns[i]);
    items.push_back(std::move(item));
  };
  for (const std::string& b : owners) {
    auto group = [&](ColumnKind kind, const char* name, const char* unit) {
      std::array<int, 4> found{};
      const std::span<int> indices(found.data(), static_cast<std::size_t>(group_size(kind)));
      if (!layout.find_group(kind, b, indices)) return;
      Item item;
      for (int i : indices) item.columns.push_back(static_cast<std::size_t>(i));
      add(std::move(item), b + "." + name, name, unit);
    };
    group(ColumnKind::position, "position", "m");
    group(ColumnKind::rotation, "rotation", "rad");
    group(ColumnKind::velocity, "velocity", "m/s");
    group(ColumnKind::angular_velocity, "angular_velocity", "rad/s");
    // An ideal joint's reaction on its first body (docs/output.md, "Joints") and the run's own
    // position-constraint violation.
    group(ColumnKind::reaction_force, "reaction_force", "N");
    group(ColumnKind::reaction_torque, "reaction_torque", "N*m");
    group(ColumnKind::violation, "violation", "m|rad");
    // Points, in the order of their x columns.
    for (const Column& c : layout.columns()) {
      if (c.kind != ColumnKind::point || c.component != 0 || c.owner != b) continue;
      std::array<int, 3> p{};
      if (!layout.find_group(ColumnKind::point, b, p, c.point)) continue;
      Item item;
      item.columns = {static_cast<std::size_t>(p[0]), static_cast<std::size_t>(p[1]),
                      static_cast<std::size_t>(p[2])};
      add(std::move(item), b + "." + c.point, "point", "m");
    }
    // Modal coordinates q<k> (not the rates qd<k>).
    Item modes;
    modes.columns = layout.mode_columns(ColumnKind::mode, b);
    if (!modes.columns.empty()) add(std::move(modes), b + ".modes", "modes", "-");
  }
  return items;
}

}  // namespace detail

ComparisonReport compare_trajectories(const TrajectoryTable& run,
                                      const TrajectoryTable& reference) {
  if (run.columns != reference.columns) {
    for (std::size_t i = 0; i < std::max(run.columns.size(), reference.columns.size()); ++i) {
      const std::string a = i < run.columns.size() ? run.columns[i] : "(none)";
      const std::string b = i < reference.columns.size() ? reference.columns[i] : "(none)";
      if (a != b) {
        throw std::invalid_argument("column " + std::to_string(i + 1) + " differs: '" + a +
                                    "' vs '" + b + "'");
      }
    }
  }
  if (run.size() != reference.size()) {
    throw std::invalid_argument("different numbers of output times: " + std::to_string(run.size()) +
                                " vs " + std::to_string(reference.size()));
  }
  for (std::size_t k = 0; k < run.size(); ++k) {
    const double a = run.time(k);
    const double b = reference.time(k);
    if (std::abs(a - b) > 1e-9 * std::max(1.0, std::abs(b))) {
      char text[128];
      std::snprintf(text, sizeof text, "output times differ at row %zu: %.17g vs %.17g", k + 1, a,
                    b);
      throw std::invalid_argument(text);
    }
  }

  return detail::compare_cells<double>(run, [&](int table, std::size_t k, std::size_t i) {
    return table == 0 ? run.rows[k][i] : reference.rows[k][i];
  });
}

std::vector<std::string> metric_names() {
  return {kDefaultMetric, "rotation+points", "rotation",        "points",
          "modes",        "position",        "velocity",        "angular_velocity",
          "wear",         "reaction_force",  "reaction_torque", "violation"};
}

std::vector<std::string> metric_quantities(const ComparisonReport& report,
                                           const std::string& metric) {
  const std::vector<std::string> names = metric_names();
  if (std::find(names.begin(), names.end(), metric) == names.end()) {
    throw std::invalid_argument("unknown metric '" + metric +
                                "' (relative, rotation+points, rotation, points, modes, position, "
                                "velocity, angular_velocity, wear, reaction_force, "
                                "reaction_torque, violation)");
  }
  std::vector<std::string> used;
  for (const QuantityError& q : report.quantities) {
    const bool take = metric == kDefaultMetric || metric == "rotation+points"
                          ? (q.kind == "rotation" || q.kind == "point")
                      : metric == "points" ? q.kind == "point"
                                           : q.kind == metric;
    if (take) used.push_back(q.name);
  }
  if (used.empty()) {
    const char* needs = metric == kDefaultMetric || metric == "rotation+points"
                            ? "Euler-parameter or tracked-point columns"
                        : metric == "rotation" ? "Euler-parameter columns B.e0..B.e3"
                        : metric == "points"   ? "tracked-point columns B.P.x..B.P.z"
                        : metric == "modes"    ? "modal-coordinate columns B.q1.."
                        : metric == "position" ? "position columns B.x..B.z"
                        : metric == "velocity" ? "velocity columns B.vx..B.vz"
                        : metric == "wear"     ? "wear-work columns C.wear_work of a named contact"
                        : metric == "reaction_force"  ? "joint reaction columns J.fx..J.fz"
                        : metric == "reaction_torque" ? "joint reaction columns J.tx..J.tz"
                        : metric == "violation"       ? "constraint-violation columns J.phi"
                                                      : "angular-velocity columns B.W1..B.W3";
    throw std::invalid_argument("metric '" + metric + "' has nothing to measure: no " + needs +
                                " were compared");
  }
  return used;
}

namespace {

/// The default metric: the largest L∞ / bound over the rotations and tracked points.
double relative_metric(const ComparisonReport& report) {
  double worst = 0.0;
  for (const QuantityError& q : report.quantities) {
    if (q.kind != "rotation" && q.kind != "point") continue;
    if (!std::isfinite(q.bound)) {
      throw std::invalid_argument(
          "metric '" + std::string(kDefaultMetric) + "' cannot scale " + q.name +
          ": the reference holds it still (its extent 0, or below kHeldFraction = 1e-6 of the "
          "largest point's), so its error is a fraction of no range; "
          "name the metric 'points' (m) or 'rotation' (rad)");
    }
    // A non-finite error (a diverged run) stays infinite, never a fraction.
    worst = std::max(worst, std::isfinite(q.norms.linf) ? q.norms.linf / q.bound
                                                        : std::numeric_limits<double>::infinity());
  }
  return worst;
}

}  // namespace

double metric_value(const ComparisonReport& report, const std::string& metric) {
  (void)metric_quantities(report, metric);  // validates the name and that something is measured
  if (metric == kDefaultMetric) return relative_metric(report);
  if (metric == "rotation+points") return report.max_rotation_linf + report.max_point_linf;
  if (metric == "rotation") return report.max_rotation_linf;
  if (metric == "points") return report.max_point_linf;
  if (metric == "modes") return report.max_modal_linf;
  if (metric == "wear") return report.max_wear_relative;
  double value = 0.0;
  for (const QuantityError& q : report.quantities) {
    if (q.kind == metric) value = std::max(value, q.norms.linf);
  }
  return value;
}

double metric_saturation(const ComparisonReport& report, const std::string& metric) {
  const std::vector<std::string> used = metric_quantities(report, metric);
  double worst = 0.0;
  for (const QuantityError& q : report.quantities) {
    if (std::find(used.begin(), used.end(), q.name) == used.end()) continue;
    if (!std::isfinite(q.bound)) continue;
    // A non-finite error (a diverged run) is as saturated as it gets.
    worst = std::max(worst, std::isfinite(q.norms.linf) ? q.norms.linf / q.bound
                                                        : std::numeric_limits<double>::infinity());
  }
  return worst;
}

std::string metric_bounds_text(const ComparisonReport& report, const std::string& metric) {
  const std::vector<std::string> used = metric_quantities(report, metric);
  std::string out;
  for (const QuantityError& q : report.quantities) {
    if (std::find(used.begin(), used.end(), q.name) == used.end()) continue;
    if (!std::isfinite(q.bound)) continue;
    char value[48];
    std::snprintf(value, sizeof value, "%.3g %s", q.bound, q.unit.c_str());
    out += (out.empty() ? "" : ", ") + q.name + " " +
           (q.kind == "rotation" ? std::string("pi rad") : std::string(value));
  }
  return out;
}

std::string metric_unit(const std::string& metric) {
  if (metric == kDefaultMetric || metric == "wear") return "1";
  if (metric == "rotation+points") return "rad + m";
  if (metric == "rotation") return "rad";
  if (metric == "points" || metric == "position") return "m";
  if (metric == "velocity") return "m/s";
  if (metric == "angular_velocity") return "rad/s";
  if (metric == "modes") return "-";
  if (metric == "reaction_force") return "N";
  if (metric == "reaction_torque") return "N*m";
  if (metric == "violation") return "m|rad";
  throw std::invalid_argument("unknown metric '" + metric + "'");
}

std::string metric_terms(const ComparisonReport& report, const std::string& metric) {
  const std::vector<std::string> used = metric_quantities(report, metric);
  if (metric != kDefaultMetric) {
    std::string names;
    for (const std::string& name : used) names += (names.empty() ? "" : ", ") + name;
    return names;
  }
  (void)relative_metric(report);  // every range is known
  std::string ranges;
  for (const QuantityError& q : report.quantities) {
    if (std::find(used.begin(), used.end(), q.name) == used.end()) continue;
    char value[48];
    std::snprintf(value, sizeof value, "%.3g %s", q.bound, q.unit.c_str());
    ranges += (ranges.empty() ? "" : ", ") + q.name + " / " +
              (q.kind == "rotation" ? std::string("pi rad") : std::string(value));
  }
  return "largest of " + ranges;
}

std::string describe_metric(const TrajectoryTable& reference, const std::string& metric) {
  const std::string named = metric + " [" + metric_unit(metric) + "]";
  // A reference that has nothing the metric measures (or no rows yet) still names the unit.
  try {
    return named + ": " + metric_terms(compare_trajectories(reference, reference), metric);
  } catch (const std::invalid_argument&) {
    return named;
  }
}

}  // namespace flexref::trajectory
