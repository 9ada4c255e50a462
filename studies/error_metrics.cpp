#include "studies/error_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "rotation/euler_parameters.hpp"

namespace flexref::studies {
namespace {

class Accumulator {
 public:
  void add(double e) {
    // A non-finite error (a diverged run) makes every norm infinite, never silently small.
    if (!std::isfinite(e)) e = std::numeric_limits<double>::infinity();
    norms_.linf = std::max(norms_.linf, e);
    sum_sq_ += e * e;
    norms_.final = e;
    ++count_;
  }
  ErrorNorms norms() const {
    ErrorNorms n = norms_;
    n.rms = count_ ? std::sqrt(sum_sq_ / static_cast<double>(count_)) : 0.0;
    return n;
  }

 private:
  ErrorNorms norms_;
  double sum_sq_ = 0.0;
  long count_ = 0;
};

Eigen::Vector3d vec3(const std::vector<double>& row, int c) {
  const auto i = static_cast<std::size_t>(c);
  return Eigen::Vector3d(row[i], row[i + 1], row[i + 2]);
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
      throw std::invalid_argument("output times differ at row " + std::to_string(k + 2) + ": " +
                                  std::to_string(a) + " vs " + std::to_string(b));
    }
  }

  // Quantities by column pattern: a body block starts at "<B>.x" followed by "<B>.e0".
  struct Item {
    std::string name, unit;
    int column;
    enum Kind { kVector, kRotation, kPoint, kModes } kind;
    std::vector<std::size_t> modal_columns = {};  ///< kModes: the B.q1 … B.qn columns
  };
  std::vector<Item> items;
  const auto& cols = run.columns;
  for (std::size_t i = 1; i + 12 < cols.size(); ++i) {
    const std::string& c = cols[i];
    if (c.size() > 2 && c.ends_with(".x") && cols[i + 3] == c.substr(0, c.size() - 2) + ".e0") {
      const std::string body = c.substr(0, c.size() - 2);
      const int ci = static_cast<int>(i);
      items.push_back({body + ".position", "m", ci, Item::kVector});
      items.push_back({body + ".rotation", "rad", ci + 3, Item::kRotation});
      items.push_back({body + ".velocity", "m/s", ci + 7, Item::kVector});
      items.push_back({body + ".angular_velocity", "rad/s", ci + 10, Item::kVector});
      std::size_t j = i + 13;
      while (j + 2 < cols.size() && cols[j].starts_with(body + ".") && cols[j].ends_with(".x") &&
             cols[j + 1].ends_with(".y") && cols[j + 2].ends_with(".z")) {
        items.push_back(
            {cols[j].substr(0, cols[j].size() - 2), "m", static_cast<int>(j), Item::kPoint});
        j += 3;
      }
      // Modal coordinates of a flexible body: "<B>.q<k>" (not the rates "<B>.qd<k>").
      Item modes{body + ".modes", "-", -1, Item::kModes};
      for (std::size_t m = j; m < cols.size() && cols[m].starts_with(body + ".q"); ++m) {
        const std::string tail = cols[m].substr(body.size() + 2);
        if (!tail.empty() &&
            std::all_of(tail.begin(), tail.end(), [](char ch) { return ch >= '0' && ch <= '9'; })) {
          modes.modal_columns.push_back(m);
        }
      }
      if (!modes.modal_columns.empty()) items.push_back(modes);
      i = j - 1;
    }
  }

  ComparisonReport report;
  for (const Item& item : items) {
    Accumulator acc;
    for (std::size_t k = 0; k < run.size(); ++k) {
      const auto& a = run.rows[k];
      const auto& b = reference.rows[k];
      if (item.kind == Item::kModes) {
        // max_i |q_i − q_i,ref| at this time
        double worst = 0.0;
        for (std::size_t c : item.modal_columns) worst = std::max(worst, std::abs(a[c] - b[c]));
        acc.add(worst);
      } else if (item.kind == Item::kRotation) {
        const auto c = static_cast<std::size_t>(item.column);
        const rotation::EulerParameters qa(a[c], a[c + 1], a[c + 2], a[c + 3]);
        const rotation::EulerParameters qb(b[c], b[c + 1], b[c + 2], b[c + 3]);
        acc.add(rotation::geodesic_angle(qa, qb));
      } else {
        acc.add((vec3(a, item.column) - vec3(b, item.column)).norm());
      }
    }
    const ErrorNorms norms = acc.norms();
    if (item.kind == Item::kRotation) {
      report.max_rotation_linf = std::max(report.max_rotation_linf, norms.linf);
    }
    if (item.kind == Item::kPoint)
      report.max_point_linf = std::max(report.max_point_linf, norms.linf);
    if (item.kind == Item::kModes)
      report.max_modal_linf = std::max(report.max_modal_linf, norms.linf);
    report.quantities.push_back({item.name, item.unit, norms});
  }
  // Wear work of named contacts: the relative error of the final value (the cumulative work is
  // what a wear model consumes; its history is monotone).
  for (std::size_t c = 1; c < cols.size() && run.size() > 0; ++c) {
    if (!cols[c].ends_with(".wear_work")) continue;
    const double a = run.rows.back()[c];
    const double b = reference.rows.back()[c];
    const double e = b != 0.0 ? std::abs(a - b) / std::abs(b) : std::abs(a);
    report.max_wear_relative = std::isnan(e) ? e : std::max(report.max_wear_relative, e);
    ErrorNorms norms;
    norms.linf = norms.rms = norms.final = e;
    report.quantities.push_back({cols[c], "-", norms});
  }
  return report;
}

double metric_value(const ComparisonReport& report, const std::string& metric) {
  if (metric == "rotation+points") return report.default_metric();
  if (metric == "rotation") return report.max_rotation_linf;
  if (metric == "points") return report.max_point_linf;
  if (metric == "modes") return report.max_modal_linf;
  if (metric == "position" || metric == "velocity" || metric == "angular_velocity") {
    double value = 0.0;
    for (const QuantityError& q : report.quantities) {
      if (q.name.ends_with("." + metric)) value = std::max(value, q.norms.linf);
    }
    return value;
  }
  if (metric == "wear") {
    if (report.max_wear_relative < 0.0) {
      throw std::invalid_argument(
          "metric 'wear' needs a named contact (a C.wear_work column, docs/output.md)");
    }
    return report.max_wear_relative;
  }
  throw std::invalid_argument("unknown metric '" + metric +
                              "' (rotation+points, rotation, points, modes, position, "
                              "velocity, angular_velocity, wear)");
}

}  // namespace flexref::studies
