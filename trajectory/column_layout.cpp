#include "trajectory/column_layout.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "trajectory/column_order.hpp"

namespace flexref::trajectory {
namespace {

/// One row of the description: a kind, whose it is, its components' suffixes (none for the
/// indexed modes, whose suffix is a prefix followed by k), the unit of each component, and the
/// group's name in messages.
struct KindDescription {
  ColumnKind kind;
  ColumnOwner owner;
  std::vector<std::string_view> suffixes;  ///< the components, in order
  std::string_view indexed_prefix;         ///< "q" and "qd": the suffix is prefix + k
  const char* unit;
  const char* group;
  bool measured;
};

const std::vector<KindDescription>& description() {
  using K = ColumnKind;
  using O = ColumnOwner;
  static const std::vector<KindDescription> kinds{
      {K::time, O::none, {"t"}, {}, "s", "the time", false},
      {K::position, O::body, {"x", "y", "z"}, {}, "m", "a position", true},
      {K::rotation, O::body, {"e0", "e1", "e2", "e3"}, {}, "-", "Euler parameters", true},
      {K::velocity, O::body, {"vx", "vy", "vz"}, {}, "m/s", "a velocity", true},
      {K::angular_velocity, O::body, {"W1", "W2", "W3"}, {}, "rad/s", "an angular velocity", true},
      {K::point, O::point, {"x", "y", "z"}, {}, "m", "a point", true},
      {K::mode, O::body, {}, "q", "modal", "a modal coordinate", true},
      {K::mode_rate, O::body, {}, "qd", "modal/s", "a modal rate", false},
      {K::drive_torque, O::body, {"drive_torque"}, {}, "N*m", "a drive torque", false},
      {K::reaction_force, O::joint, {"fx", "fy", "fz"}, {}, "N", "a reaction force", true},
      {K::reaction_torque, O::joint, {"tx", "ty", "tz"}, {}, "N*m", "a reaction torque", true},
      {K::violation, O::joint, {"phi"}, {}, "m|rad", "a position violation", true},
      {K::violation_rate, O::joint, {"phi_dot"}, {}, "m/s|rad/s", "a velocity violation", false},
      {K::energy, O::none, {"energy"}, {}, "J", "the energy", false},
      {K::dissipated_work, O::none, {"dissipated_work"}, {}, "J", "the dissipated work", false},
      {K::applied_work, O::none, {"applied_work"}, {}, "J", "the applied work", false},
      {K::drive_work, O::none, {"drive_work"}, {}, "J", "the drives' work", false},
      {K::energy_balance, O::none, {"energy_balance"}, {}, "J", "the energy balance", false},
      {K::normal_force, O::contact, {"fn"}, {}, "N", "a normal force", false},
      {K::slip_speed, O::contact, {"slip_speed"}, {}, "m/s", "a slip speed", false},
      {K::wear_work, O::contact, {"wear_work"}, {}, "J", "a wear work", true},
      {K::impacts, O::contact, {"impacts"}, {}, "-", "a number of impacts", false},
      {K::wear_depth, O::contact, {"wear_depth"}, {}, "m", "a largest worn depth", false},
      {K::wear_volume, O::contact, {"wear_volume"}, {}, "m^3", "a worn volume", false},
      {K::depth, O::contact, {}, "depth", "m", "a worn depth", false},
  };
  return kinds;
}

const KindDescription& described(ColumnKind kind) {
  for (const KindDescription& d : description()) {
    if (d.kind == kind) return d;
  }
  throw std::invalid_argument("column kind without a description");
}

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// The kind and component of a suffix among the kinds of one owner class; false when none.
bool match_suffix(std::string_view suffix, bool point_owner, Column& column) {
  for (const KindDescription& d : description()) {
    if (d.owner == ColumnOwner::none || (d.owner == ColumnOwner::point) != point_owner) continue;
    if (!d.indexed_prefix.empty()) {
      const std::string_view rest = suffix.substr(std::min(suffix.size(), d.indexed_prefix.size()));
      if (suffix.starts_with(d.indexed_prefix) && all_digits(rest)) {
        column.kind = d.kind;
        // Digits only, at most as many as a name can carry: k fits an int for any real table;
        // a longer run of digits is clamped (still a mode, with an index no model writes).
        column.component = rest.size() > 9 ? 999999999 : std::stoi(std::string(rest));
        return true;
      }
      continue;
    }
    const auto it = std::find(d.suffixes.begin(), d.suffixes.end(), suffix);
    if (it != d.suffixes.end()) {
      column.kind = d.kind;
      column.component = static_cast<int>(it - d.suffixes.begin());
      return true;
    }
  }
  return false;
}

}  // namespace

ColumnOwner owner_of(ColumnKind kind) {
  return kind == ColumnKind::unknown ? ColumnOwner::none : described(kind).owner;
}

const char* unit_of(ColumnKind kind) {
  return kind == ColumnKind::unknown ? "" : described(kind).unit;
}

const char* group_name(ColumnKind kind) {
  return kind == ColumnKind::unknown ? "an unknown column" : described(kind).group;
}

int group_size(ColumnKind kind) {
  if (kind == ColumnKind::unknown) return 1;
  const KindDescription& d = described(kind);
  return d.indexed_prefix.empty() ? static_cast<int>(d.suffixes.size()) : 1;
}

bool is_measured(ColumnKind kind) {
  return kind != ColumnKind::unknown && described(kind).measured;
}

std::string column_name(ColumnKind kind, const std::string& owner, int component,
                        const std::string& point) {
  const KindDescription& d = described(kind);
  if (!d.indexed_prefix.empty()) {
    if (component < 1) throw std::invalid_argument("column_name: modes count from 1");
    return owner + "." + std::string(d.indexed_prefix) + std::to_string(component);
  }
  if (component < 0 || component >= static_cast<int>(d.suffixes.size())) {
    throw std::invalid_argument("column_name: component " + std::to_string(component) +
                                " outside " + d.group);
  }
  const std::string suffix(d.suffixes[static_cast<std::size_t>(component)]);
  switch (d.owner) {
    case ColumnOwner::none:
      return suffix;
    case ColumnOwner::point:
      return owner + "." + point + "." + suffix;
    default:
      return owner + "." + suffix;
  }
}

Column parse_column(const std::string& name) {
  Column column;
  column.name = name;
  const auto dot = name.find('.');
  if (dot == std::string::npos) {
    for (const KindDescription& d : description()) {
      if (d.owner == ColumnOwner::none && d.suffixes.front() == name) column.kind = d.kind;
    }
    return column;
  }
  column.owner = name.substr(0, dot);
  if (dot == 0) return column;
  const std::string_view rest = std::string_view(name).substr(dot + 1);
  const auto dot2 = rest.find('.');
  if (dot2 == std::string_view::npos) {
    match_suffix(rest, false, column);
    return column;
  }
  const std::string_view point = rest.substr(0, dot2);
  if (!point.empty() && match_suffix(rest.substr(dot2 + 1), true, column)) {
    column.point = std::string(point);
  }
  return column;
}

ColumnLayout ColumnLayout::of(const core::Model& model) {
  ColumnLayout layout;
  auto add = [&](ColumnKind kind, const std::string& owner, const std::string& point = {}) {
    const KindDescription& d = described(kind);
    for (int c = 0; c < static_cast<int>(d.suffixes.size()); ++c) {
      layout.columns_.push_back({kind, owner, point, c, column_name(kind, owner, c, point)});
    }
  };
  auto add_modes = [&](ColumnKind kind, const std::string& body, int count) {
    for (int k = 1; k <= count; ++k) {
      layout.columns_.push_back({kind, body, {}, k, column_name(kind, body, k)});
    }
  };
  for_each_column_group(model, [&](const ColumnGroup& g) {
    // The owner's name: a body's, a joint's or a wear channel's (none for t and the energies).
    std::string owner;
    switch (owner_of(g.kind)) {
      case ColumnOwner::body:
      case ColumnOwner::point:
        owner = model.body(g.owner).name();
        break;
      case ColumnOwner::joint:
        owner = model.constraints()->joint_name(g.owner);
        break;
      case ColumnOwner::contact:
        owner = model.wear_channel_names()[static_cast<std::size_t>(g.owner)];
        break;
      case ColumnOwner::none:
        break;
    }
    if (g.kind == ColumnKind::mode || g.kind == ColumnKind::mode_rate ||
        g.kind == ColumnKind::depth) {
      add_modes(g.kind, owner, g.count);
    } else if (g.kind == ColumnKind::point) {
      add(g.kind, owner,
          model.body(g.owner).description().points[static_cast<std::size_t>(g.point)].name);
    } else {
      add(g.kind, owner);
    }
  });
  return layout;
}

ColumnLayout ColumnLayout::parse(const std::vector<std::string>& names) {
  ColumnLayout layout;
  layout.columns_.reserve(names.size());
  for (const std::string& n : names) layout.columns_.push_back(parse_column(n));
  return layout;
}

std::vector<std::string> ColumnLayout::names() const {
  std::vector<std::string> out;
  out.reserve(columns_.size());
  for (const Column& c : columns_) out.push_back(c.name);
  return out;
}

std::vector<std::string> ColumnLayout::units() const {
  std::vector<std::string> out;
  out.reserve(columns_.size());
  for (const Column& c : columns_) out.emplace_back(unit_of(c.kind));
  return out;
}

int ColumnLayout::find(ColumnKind kind, std::string_view owner, int component,
                       std::string_view point) const {
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    const Column& c = columns_[i];
    if (c.kind == kind && c.component == component && c.owner == owner && c.point == point) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

bool ColumnLayout::find_group(ColumnKind kind, std::string_view owner, std::span<int> indices,
                              std::string_view point) const {
  const int n = group_size(kind);
  if (static_cast<int>(indices.size()) != n) {
    throw std::invalid_argument(std::string("find_group: ") + group_name(kind) + " has " +
                                std::to_string(n) + " columns");
  }
  for (int c = 0; c < n; ++c) {
    indices[static_cast<std::size_t>(c)] = find(kind, owner, c, point);
    if (indices[static_cast<std::size_t>(c)] < 0) return false;
  }
  return true;
}

std::vector<std::string> ColumnLayout::owners() const {
  std::vector<std::string> out;
  for (const Column& c : columns_) {
    if (c.kind == ColumnKind::unknown || c.owner.empty()) continue;
    if (std::find(out.begin(), out.end(), c.owner) == out.end()) out.push_back(c.owner);
  }
  return out;
}

std::vector<std::size_t> ColumnLayout::mode_columns(ColumnKind kind, std::string_view body) const {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (columns_[i].kind == kind && columns_[i].owner == body) out.push_back(i);
  }
  return out;
}

}  // namespace flexref::trajectory
