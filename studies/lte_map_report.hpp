#pragma once
/// \file lte_map_report.hpp
/// What the `lte-map` study reports (studies/lte_map.hpp): a metric's value at a grid point,
/// where it crosses a level along each inertia ratio's row, the CSV of every point and the
/// terminal table.
#include <string>
#include <vector>

#include "studies/lte_map.hpp"

namespace flexref::studies {

/// A metric of the map: which simplification, which measure (absolute values).
enum class LteMapMetric { kTip, kEnvelope, kFrequency };
double lte_map_value(const LteMapPoint& point, bool classical, LteMapMetric metric);

/// Where a metric (default: the LTE tip error) crosses `level` along each inertia ratio's row:
/// the spin ratio by log-log interpolation between the bracketing grid points, NaN when the
/// row does not cross.
std::vector<double> lte_map_crossings(const LteMapResult& result, double level,
                                      bool classical = false,
                                      LteMapMetric metric = LteMapMetric::kTip);

/// CSV columns: spin_ratio,inertia_ratio,spin,omega1,hub_scale,load_scale,tip_error,
/// envelope_error,frequency_shift,attitude_error,classical_tip_error,classical_envelope_error,
/// classical_frequency_shift,max_deflection,truth_frequency,truth_estimate,lte_estimate,
/// classical_estimate,resolved,classical_resolved,status. A value that is not measured (a
/// failed point, the classical columns of a two-level map, a frequency the status says is
/// missing) is an empty cell, never NaN.
std::string lte_map_csv(const LteMapResult& result);
/// The terminal table: the LTE tip error (%) per inertia ratio (rows) and spin ratio (columns),
/// the classical coupled model's (stiffened truth), the crossings of the 1 %, 5 % and 20 % lines
/// of every metric, and the notes.
std::string format_lte_map_table(const LteMapResult& result);

}  // namespace flexref::studies
