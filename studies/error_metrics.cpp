#include "studies/error_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "rotation/euler_parameters.hpp"
#include "studies/error_metrics_tpl.hpp"

namespace flexref::studies {
namespace {

bool is_digits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

namespace detail {

std::vector<Item> find_items(const TrajectoryTable& table) {
  const auto& cols = table.columns;
  auto index = [&](const std::string& name) { return table.column(name); };
  std::vector<std::string> bodies;
  for (const std::string& c : cols) {
    const auto dot = c.find('.');
    if (dot == std::string::npos || dot == 0) continue;
    const std::string body = c.substr(0, dot);
    if (std::find(bodies.begin(), bodies.end(), body) == bodies.end()) bodies.push_back(body);
  }
  std::vector<Item> items;
  for (const std::string& b : bodies) {
    auto group = [&](const char* kind, const char* unit, std::initializer_list<const char*> sfx) {
      Item item;
      for (const char* s : sfx) {
        const int i = index(b + s);
        if (i < 0) return;
        item.columns.push_back(static_cast<std::size_t>(i));
        item.quantity.columns.push_back(b + s);
      }
      item.quantity.name = b + "." + kind;
      item.quantity.unit = unit;
      item.quantity.kind = kind;
      items.push_back(std::move(item));
    };
    group("position", "m", {".x", ".y", ".z"});
    group("rotation", "rad", {".e0", ".e1", ".e2", ".e3"});
    group("velocity", "m/s", {".vx", ".vy", ".vz"});
    group("angular_velocity", "rad/s", {".W1", ".W2", ".W3"});
    // An ideal joint's reaction on its first body (docs/output.md, "Joints") and the run's own
    // position-constraint violation.
    group("reaction_force", "N", {".fx", ".fy", ".fz"});
    group("reaction_torque", "N*m", {".tx", ".ty", ".tz"});
    group("violation", "m|rad", {".phi"});
    // Points: "<B>.<P>.x" with ".y" and ".z" (names have no dots: scenes/README.md).
    for (const std::string& c : cols) {
      if (c.size() <= b.size() + 3 || !c.starts_with(b + ".") || !c.ends_with(".x")) continue;
      const std::string point = c.substr(b.size() + 1, c.size() - b.size() - 3);
      if (point.empty() || point.find('.') != std::string::npos) continue;
      const std::string stem = b + "." + point;
      const int ix = index(stem + ".x"), iy = index(stem + ".y"), iz = index(stem + ".z");
      if (iy < 0 || iz < 0) continue;
      Item item;
      item.quantity = {stem, "m", "point", {}, 0.0, {stem + ".x", stem + ".y", stem + ".z"}};
      item.columns = {static_cast<std::size_t>(ix), static_cast<std::size_t>(iy),
                      static_cast<std::size_t>(iz)};
      items.push_back(std::move(item));
    }
    // Modal coordinates "<B>.q<k>" (not the rates "<B>.qd<k>").
    Item modes;
    for (std::size_t i = 0; i < cols.size(); ++i) {
      if (cols[i].starts_with(b + ".q") && is_digits(cols[i].substr(b.size() + 2))) {
        modes.columns.push_back(i);
        modes.quantity.columns.push_back(cols[i]);
      }
    }
    if (!modes.columns.empty()) {
      modes.quantity.name = b + ".modes";
      modes.quantity.unit = "-";
      modes.quantity.kind = "modes";
      items.push_back(std::move(modes));
    }
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
  return {"rotation+points", "rotation",        "points",           "modes",
          "position",        "velocity",        "angular_velocity", "wear",
          "reaction_force",  "reaction_torque", "violation"};
}

std::vector<std::string> metric_quantities(const ComparisonReport& report,
                                           const std::string& metric) {
  const std::vector<std::string> names = metric_names();
  if (std::find(names.begin(), names.end(), metric) == names.end()) {
    throw std::invalid_argument("unknown metric '" + metric +
                                "' (rotation+points, rotation, points, modes, position, "
                                "velocity, angular_velocity, wear, reaction_force, "
                                "reaction_torque, violation)");
  }
  std::vector<std::string> used;
  for (const QuantityError& q : report.quantities) {
    const bool take = metric == "rotation+points" ? (q.kind == "rotation" || q.kind == "point")
                      : metric == "points"        ? q.kind == "point"
                                                  : q.kind == metric;
    if (take) used.push_back(q.name);
  }
  if (used.empty()) {
    const char* needs = metric == "rotation+points" ? "Euler-parameter or tracked-point columns"
                        : metric == "rotation"      ? "Euler-parameter columns B.e0..B.e3"
                        : metric == "points"        ? "tracked-point columns B.P.x..B.P.z"
                        : metric == "modes"         ? "modal-coordinate columns B.q1.."
                        : metric == "position"      ? "position columns B.x..B.z"
                        : metric == "velocity"      ? "velocity columns B.vx..B.vz"
                        : metric == "wear" ? "wear-work columns C.wear_work of a named contact"
                        : metric == "reaction_force"  ? "joint reaction columns J.fx..J.fz"
                        : metric == "reaction_torque" ? "joint reaction columns J.tx..J.tz"
                        : metric == "violation"       ? "constraint-violation columns J.phi"
                                                      : "angular-velocity columns B.W1..B.W3";
    throw std::invalid_argument("metric '" + metric + "' has nothing to measure: no " + needs +
                                " were compared");
  }
  return used;
}

double metric_value(const ComparisonReport& report, const std::string& metric) {
  (void)metric_quantities(report, metric);  // validates the name and that something is measured
  if (metric == "rotation+points") return report.default_metric();
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

}  // namespace flexref::studies
