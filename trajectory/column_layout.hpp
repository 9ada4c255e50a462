#pragma once
/// \file column_layout.hpp
/// The typed columns of a trajectory table (docs/output.md): one description of which columns a
/// body, a tracked point, a joint, a named contact and the energy bookkeeping have, used both to
/// write a table's header (ColumnLayout::of) and to read one back (ColumnLayout::parse), so that
/// no other code takes a column name apart by its characters.
///
/// A name is `t`; `B.<suffix>` for a body B's own columns, a joint's or a named contact's;
/// `B.P.<x|y|z>` for B's tracked point P; or one of the energy columns. Names of bodies, points,
/// joints and contacts have no dots (scenes/README.md), so the dots split a name unambiguously,
/// and every suffix belongs to one kind: `x y z` (position), `e0..e3` (Euler parameters),
/// `vx vy vz`, `W1 W2 W3`, `q<k>`, `qd<k>`, `drive_torque`; a joint's `fx fy fz`, `tx ty tz`,
/// `phi`, `phi_dot`; a contact's `fn`, `slip_speed`, `wear_work`, `impacts`, and with a wear law
/// `wear_depth`, `wear_volume`, `depth<k>`.
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/model.hpp"

namespace flexref::trajectory {

/// What a column holds. Each kind is a group of one or more components: `position` is x, y, z;
/// `mode` is one modal coordinate, its component the index k of `q<k>`.
enum class ColumnKind {
  time,              ///< t, s
  position,          ///< p_WBo of a body, m (x, y, z)
  rotation,          ///< Euler parameters θ (B → W), e0..e3
  velocity,          ///< v_WBo, m/s (vx, vy, vz)
  angular_velocity,  ///< ω̄, body frame, rad/s (W1, W2, W3)
  point,             ///< p_WP of a tracked point, m (x, y, z)
  mode,              ///< a modal coordinate q<k>
  mode_rate,         ///< its rate qd<k>
  drive_torque,      ///< the torque that drives a prescribed body, N·m
  reaction_force,    ///< an ideal joint's reaction force on its first body, world, N
  reaction_torque,   ///< and torque about the joint point, world, N·m
  violation,         ///< the joint's largest position-constraint violation, m | rad
  violation_rate,    ///< and velocity-constraint violation, m/s | rad/s
  energy,            ///< E, J
  dissipated_work,   ///< W_d, J
  applied_work,      ///< W_a, J
  drive_work,        ///< W_drive, J: the work the joints' drives did
  energy_balance,    ///< E − E(0) + W_d − W_a − W_drive, J
  normal_force,      ///< a named contact's normal force, N
  slip_speed,        ///< its slip speed, m/s
  wear_work,         ///< its wear work, J
  impacts,           ///< its number of impacts
  wear_depth,        ///< its largest worn depth, m (a contact with a wear law)
  wear_volume,       ///< its worn volume, m³
  depth,             ///< the worn depth depth<k> of its point or sector k (from 1), m
  unknown,           ///< none of the above (a user's own column)
};

/// Whose column it is.
enum class ColumnOwner { none, body, point, joint, contact };

/// One typed column.
struct Column {
  ColumnKind kind = ColumnKind::unknown;
  std::string owner;  ///< the body, joint or contact ("" for t and the energy columns)
  std::string point;  ///< the tracked point (kind point)
  /// The component within the kind's group (0 for x, e0, vx, W1, fx, tx; 1 for y, e1, …), or
  /// the mode's index k of `q<k>`, `qd<k>`, or a contact's point or sector k of `depth<k>` (from
  /// 1, as written).
  int component = 0;
  std::string name;  ///< the column's name as written
};

/// Whose columns a kind's are, the unit of a column of that kind, and what a group of that kind
/// is called in messages ("Euler parameters", "a position").
ColumnOwner owner_of(ColumnKind kind);
const char* unit_of(ColumnKind kind);
const char* group_name(ColumnKind kind);
/// The number of components of a kind's group: 3 for position, 4 for rotation, 1 for a mode
/// (each mode a group of its own) and the scalars.
int group_size(ColumnKind kind);
/// True for the kinds the error metrics measure: the body's state groups, points, modes, a
/// joint's reaction and position violation, a contact's wear work (not qd, drive_torque,
/// phi_dot, fn, slip_speed, impacts, the energies).
bool is_measured(ColumnKind kind);

/// The name of a column from its kind, owner, point and component (the inverse of
/// parse_column); throws std::invalid_argument for a component outside the kind's group.
std::string column_name(ColumnKind kind, const std::string& owner, int component,
                        const std::string& point = {});

/// The typed column a name denotes; kind unknown when it is none of the described ones (the
/// owner is then what precedes the first dot, "" without one).
Column parse_column(const std::string& name);

class ColumnLayout {
 public:
  ColumnLayout() = default;

  /// The columns of a model's trajectory table, in the order they are written: t; per body
  /// p, θ, v, ω̄, its tracked points, q<k>, qd<k>, the drive torque (prescribed bodies); per
  /// ideal joint its reaction and violations; the energy columns the model has; per named
  /// contact its four outputs, then with a wear law its largest depth, volume and depths.
  static ColumnLayout of(const core::Model& model);

  /// The typed columns of a header, in its order; unknown names stay as kind unknown.
  static ColumnLayout parse(const std::vector<std::string>& names);

  const std::vector<Column>& columns() const { return columns_; }
  std::size_t size() const { return columns_.size(); }
  const Column& operator[](std::size_t i) const { return columns_[i]; }
  std::vector<std::string> names() const;
  std::vector<std::string> units() const;

  /// Index of a column, or -1.
  int find(ColumnKind kind, std::string_view owner, int component,
           std::string_view point = {}) const;
  /// The indices of a whole group (group_size(kind) of them) into `indices`; false when one is
  /// missing.
  bool find_group(ColumnKind kind, std::string_view owner, std::span<int> indices,
                  std::string_view point = {}) const;
  /// The owners of the known columns (bodies, joints, contacts), in the order of their first
  /// column.
  std::vector<std::string> owners() const;
  /// The indices of a body's columns of `kind` (mode or mode_rate), in column order.
  std::vector<std::size_t> mode_columns(ColumnKind kind, std::string_view body) const;

 private:
  std::vector<Column> columns_;
};

}  // namespace flexref::trajectory
