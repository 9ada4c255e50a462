#include "precision/roundoff_scale.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "scene/scene_spec.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/column_layout.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::precision {
namespace {

double value(const trajectory::TrajectoryTable& table, std::size_t row, int column) {
  return table.rows[row][static_cast<std::size_t>(column)];
}

double norm_at(const trajectory::TrajectoryTable& table, std::size_t row, const int (&index)[3]) {
  return std::hypot(value(table, row, index[0]), value(table, row, index[1]),
                    value(table, row, index[2]));
}

/// |a − b| of two column triples in one row.
double distance_at(const trajectory::TrajectoryTable& table, std::size_t row, const int (&a)[3],
                   const int (&b)[3]) {
  return std::hypot(value(table, row, a[0]) - value(table, row, b[0]),
                    value(table, row, a[1]) - value(table, row, b[1]),
                    value(table, row, a[2]) - value(table, row, b[2]));
}

/// |q̇_f| of a body at an output row from its columns qd_1 … (indices), 0 without them.
double modal_rate_at(const trajectory::TrajectoryTable& table, std::size_t row,
                     const std::vector<int>& qd) {
  double sum = 0.0;
  for (const int c : qd) sum += value(table, row, c) * value(table, row, c);
  return std::sqrt(sum);
}

/// The columns <body>.qd1, <body>.qd2, … present in the table.
std::vector<int> modal_rate_columns(const trajectory::ColumnLayout& layout,
                                    const std::string& body) {
  std::vector<int> qd;
  for (int k = 1;; ++k) {
    const int c = layout.find(trajectory::ColumnKind::mode_rate, body, k);
    if (c < 0) return qd;
    qd.push_back(c);
  }
}

}  // namespace

std::vector<NodePoint> node_points(const scene::SceneSpec& spec) {
  std::vector<NodePoint> nodes;
  for (const scene::BodySpec& body : spec.bodies) {
    const core::RigidBodyDescription& d = body.description;
    if (!d.flexible) continue;
    for (const core::TrackedPoint& p : d.points) {
      if (p.node < 0) continue;
      nodes.push_back({d.name + "." + p.name, d.flexible->modal.mode_rows(p.node).norm()});
    }
  }
  return nodes;
}

double roundoff_scale(const trajectory::TrajectoryTable& table, const std::string& metric,
                      std::span<const NodePoint> nodes) {
  if (metric == trajectory::kDefaultMetric) {
    // The default metric's errors are fractions of each quantity's range: the rotation's
    // round-off over π, the points' over the smallest extent of a point (which bounds every
    // point's fraction). Summed: a bound on the larger of the two.
    double smallest_extent = std::numeric_limits<double>::infinity();
    bool rotation = false;
    for (const trajectory::QuantityError& q :
         trajectory::compare_trajectories(table, table).quantities) {
      rotation |= q.kind == "rotation";
      if (q.kind == "point") smallest_extent = std::min(smallest_extent, q.bound);
    }
    double scale = rotation ? roundoff_scale(table, "rotation", nodes) / std::numbers::pi : 0.0;
    if (std::isfinite(smallest_extent)) {
      scale += roundoff_scale(table, "points", nodes) / smallest_extent;
    }
    return scale;
  }
  const bool rotation = metric == "rotation" || metric == "rotation+points";
  const bool points = metric == "points" || metric == "rotation+points";
  const double duration = table.size() > 1 ? table.time(table.size() - 1) - table.time(0) : 0.0;
  double largest_rate = 0.0;   // max |ω̄| of a body at an output
  double largest_speed = 0.0;  // max |v_WBo| + |ω̄| |p_WP − p_WBo| of a tracked point
  double longest_path = 0.0;   // the polyline through a point's outputs (no body columns)
  using trajectory::ColumnKind;
  const trajectory::ColumnLayout layout = trajectory::ColumnLayout::parse(table.columns);
  for (const trajectory::Column& column : layout.columns()) {
    int w[3];
    if (rotation && column.kind == ColumnKind::angular_velocity && column.component == 0) {
      if (!layout.find_group(ColumnKind::angular_velocity, column.owner, w)) continue;
      for (std::size_t k = 0; k < table.size(); ++k) {
        largest_rate = std::max(largest_rate, norm_at(table, k, w));
      }
    }
    // Tracked points, at their x column.
    if (!points || column.kind != ColumnKind::point || column.component != 0) continue;
    const std::string& body = column.owner;
    const std::string stem = body + "." + column.point;
    int p[3], o[3], v[3];
    if (!layout.find_group(ColumnKind::point, body, p, column.point)) continue;
    if (layout.find_group(ColumnKind::position, body, o) &&
        layout.find_group(ColumnKind::velocity, body, v) &&
        layout.find_group(ColumnKind::angular_velocity, body, w)) {
      // A node's elastic speed ‖Φ_k‖_F |q̇_f| on top of its rigid-motion speed.
      const auto node = std::find_if(nodes.begin(), nodes.end(),
                                     [&](const NodePoint& n) { return n.stem == stem; });
      const double shape_norm = node != nodes.end() ? node->shape_norm : 0.0;
      const std::vector<int> qd =
          shape_norm > 0.0 ? modal_rate_columns(layout, body) : std::vector<int>{};
      for (std::size_t k = 0; k < table.size(); ++k) {
        largest_speed =
            std::max(largest_speed, norm_at(table, k, v) +
                                        norm_at(table, k, w) * distance_at(table, k, p, o) +
                                        shape_norm * modal_rate_at(table, k, qd));
      }
    } else {
      double length = 0.0;
      for (std::size_t k = 1; k < table.size(); ++k) {
        length += std::hypot(value(table, k, p[0]) - value(table, k - 1, p[0]),
                             value(table, k, p[1]) - value(table, k - 1, p[1]),
                             value(table, k, p[2]) - value(table, k - 1, p[2]));
      }
      longest_path = std::max(longest_path, length);
    }
  }
  return trajectory::solution_scale(table, metric) + duration * largest_rate +
         std::max(duration * largest_speed, longest_path);
}

}  // namespace flexref::precision
