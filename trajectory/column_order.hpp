#pragma once
/// \file column_order.hpp
/// The order of a model's trajectory columns (docs/output.md), written once: the header's names
/// (ColumnLayout::of), the rows of the double trajectory table (trajectory::tabulate) and the
/// precision references' rows (precision::OdeSystemTpl::output_row) all walk it, so no two of
/// them can disagree on which column comes where.
///
/// The order: t; per body its position, Euler parameters, velocity, angular velocity, its tracked
/// points, its modal coordinates and their rates, and a prescribed body's drive torque; per ideal
/// joint its reaction force and torque and its position and velocity violations; the energy, and
/// where the model tracks work the dissipated work, the applied work, the drives' work and the
/// energy balance; per wear channel its normal force, slip speed, wear work and impacts, and with
/// a wear law its largest worn depth, worn volume and each depth.
#include "trajectory/column_layout.hpp"

namespace flexref::trajectory {

/// One group of columns: its kind, whose it is (a body, joint or wear channel; −1 for t and the
/// energy columns), the tracked point (kind point) and, for the indexed kinds (mode, mode_rate,
/// depth), how many columns the group has.
struct ColumnGroup {
  ColumnKind kind = ColumnKind::unknown;
  int owner = -1;
  int point = -1;
  int count = 1;
};

/// Calls visit(group) for each group of the columns of `model` (a core::ModelTpl<S>), in the
/// order they are written.
template <typename Model, typename Visit>
void for_each_column_group(const Model& model, Visit&& visit) {
  using K = ColumnKind;
  visit(ColumnGroup{K::time});
  for (int i = 0; i < model.num_bodies(); ++i) {
    const auto& b = model.body(i);
    for (K k : {K::position, K::rotation, K::velocity, K::angular_velocity})
      visit(ColumnGroup{k, i});
    // Points right after the rigid block, in the order of the body's description.
    const auto points = static_cast<int>(b.description().points.size());
    for (int p = 0; p < points; ++p) visit(ColumnGroup{K::point, i, p});
    visit(ColumnGroup{K::mode, i, -1, b.mode_count()});
    visit(ColumnGroup{K::mode_rate, i, -1, b.mode_count()});
    if (b.is_prescribed()) visit(ColumnGroup{K::drive_torque, i});
  }
  if (model.has_constraints()) {
    for (int j = 0; j < model.constraints()->joint_count(); ++j) {
      for (K k : {K::reaction_force, K::reaction_torque, K::violation, K::violation_rate}) {
        visit(ColumnGroup{k, j});
      }
    }
  }
  visit(ColumnGroup{K::energy});
  if (model.tracks_work()) {
    visit(ColumnGroup{K::dissipated_work});
    if (model.tracks_applied_work()) visit(ColumnGroup{K::applied_work});
    if (model.tracks_drive_work()) visit(ColumnGroup{K::drive_work});
    visit(ColumnGroup{K::energy_balance});
  }
  for (int c = 0; c < model.wear_channel_count(); ++c) {
    for (K k : {K::normal_force, K::slip_speed, K::wear_work, K::impacts}) visit(ColumnGroup{k, c});
    const int depths = model.channel_depth_count(c);
    if (depths == 0) continue;
    visit(ColumnGroup{K::wear_depth, c});
    visit(ColumnGroup{K::wear_volume, c});
    visit(ColumnGroup{K::depth, c, -1, depths});
  }
}

}  // namespace flexref::trajectory
