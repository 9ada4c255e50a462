#include "studies/error_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "rotation/euler_parameters.hpp"

namespace flexref::studies {
namespace {

class Accumulator {
 public:
  void add(double t, double e) {
    // A non-finite error (a diverged run) makes every norm infinite, never silently small.
    if (!std::isfinite(e)) e = std::numeric_limits<double>::infinity();
    if (count_ == 0 || e > norms_.linf) {
      norms_.linf = e;
      linf_time_ = t;
    }
    sum_sq_ += e * e;
    norms_.final = e;
    ++count_;
  }
  ErrorNorms norms() const {
    ErrorNorms n = norms_;
    n.rms = count_ ? std::sqrt(sum_sq_ / static_cast<double>(count_)) : 0.0;
    return n;
  }
  double linf_time() const { return linf_time_; }

 private:
  ErrorNorms norms_;
  double linf_time_ = 0.0;
  double sum_sq_ = 0.0;
  long count_ = 0;
};

/// A measured quantity: its kind and the column indices (same in both tables).
struct Item {
  QuantityError quantity;
  std::vector<std::size_t> columns;
};

bool is_digits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// The quantities a table's columns measure, body by body in column order: position,
/// rotation, velocity, angular velocity (each only when its whole group of columns is
/// present), the tracked points, the modal coordinates.
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

}  // namespace

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

  ComparisonReport report;
  report.rows = run.size();
  for (Item& item : find_items(run)) {
    Accumulator acc;
    const std::string& kind = item.quantity.kind;
    for (std::size_t k = 0; k < run.size(); ++k) {
      const auto& a = run.rows[k];
      const auto& b = reference.rows[k];
      const auto& c = item.columns;
      if (kind == "modes") {
        // max_i |q_i − q_i,ref| at this time (NaN propagates through the sum to the norms)
        double worst = 0.0;
        for (std::size_t i : c) {
          const double d = std::abs(a[i] - b[i]);
          worst = std::isnan(d) ? d : std::max(worst, d);
          if (std::isnan(worst)) break;
        }
        acc.add(run.time(k), worst);
      } else if (kind == "rotation") {
        const rotation::EulerParameters qa(a[c[0]], a[c[1]], a[c[2]], a[c[3]]);
        const rotation::EulerParameters qb(b[c[0]], b[c[1]], b[c[2]], b[c[3]]);
        acc.add(run.time(k), rotation::geodesic_angle(qa, qb));
      } else {
        const Eigen::Vector3d d(a[c[0]] - b[c[0]], a[c[1]] - b[c[1]], a[c[2]] - b[c[2]]);
        acc.add(run.time(k), d.norm());
      }
    }
    item.quantity.norms = acc.norms();
    item.quantity.linf_time = acc.linf_time();
    const double linf = item.quantity.norms.linf;
    if (kind == "rotation") {
      report.max_rotation_linf = std::max(report.max_rotation_linf, linf);
      ++report.rotation_count;
    } else if (kind == "point") {
      report.max_point_linf = std::max(report.max_point_linf, linf);
      ++report.point_count;
    } else if (kind == "modes") {
      report.max_modal_linf = std::max(report.max_modal_linf, linf);
      ++report.modal_count;
    }
    report.quantities.push_back(std::move(item.quantity));
  }
  // Wear work of named contacts: the relative error of the final value (the cumulative work is
  // what a wear model consumes; its history is monotone).
  const std::vector<std::string>& cols = run.columns;
  for (std::size_t c = 1; c < cols.size() && run.size() > 0; ++c) {
    if (!cols[c].ends_with(".wear_work")) continue;
    const double a = run.rows.back()[c];
    const double b = reference.rows.back()[c];
    const double e = b != 0.0 ? std::abs(a - b) / std::abs(b) : std::abs(a);
    report.max_wear_relative = std::isnan(e) ? e : std::max(report.max_wear_relative, e);
    QuantityError wear{cols[c], "-", "wear", {}, run.time(run.size() - 1), {cols[c]}};
    wear.norms.linf = wear.norms.rms = wear.norms.final = e;
    report.quantities.push_back(std::move(wear));
  }
  return report;
}

std::vector<std::string> metric_names() {
  return {"rotation+points", "rotation", "points",           "modes",
          "position",        "velocity", "angular_velocity", "wear"};
}

std::vector<std::string> metric_quantities(const ComparisonReport& report,
                                           const std::string& metric) {
  const std::vector<std::string> names = metric_names();
  if (std::find(names.begin(), names.end(), metric) == names.end()) {
    throw std::invalid_argument("unknown metric '" + metric +
                                "' (rotation+points, rotation, points, modes, position, "
                                "velocity, angular_velocity, wear)");
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

}  // namespace flexref::studies
