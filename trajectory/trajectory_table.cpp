#include "trajectory/trajectory_table.hpp"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "io/input_file.hpp"
#include "io/output_file.hpp"
#include "trajectory/column_layout.hpp"
#include "trajectory/column_order.hpp"

namespace flexref::trajectory {

int TrajectoryTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (columns[i] == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<std::string> trajectory_columns(const core::Model& model) {
  return ColumnLayout::of(model).names();
}

std::vector<std::string> trajectory_units(const core::Model& model) {
  return ColumnLayout::of(model).units();
}

TrajectoryTable tabulate(const core::Model& model, const core::Trajectory& trajectory) {
  if (trajectory.states.size() != trajectory.times.size()) {
    throw std::invalid_argument("tabulate: " + std::to_string(trajectory.states.size()) +
                                " states for " + std::to_string(trajectory.times.size()) +
                                " output times");
  }
  TrajectoryTable table;
  table.columns = trajectory_columns(model);
  core::Workspace ws = model.make_workspace();
  core::Accelerations accelerations = model.make_accelerations();
  // The joints' rows follow the outputs as an integrator's follow its steps (chosen again where
  // they become ill-conditioned; outputs come at any spacing, so no orientation test).
  core::ConstraintTracker tracker = model.make_constraint_tracker();
  bool prescribed = false;
  for (const core::Body& b : model.bodies()) prescribed = prescribed || b.is_prescribed();
  table.rows.reserve(trajectory.times.size());
  double energy0 = 0.0;
  for (std::size_t k = 0; k < trajectory.times.size(); ++k) {
    const double t = trajectory.times[k];
    const core::State& state = trajectory.states[k];
    if (model.has_constraints()) {
      model.advance_tracker(t, state, tracker, ws, core::TrackerAdvance::kWithoutOrientation);
    }
    // Driving torques of prescribed bodies need the accelerations at the state (loads of the
    // right-limit branch at t, like the energy below).
    std::optional<core::Loads> loads;
    if (prescribed) {
      loads =
          model.compute_accelerations(core::LoadContext{t, t}, state, tracker, ws, accelerations);
    }
    // Energy at an output time: the right-limit branch of piecewise loads (potentials do not
    // depend on time, so the branch only matters for future time-dependent potentials).
    const core::LoadContext context{t, t};
    const core::IntegralLayout& integrals = model.integral_layout();
    const auto extra = static_cast<std::size_t>(model.extra_integral_count());
    const bool tracked =
        extra > 0 && trajectory.extra_work.size() == extra * trajectory.times.size();
    // Integral i ≥ 1 of integral_layout at output k; NaN when the integrator did not track it.
    const auto integral = [&](int i) {
      return tracked ? trajectory.extra_work[k * extra + static_cast<std::size_t>(i - 1)]
                     : std::numeric_limits<double>::quiet_NaN();
    };
    // W_d(t); NaN when the integrator did not track the integrals.
    const double work = trajectory.dissipated_work.size() == trajectory.times.size()
                            ? trajectory.dissipated_work[k]
                            : std::numeric_limits<double>::quiet_NaN();
    const double applied = integrals.applied >= 0 ? integral(integrals.applied) : 0.0;
    const double driven = integrals.drive >= 0 ? integral(integrals.drive) : 0.0;
    const auto channels = static_cast<std::size_t>(model.wear_channel_count());
    const bool counted = trajectory.impacts.size() == channels * trajectory.times.size();
    // What several groups share, evaluated where the first of them is written (the order of
    // the evaluations on ws as the columns').
    std::vector<core::JointReaction> reactions;
    std::vector<std::array<double, 2>> violations;
    double energy = 0.0;
    bool wear_sampled = false;
    std::vector<double> row;
    row.reserve(table.columns.size());
    const auto push3 = [&row](const Eigen::Vector3d& v) {
      row.insert(row.end(), {v.x(), v.y(), v.z()});
    };
    for_each_column_group(model, [&](const ColumnGroup& g) {
      const auto owner = static_cast<std::size_t>(g.owner);
      switch (g.kind) {
        case ColumnKind::time:
          row.push_back(t);
          break;
        case ColumnKind::position:
          push3(model.p_WBo(g.owner, state[owner]));
          break;
        case ColumnKind::rotation:
          row.insert(row.end(), state[owner].theta_WB.data(), state[owner].theta_WB.data() + 4);
          break;
        case ColumnKind::velocity:
          push3(model.v_WBo(g.owner, state[owner]));
          break;
        case ColumnKind::angular_velocity:
          push3(state[owner].w_WB_B);
          break;
        case ColumnKind::point:
          push3(model.p_WP(
              g.owner, state[owner],
              model.body(g.owner).description().points[static_cast<std::size_t>(g.point)]));
          break;
        case ColumnKind::mode:
          row.insert(row.end(), state[owner].q_f.data(), state[owner].q_f.data() + g.count);
          break;
        case ColumnKind::mode_rate:
          row.insert(row.end(), state[owner].qd_f.data(), state[owner].qd_f.data() + g.count);
          break;
        case ColumnKind::drive_torque:
          row.push_back(model.driving_torque(g.owner, *loads, accelerations[owner], ws));
          break;
        case ColumnKind::reaction_force:
          if (reactions.empty()) {
            // Reactions at the state's accelerations (loads of the right-limit branch at t).
            reactions = model.joint_reactions(core::LoadContext{t, t}, state, tracker, ws);
            violations = model.constraint_violations(t, state, ws);
          }
          push3(reactions[owner].f_W);
          break;
        case ColumnKind::reaction_torque:
          push3(reactions[owner].tau_W);
          break;
        case ColumnKind::violation:
          row.push_back(violations[owner][0]);
          break;
        case ColumnKind::violation_rate:
          row.push_back(violations[owner][1]);
          break;
        case ColumnKind::energy:
          energy = model.kinetic_energy(state) + model.potential_energy(context, state, ws);
          if (k == 0) energy0 = energy;
          row.push_back(energy);
          break;
        case ColumnKind::dissipated_work:
          row.push_back(work);
          break;
        case ColumnKind::applied_work:
          row.push_back(applied);
          break;
        case ColumnKind::drive_work:
          row.push_back(driven);
          break;
        case ColumnKind::energy_balance:
          // E(t) − E(0) + W_d(t) − W_a(t) − W_drive(t) (0 up to the integration error when every
          // joule is accounted for).
          row.push_back(energy - energy0 + work - applied - driven);
          break;
        case ColumnKind::normal_force:
          if (!wear_sampled) {
            model.wear_samples(context, state, ws);
            wear_sampled = true;
          }
          row.push_back(ws.wear[owner].normal_force);
          break;
        case ColumnKind::slip_speed:
          row.push_back(ws.wear[owner].slip_speed);
          break;
        case ColumnKind::wear_work:
          row.push_back(integrals.first_wear >= 0 ? integral(integrals.first_wear + g.owner)
                                                  : std::numeric_limits<double>::quiet_NaN());
          break;
        case ColumnKind::impacts:
          row.push_back(counted ? trajectory.impacts[k * channels + owner]
                                : std::numeric_limits<double>::quiet_NaN());
          break;
        case ColumnKind::wear_depth:
          // The worn depths of the state: the largest, the volume, each point's or sector's.
          row.push_back(model.wear_depth_max(g.owner, state));
          break;
        case ColumnKind::wear_volume:
          row.push_back(model.wear_volume(g.owner, state));
          break;
        case ColumnKind::depth: {
          const int first = model.channel_depth_first(g.owner);
          for (int j = first; j < first + g.count; ++j) row.push_back(state.wear_depth(j));
          break;
        }
        case ColumnKind::unknown:
          break;
      }
    });
    table.rows.push_back(std::move(row));
  }
  return table;
}

void write_csv(const TrajectoryTable& table, const std::string& path) {
  std::ostringstream out;
  out.precision(17);
  for (std::size_t i = 0; i < table.columns.size(); ++i) {
    out << (i ? "," : "") << table.columns[i];
  }
  out << '\n';
  for (const auto& row : table.rows) {
    for (std::size_t i = 0; i < row.size(); ++i) out << (i ? "," : "") << row[i];
    out << '\n';
  }
  io::write_output_file(path, out.str());
}

std::string csv_text(std::string text) {
  for (char& c : text) {
    if (c == ',') c = ';';
    if (c == '"') c = '\'';
    if (c == '\n' || c == '\r') c = ' ';
  }
  return text;
}

std::string csv_number(double x) {
  if (std::isnan(x)) return {};
  char text[32];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(text, sizeof text, "%.*g", precision, x);
    if (std::strtod(text, nullptr) == x) break;
  }
  return text;
}

TrajectoryTable read_csv(const std::string& path) {
  io::InputFile in(path, "a trajectory CSV file");
  if (!in.is_open()) throw core::InputError(path, 0, "", in.error());
  TrajectoryTable table;
  std::string line;
  int line_number = 0;
  auto split = [](const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(item);
    if (!s.empty() && s.back() == ',') out.emplace_back();
    return out;
  };
  if (!std::getline(in, line)) throw core::InputError(path, 1, "", "empty file, expected a header");
  ++line_number;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  table.columns = split(line);
  if (table.columns.empty() || table.columns[0] != "t") {
    throw core::InputError(path, 1, "t", "the first column must be 't'");
  }
  // Every column one of a trajectory's (trajectory/column_layout.hpp): a table this reads was
  // written by write_csv.
  const ColumnLayout layout = ColumnLayout::parse(table.columns);
  for (const Column& c : layout.columns()) {
    if (c.kind != ColumnKind::unknown) continue;
    throw core::InputError(path, 1, c.name,
                           "not a trajectory column (docs/output.md: t, B.x .. B.W3, B.P.x, "
                           "B.q1, B.qd1, B.drive_torque, J.fx .. J.phi_dot, energy, "
                           "dissipated_work, applied_work, energy_balance, C.fn .. C.impacts)");
  }
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const auto cells = split(line);
    if (cells.size() != table.columns.size()) {
      throw core::InputError(path, line_number, "",
                             "expected " + std::to_string(table.columns.size()) +
                                 " values, found " + std::to_string(cells.size()));
    }
    std::vector<double> row(cells.size());
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const char* begin = cells[i].c_str();
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(begin, &end);
      if (end == begin || *end != '\0' || errno == ERANGE) {
        throw core::InputError(path, line_number, table.columns[i],
                               "'" + cells[i] + "' is not a number");
      }
      row[i] = v;
    }
    if (!table.rows.empty() && !(row[0] > table.rows.back()[0])) {
      throw core::InputError(path, line_number, "t", "times must increase");
    }
    table.rows.push_back(std::move(row));
  }
  if (table.rows.empty()) throw core::InputError(path, line_number, "", "no data rows");
  return table;
}

}  // namespace flexref::trajectory
