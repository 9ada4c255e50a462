#pragma once
/// \file error_metrics_tpl.hpp
/// The error norms of trajectory/error_metrics.hpp written once for any scalar type S: the double
/// comparison (compare_trajectories) instantiates it with double, and precision/ with long
/// double or float128 to compare references beyond double without rounding their values to
/// double before subtracting (docs/precision.md, "compare"). Only the reduced norms are
/// returned as double.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "rotation/euler_parameters.hpp"
#include "trajectory/column_layout.hpp"
#include "trajectory/error_metrics.hpp"

namespace flexref::trajectory::detail {

/// A measured quantity: its kind and the column indices (same in both tables).
struct Item {
  QuantityError quantity;
  std::vector<std::size_t> columns;
};

/// The quantities a table's columns measure, body by body in column order: position,
/// rotation, velocity, angular velocity (each only when its whole group of columns is
/// present), the tracked points, the modal coordinates.
std::vector<Item> find_items(const TrajectoryTable& table);

/// L∞ (with the time it is reached), RMS and final value of an error history, accumulated in S.
/// The RMS keeps the plain sum of squares and, beside it, a scaled one (LAPACK's dlassq: the
/// largest value so far and the sum of squares of the values divided by it), used when the plain
/// sum over- or underflows: errors of 1e200 give an RMS of 1e200, not inf, and errors of 1e-200
/// not 0. Where the plain sum is representable it is used, so ordinary results keep their bits.
template <typename S>
class Accumulator {
 public:
  void add(double t, S e) {
    using std::isfinite;
    // A non-finite error (a diverged run) makes every norm infinite, never silently small.
    if (!static_cast<bool>(isfinite(e))) e = std::numeric_limits<S>::infinity();
    if (count_ == 0 || e > linf_) {
      linf_ = e;
      linf_time_ = t;
    }
    sum_sq_ += e * e;
    if (e > scale_) {
      const S r = scale_ / e;
      scaled_sum_sq_ = S(1) + scaled_sum_sq_ * r * r;
      scale_ = e;
    } else if (e > S(0)) {
      const S r = e / scale_;
      scaled_sum_sq_ += r * r;
    }
    final_ = e;
    ++count_;
  }
  ErrorNorms norms() const {
    using std::isfinite;
    using std::sqrt;
    ErrorNorms n;
    n.linf = static_cast<double>(linf_);
    n.final = static_cast<double>(final_);
    if (count_ == 0) return n;
    const bool plain = static_cast<bool>(isfinite(sum_sq_)) &&
                       (sum_sq_ >= std::numeric_limits<S>::min() || linf_ == S(0));
    const bool finite = static_cast<bool>(isfinite(scale_));
    n.rms = plain    ? static_cast<double>(S(sqrt(sum_sq_ / S(count_))))
            : finite ? static_cast<double>(S(scale_ * sqrt(scaled_sum_sq_ / S(count_))))
                     : std::numeric_limits<double>::infinity();
    return n;
  }
  double linf_time() const { return linf_time_; }

 private:
  S linf_ = S(0);
  S final_ = S(0);
  S sum_sq_ = S(0);
  S scale_ = S(0);          ///< the largest error so far (0 before the first nonzero one)
  S scaled_sum_sq_ = S(0);  ///< Σ (e/scale_)²
  double linf_time_ = 0.0;
  long count_ = 0;
};

/// |(dx, dy, dz)| without overflow or underflow in the squares: the plain root of the sum of
/// squares where it is representable (ordinary results keep their bits), else the largest
/// component times the root of the sum of the squared ratios.
template <typename S>
S vector_norm(S dx, S dy, S dz) {
  using std::abs;
  using std::isfinite;
  using std::sqrt;
  S plain;
  if constexpr (std::is_same_v<S, double>) {
    plain = Eigen::Vector3d(dx, dy, dz).norm();
  } else {
    plain = S(sqrt(dx * dx + dy * dy + dz * dz));
  }
  const S m = std::max({S(abs(dx)), S(abs(dy)), S(abs(dz))});
  if (!static_cast<bool>(isfinite(m)) || m == S(0))
    return static_cast<bool>(isfinite(m)) ? plain : m;
  if (static_cast<bool>(isfinite(plain)) && plain * plain >= std::numeric_limits<S>::min()) {
    return plain;
  }
  const S x = dx / m;
  const S y = dy / m;
  const S z = dz / m;
  return m * S(sqrt(x * x + y * y + z * z));
}

/// |log(A(a)ᵀ A(b))| = 2 atan2(|vec(a* ⊗ b)|, |scalar(a* ⊗ b)|) (rotation::geodesic_angle,
/// which double calls).
template <typename S>
S geodesic_angle(const S (&a)[4], const S (&b)[4]) {
  if constexpr (std::is_same_v<S, double>) {
    return rotation::geodesic_angle(rotation::EulerParameters(a[0], a[1], a[2], a[3]),
                                    rotation::EulerParameters(b[0], b[1], b[2], b[3]));
  } else {
    using std::abs;
    using std::atan2;
    using std::sqrt;
    // a* ⊗ b, its vector part as differences of mirrored products, so that a = b gives exactly
    // 0 (every difference is of two equal products).
    const S d0 = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    const S d1 = (a[0] * b[1] - a[1] * b[0]) + (a[3] * b[2] - a[2] * b[3]);
    const S d2 = (a[0] * b[2] - a[2] * b[0]) + (a[1] * b[3] - a[3] * b[1]);
    const S d3 = (a[0] * b[3] - a[3] * b[0]) + (a[2] * b[1] - a[1] * b[2]);
    return S(2) * atan2(sqrt(d1 * d1 + d2 * d2 + d3 * d3), abs(d0));
  }
}

/// QuantityError::bound of a quantity from the reference (table 1) alone: π for a rotation; for
/// the modes the largest range of a coordinate; otherwise the extent of the reference's values,
/// twice the largest distance from the centre of their bounding box (an upper bound on their
/// diameter, exact for a symmetric set such as a sphere). +∞ when that is 0 (a constant
/// quantity has no range to saturate) or not finite. In double: a bound needs no more.
template <typename Cell>
double reference_bound(const TrajectoryTable& shape, Cell cell, const std::string& kind,
                       const std::vector<std::size_t>& c) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (kind == "rotation") return 3.14159265358979323846;
  if (kind == "violation") return kNone;  // the run's own value: no range of the reference's
  const std::size_t n = shape.size();
  std::vector<double> lo(c.size(), kNone), hi(c.size(), -kNone);
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t j = 0; j < c.size(); ++j) {
      const auto v = static_cast<double>(cell(1, k, c[j]));
      lo[j] = std::min(lo[j], v);
      hi[j] = std::max(hi[j], v);
    }
  }
  double bound = 0.0;
  if (kind == "modes") {
    for (std::size_t j = 0; j < c.size(); ++j) bound = std::max(bound, hi[j] - lo[j]);
  } else {
    for (std::size_t k = 0; k < n; ++k) {
      double d2 = 0.0;
      for (std::size_t j = 0; j < c.size(); ++j) {
        const double d = static_cast<double>(cell(1, k, c[j])) - 0.5 * (lo[j] + hi[j]);
        d2 += d * d;
      }
      bound = std::max(bound, 2.0 * std::sqrt(d2));
    }
  }
  return bound > 0.0 && std::isfinite(bound) ? bound : kNone;
}

/// compare_trajectories' norms in S. `shape` gives the columns and the times (the caller has
/// checked that both tables have them); cell(table, k, i) is column i of row k of the run
/// (table 0) or the reference (table 1) in S.
template <typename S, typename Cell>
ComparisonReport compare_cells(const TrajectoryTable& shape, Cell cell) {
  using std::abs;
  using std::isnan;
  using std::sqrt;
  ComparisonReport report;
  report.rows = shape.size();
  for (Item& item : find_items(shape)) {
    Accumulator<S> acc;
    const std::string& kind = item.quantity.kind;
    const auto& c = item.columns;
    for (std::size_t k = 0; k < shape.size(); ++k) {
      const double t = shape.time(k);
      if (kind == "modes") {
        // max_i |q_i − q_i,ref| at this time (NaN propagates through the sum to the norms)
        S worst(0);
        for (std::size_t i : c) {
          const S d = abs(S(cell(0, k, i) - cell(1, k, i)));
          worst = static_cast<bool>(isnan(d)) ? d : (d > worst ? d : worst);
          if (static_cast<bool>(isnan(worst))) break;
        }
        acc.add(t, worst);
      } else if (kind == "violation") {
        // The run's own |Φ| (the reference holds Φ at its solver's round-off): how far the run
        // has left the constraint manifold, not a difference of two drifts.
        acc.add(t, S(abs(S(cell(0, k, c[0])))));
      } else if (kind == "rotation") {
        const S qa[4] = {cell(0, k, c[0]), cell(0, k, c[1]), cell(0, k, c[2]), cell(0, k, c[3])};
        const S qb[4] = {cell(1, k, c[0]), cell(1, k, c[1]), cell(1, k, c[2]), cell(1, k, c[3])};
        acc.add(t, geodesic_angle(qa, qb));
      } else {
        const S dx = cell(0, k, c[0]) - cell(1, k, c[0]);
        const S dy = cell(0, k, c[1]) - cell(1, k, c[1]);
        const S dz = cell(0, k, c[2]) - cell(1, k, c[2]);
        acc.add(t, vector_norm(dx, dy, dz));
      }
    }
    item.quantity.norms = acc.norms();
    item.quantity.linf_time = acc.linf_time();
    item.quantity.bound = reference_bound(shape, cell, kind, c);
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
  // A quantity whose extent is below kHeldFraction of the largest of its kind is one the model
  // holds (a point on a joint to the ground, a body's centre on a symmetry axis): its extent is
  // the reference's round-off, and the run's error there, however small beside the motion, is
  // not a fraction of a range it could saturate.
  for (QuantityError& q : report.quantities) {
    if (q.kind == "rotation" || q.kind == "violation" || !std::isfinite(q.bound)) continue;
    double largest = 0.0;
    for (const QuantityError& other : report.quantities) {
      if (other.kind == q.kind && std::isfinite(other.bound))
        largest = std::max(largest, other.bound);
    }
    if (q.bound < kHeldFraction * largest) q.bound = std::numeric_limits<double>::infinity();
  }
  // Wear work of named contacts, and the largest worn depth of those with a wear law: the
  // relative error of the final value (the cumulative work is what a wear model consumes, the
  // depth what it produces; both histories are monotone).
  const std::vector<std::string>& cols = shape.columns;
  for (std::size_t i = 1; i < cols.size() && shape.size() > 0; ++i) {
    const ColumnKind kind = parse_column(cols[i]).kind;
    if (kind != ColumnKind::wear_work && kind != ColumnKind::wear_depth) continue;
    const std::size_t last = shape.size() - 1;
    const S a = cell(0, last, i);
    const S b = cell(1, last, i);
    const double e = static_cast<double>(b != S(0) ? S(abs(S(a - b)) / abs(b)) : S(abs(a)));
    report.max_wear_relative = std::isnan(e) ? e : std::max(report.max_wear_relative, e);
    QuantityError wear{cols[i], "-", "wear", {}, shape.time(last), {cols[i]}};
    wear.norms.linf = wear.norms.rms = wear.norms.final = e;
    report.quantities.push_back(std::move(wear));
  }
  return report;
}

}  // namespace flexref::trajectory::detail
