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
    if (model.has_constraints()) model.advance_tracker(t, state, tracker, ws, false);
    // Driving torques of prescribed bodies need the accelerations at the state (loads of the
    // right-limit branch at t, like the energy below).
    std::optional<core::Loads> loads;
    if (prescribed) {
      loads =
          model.compute_accelerations(core::LoadContext{t, t}, state, tracker, ws, accelerations);
    }
    std::vector<double> row;
    row.reserve(table.columns.size());
    row.push_back(t);
    for (int i = 0; i < model.num_bodies(); ++i) {
      const core::BodyState& s = state[static_cast<std::size_t>(i)];
      const Eigen::Vector3d p = model.p_WBo(i, s);
      const Eigen::Vector3d v = model.v_WBo(i, s);
      row.insert(row.end(),
                 {p.x(), p.y(), p.z(), s.theta_WB(0), s.theta_WB(1), s.theta_WB(2), s.theta_WB(3),
                  v.x(), v.y(), v.z(), s.w_WB_B.x(), s.w_WB_B.y(), s.w_WB_B.z()});
      const core::Body& b = model.body(i);
      for (const core::TrackedPoint& pt : b.description().points) {
        const Eigen::Vector3d r = model.p_WP(i, s, pt);
        row.insert(row.end(), {r.x(), r.y(), r.z()});
      }
      for (int m = 0; m < b.mode_count(); ++m) row.push_back(s.q_f(m));
      for (int m = 0; m < b.mode_count(); ++m) row.push_back(s.qd_f(m));
      if (b.is_prescribed()) {
        row.push_back(
            model.driving_torque(i, *loads, accelerations[static_cast<std::size_t>(i)], ws));
      }
    }
    if (model.has_constraints()) {
      // Reactions at the state's accelerations (loads of the right-limit branch at t).
      const std::vector<core::JointReaction> reactions =
          model.joint_reactions(core::LoadContext{t, t}, state, tracker, ws);
      const std::vector<std::array<double, 2>> violations =
          model.constraint_violations(t, state, ws);
      for (std::size_t j = 0; j < reactions.size(); ++j) {
        const core::JointReaction& r = reactions[j];
        row.insert(row.end(), {r.f_W.x(), r.f_W.y(), r.f_W.z(), r.tau_W.x(), r.tau_W.y(),
                               r.tau_W.z(), violations[j][0], violations[j][1]});
      }
    }
    // Energy at an output time: the right-limit branch of piecewise loads (potentials do not
    // depend on time, so the branch only matters for future time-dependent potentials).
    const core::LoadContext context{t, t};
    const double energy = model.kinetic_energy(state) + model.potential_energy(context, state, ws);
    row.push_back(energy);
    const core::IntegralLayout& integrals = model.integral_layout();
    const auto extra = static_cast<std::size_t>(model.extra_integral_count());
    const bool tracked =
        extra > 0 && trajectory.extra_work.size() == extra * trajectory.times.size();
    // Integral i ≥ 1 of integral_layout at output k; NaN when the integrator did not track it.
    const auto integral = [&](int i) {
      return tracked ? trajectory.extra_work[k * extra + static_cast<std::size_t>(i - 1)]
                     : std::numeric_limits<double>::quiet_NaN();
    };
    if (model.tracks_work()) {
      // W_d(t) and the balance E(t) − E(0) + W_d(t) − W_a(t) − W_drive(t) (0 up to the
      // integration error when every joule is accounted for). NaN when the integrator did not
      // track the integrals.
      const double work = trajectory.dissipated_work.size() == trajectory.times.size()
                              ? trajectory.dissipated_work[k]
                              : std::numeric_limits<double>::quiet_NaN();
      if (k == 0) energy0 = energy;
      row.push_back(work);
      const double applied = integrals.applied >= 0 ? integral(integrals.applied) : 0.0;
      if (integrals.applied >= 0) row.push_back(applied);
      const double driven = integrals.drive >= 0 ? integral(integrals.drive) : 0.0;
      if (integrals.drive >= 0) row.push_back(driven);
      row.push_back(energy - energy0 + work - applied - driven);
    }
    const auto channels = static_cast<std::size_t>(model.wear_channel_count());
    if (channels > 0) {
      model.wear_samples(context, state, ws);
      const bool counted = trajectory.impacts.size() == channels * trajectory.times.size();
      for (std::size_t c = 0; c < channels; ++c) {
        row.push_back(ws.wear[c].normal_force);
        row.push_back(ws.wear[c].slip_speed);
        row.push_back(integrals.first_wear >= 0
                          ? integral(integrals.first_wear + static_cast<int>(c))
                          : std::numeric_limits<double>::quiet_NaN());
        row.push_back(counted ? trajectory.impacts[k * channels + c]
                              : std::numeric_limits<double>::quiet_NaN());
        const int channel = static_cast<int>(c);
        const int depths = model.channel_depth_count(channel);
        if (depths == 0) continue;
        // The worn depths of the state: the largest, the volume, each point's or sector's.
        row.push_back(model.wear_depth_max(channel, state));
        row.push_back(model.wear_volume(channel, state));
        const int first = model.channel_depth_first(channel);
        for (int j = first; j < first + depths; ++j) row.push_back(state.wear_depth(j));
      }
    }
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
