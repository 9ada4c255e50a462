#include "precision/roundoff_scale.hpp"

#include <algorithm>
#include <cmath>

#include "studies/certified_reference.hpp"

namespace flexref::precision {
namespace {

/// The columns `stem` + each suffix, or false when one is missing.
bool find_columns(const studies::TrajectoryTable& table, const std::string& stem,
                  const char* const (&suffixes)[3], int (&index)[3]) {
  for (int k = 0; k < 3; ++k) {
    index[k] = table.column(stem + suffixes[k]);
    if (index[k] < 0) return false;
  }
  return true;
}

double norm_at(const studies::TrajectoryTable& table, std::size_t row, const int (&index)[3]) {
  const std::vector<double>& r = table.rows[row];
  return std::hypot(r[static_cast<std::size_t>(index[0])], r[static_cast<std::size_t>(index[1])],
                    r[static_cast<std::size_t>(index[2])]);
}

double distance_between(const studies::TrajectoryTable& table, std::size_t a, std::size_t b,
                        const int (&index)[3]) {
  double sum = 0.0;
  for (const int i : index) {
    const double d =
        table.rows[b][static_cast<std::size_t>(i)] - table.rows[a][static_cast<std::size_t>(i)];
    sum += d * d;
  }
  return std::sqrt(sum);
}

}  // namespace

double roundoff_scale(const studies::TrajectoryTable& table, const std::string& metric) {
  const bool rotation = metric == "rotation" || metric == "rotation+points";
  const bool points = metric == "points" || metric == "rotation+points";
  double swept_angle = 0.0;  // the largest ∫|ω̄| dt of a body
  double path = 0.0;         // the longest path of a tracked point
  for (const std::string& name : table.columns) {
    int index[3];
    if (rotation && name.ends_with(".W1")) {
      const std::string body = name.substr(0, name.size() - 3);
      if (!find_columns(table, body, {".W1", ".W2", ".W3"}, index)) continue;
      double angle = 0.0;
      for (std::size_t k = 1; k < table.size(); ++k) {
        angle += 0.5 * (norm_at(table, k - 1, index) + norm_at(table, k, index)) *
                 (table.time(k) - table.time(k - 1));
      }
      swept_angle = std::max(swept_angle, angle);
    }
    // Tracked points "<B>.<P>.x" (one dot before the suffix: a body's own B.x is its origin).
    if (points && name.ends_with(".x") && std::count(name.begin(), name.end(), '.') == 2) {
      const std::string stem = name.substr(0, name.size() - 2);
      if (!find_columns(table, stem, {".x", ".y", ".z"}, index)) continue;
      double length = 0.0;
      for (std::size_t k = 1; k < table.size(); ++k)
        length += distance_between(table, k - 1, k, index);
      path = std::max(path, length);
    }
  }
  return studies::solution_scale(table, metric) + swept_angle + path;
}

}  // namespace flexref::precision
