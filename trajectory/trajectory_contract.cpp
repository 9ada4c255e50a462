#include "trajectory/trajectory_contract.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "io/input_file.hpp"
#include "trajectory/column_layout.hpp"

namespace flexref::trajectory {
namespace {

std::string trim(const std::string& s) {
  const auto begin = s.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  const auto end = s.find_last_not_of(" \t\r");
  return s.substr(begin, end - begin + 1);
}

std::vector<std::string> split_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    cells.push_back(trim(line.substr(start, comma == std::string::npos ? comma : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

/// strtod of the whole cell; false when it is not a number (overflow included).
bool parse_number(const std::string& cell, double& value) {
  if (cell.empty()) return false;
  const char* begin = cell.c_str();
  char* end = nullptr;
  errno = 0;
  value = std::strtod(begin, &end);
  if (end == begin || *end != '\0') return false;
  return !(errno == ERANGE && std::isinf(value));  // underflow to a subnormal is a number
}

std::string g17(double x) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

std::string g3(double x) {
  char text[40];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

/// A column of the contract (trajectory/column_layout.hpp): a body's, point's, joint's or
/// named contact's known column (not `t`, not the energy columns).
bool is_standard(const Column& c) { return c.kind != ColumnKind::unknown && !c.owner.empty(); }

core::InputError error_at(const RunData& data, std::size_t row, const std::string& column,
                          const std::string& what) {
  const int line = row < data.lines.size() ? data.lines[row] : 0;
  return core::InputError(data.source, line, column,
                          "row " + std::to_string(row + 1) + ": " + what);
}

/// The value at (row, column), checked: a number and finite.
double checked_value(const RunData& data, std::size_t row, std::size_t column) {
  const double v = data.table.rows[row][column];
  if (std::isfinite(v)) return v;
  const std::string& name = data.table.columns[column];
  for (const auto& bad : data.bad_cells) {
    if (bad.row == row && bad.column == column) {
      throw error_at(data, row, name, "'" + bad.text + "' is not a number");
    }
  }
  throw error_at(data, row, name,
                 "non-finite value " + g17(v) + " (a diverged or corrupt run cannot be measured)");
}

void check_euler_norm(const RunData& data, std::size_t row, const std::vector<std::size_t>& cols,
                      double tolerance) {
  double sq = 0.0;
  for (std::size_t c : cols) {
    const double v = checked_value(data, row, c);
    sq += v * v;
  }
  const double norm = std::sqrt(sq);
  if (!(std::abs(norm - 1.0) <= tolerance)) {
    throw error_at(data, row, data.table.columns[cols[0]],
                   "Euler parameters have norm " + g17(norm) + " (off 1 by " +
                       g3(std::abs(norm - 1.0)) + " > tolerance " + g3(tolerance) +
                       "): they must describe a rotation; normalize them in the integrator");
  }
}

/// Index of the `t` column; throws naming the header line.
std::size_t time_column(const RunData& data) {
  const int t = data.table.column("t");
  if (t < 0) {
    throw core::InputError(
        data.source, data.header_line, "t",
        "no 't' column: every row needs its time (columns: " + join(data.table.columns) + ")");
  }
  return static_cast<std::size_t>(t);
}

/// The measured groups of a table: for each complete group its column indices and whether it is
/// an attitude. Throws for an incomplete group, naming the first missing column.
struct Group {
  std::vector<std::size_t> columns;
  bool euler = false;
};
std::vector<Group> measured_groups(const RunData& data) {
  const ColumnLayout layout = ColumnLayout::parse(data.table.columns);
  std::vector<Group> groups;
  std::set<std::string> done;
  for (std::size_t i = 0; i < layout.size(); ++i) {
    const Column& c = layout[i];
    if (!is_measured(c.kind)) continue;
    if (c.kind == ColumnKind::point) {
      const std::string stem = c.owner + "." + c.point;
      if (!done.insert(stem).second) continue;
      Group g;
      for (int k = 0; k < group_size(c.kind); ++k) {
        const int j = layout.find(c.kind, c.owner, k, c.point);
        if (j < 0) {
          throw core::InputError(
              data.source, data.header_line, column_name(c.kind, c.owner, k, c.point),
              "missing: point " + stem + " is compared as the group " + stem + ".x, .y, .z");
        }
        g.columns.push_back(static_cast<std::size_t>(j));
      }
      groups.push_back(std::move(g));
      continue;
    }
    if (group_size(c.kind) == 1) {  // a mode, a joint's violation, a contact's wear work
      groups.push_back({{i}, false});
      continue;
    }
    if (!done.insert(column_name(c.kind, c.owner, 0)).second) continue;
    Group g;
    g.euler = c.kind == ColumnKind::rotation;
    for (int k = 0; k < group_size(c.kind); ++k) {
      const int j = layout.find(c.kind, c.owner, k);
      if (j < 0) {
        std::string all;
        for (int m = 0; m < group_size(c.kind); ++m) {
          all += (all.empty() ? "" : ", ") + column_name(c.kind, c.owner, m);
        }
        throw core::InputError(data.source, data.header_line, column_name(c.kind, c.owner, k),
                               std::string("missing: ") + group_name(c.kind) + " of " + c.owner +
                                   " are compared as the group " + all);
      }
      g.columns.push_back(static_cast<std::size_t>(j));
    }
    groups.push_back(std::move(g));
  }
  return groups;
}

void check_values(const RunData& data, const std::vector<Group>& groups,
                  const ContractOptions& options) {
  for (std::size_t r = 0; r < data.table.size(); ++r) {
    for (const Group& g : groups) {
      if (g.euler) {
        check_euler_norm(data, r, g.columns, options.euler_norm_tolerance);
      } else {
        for (std::size_t c : g.columns) (void)checked_value(data, r, c);
      }
    }
  }
}

}  // namespace

RunData read_run_csv(const std::string& path) {
  io::InputFile in(path, "a trajectory CSV file");
  if (!in.is_open()) throw core::InputError(path, 0, "", in.error());
  RunData data;
  data.source = path;
  std::string line;
  int line_number = 0;
  std::string last_comment;
  int last_comment_line = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++line_number;
    // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first column's name.
    if (line_number == 1 && line.starts_with(kUtf8ByteOrderMark)) {
      line.erase(0, kUtf8ByteOrderMark.size());
    }
    const std::string text = trim(line);
    if (text.empty()) continue;
    if (text[0] == '#') {
      const std::string comment = trim(text.substr(1));
      if (comment.starts_with("cpu_seconds") && trim(comment.substr(11)).starts_with("=")) {
        const std::string value = trim(trim(comment.substr(11)).substr(1));
        double cpu = 0.0;
        if (!parse_number(value, cpu) || !std::isfinite(cpu) || cpu < 0.0) {
          throw core::InputError(path, line_number, "cpu_seconds",
                                 "expected the integration's CPU time in s, a finite number >= "
                                 "0, got '" +
                                     value + "'");
        }
        if (data.reported_cpu_line != 0) {
          throw core::InputError(
              path, line_number, "cpu_seconds",
              "given twice (first on line " + std::to_string(data.reported_cpu_line) + ")");
        }
        data.reported_cpu_seconds = cpu;
        data.reported_cpu_line = line_number;
        continue;
      }
      if (!have_header) {
        last_comment = trim(text.substr(1));
        last_comment_line = line_number;
      }
      continue;
    }
    std::vector<std::string> cells = split_cells(text);
    if (!have_header) {
      // numpy.savetxt writes the header as a comment ("# t,a,b"): a first non-comment line
      // that is all numbers is data, and the comment line before it is the header.
      double unused = 0.0;
      const bool numeric = std::all_of(cells.begin(), cells.end(), [&](const std::string& c) {
        return parse_number(c, unused);
      });
      if (numeric && !last_comment.empty()) {
        data.table.columns = split_cells(last_comment);
        data.header_line = last_comment_line;
      } else {
        data.table.columns = cells;
        data.header_line = line_number;
      }
      have_header = true;
      std::set<std::string> seen;
      for (const std::string& name : data.table.columns) {
        if (name.empty()) {
          throw core::InputError(path, data.header_line, "", "empty column name in the header");
        }
        if (!seen.insert(name).second) {
          throw core::InputError(path, data.header_line, name, "column named twice in the header");
        }
      }
      if (!numeric || last_comment.empty()) continue;
    }
    if (cells.size() != data.table.columns.size()) {
      throw core::InputError(path, line_number, "",
                             "row " + std::to_string(data.table.size() + 1) + ": expected " +
                                 std::to_string(data.table.columns.size()) + " values, found " +
                                 std::to_string(cells.size()));
    }
    std::vector<double> row(cells.size());
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (!parse_number(cells[i], row[i])) {
        row[i] = std::numeric_limits<double>::quiet_NaN();
        data.bad_cells.push_back({data.table.size(), i, cells[i]});
      }
    }
    data.table.rows.push_back(std::move(row));
    data.lines.push_back(line_number);
  }
  if (!have_header) throw core::InputError(path, line_number, "", "empty file, expected a header");
  if (data.table.rows.empty()) throw core::InputError(path, line_number, "", "no data rows");
  return data;
}

RunData run_from_columns(const std::string& source, std::vector<std::string> names,
                         const std::vector<std::vector<double>>& columns) {
  if (names.size() != columns.size()) {
    throw core::InputError(source, 0, "", "column names and columns differ in number");
  }
  RunData data;
  data.source = source;
  data.header_line = 0;
  const std::size_t n = columns.empty() ? 0 : columns[0].size();
  std::set<std::string> seen;
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (!seen.insert(names[c]).second) {
      throw core::InputError(source, 0, names[c], "column given twice");
    }
    if (columns[c].size() != n) {
      throw core::InputError(source, 0, names[c],
                             "has " + std::to_string(columns[c].size()) + " values, '" + names[0] +
                                 "' has " + std::to_string(n));
    }
  }
  if (n == 0) throw core::InputError(source, 0, "", "no rows");
  data.table.columns = std::move(names);
  data.table.rows.assign(n, std::vector<double>(columns.size()));
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) data.table.rows[r][c] = columns[c][r];
    data.lines.push_back(static_cast<int>(r + 1));
  }
  return data;
}

TrajectoryTable checked_reference(const RunData& reference, const ContractOptions& options) {
  const std::size_t t = time_column(reference);
  for (std::size_t r = 0; r < reference.table.size(); ++r) {
    const double time = checked_value(reference, r, t);
    if (r > 0 && !(time > reference.table.rows[r - 1][t])) {
      throw error_at(reference, r, "t",
                     "times must increase (" + g17(time) + " after " +
                         g17(reference.table.rows[r - 1][t]) + ")");
    }
  }
  check_values(reference, measured_groups(reference), options);
  // `t` first, as TrajectoryTable::time expects; the other columns in file order.
  TrajectoryTable table;
  table.columns.push_back("t");
  std::vector<std::size_t> order{t};
  for (std::size_t c = 0; c < reference.table.columns.size(); ++c) {
    if (c == t) continue;
    table.columns.push_back(reference.table.columns[c]);
    order.push_back(c);
  }
  for (const auto& row : reference.table.rows) {
    std::vector<double> out;
    out.reserve(order.size());
    for (std::size_t c : order) out.push_back(row[c]);
    table.rows.push_back(std::move(out));
  }
  return table;
}

ComparisonReport compare_run(const RunData& run, const TrajectoryTable& reference,
                             const ContractOptions& options) {
  if (reference.columns.empty() || reference.columns[0] != "t" || reference.rows.empty()) {
    throw std::invalid_argument("compare_run: the reference needs rows and 't' first");
  }
  const std::size_t t_col = time_column(run);

  // Columns: known ones are compared, unknown ones ignored, names of absent bodies refused.
  const std::vector<std::string> bodies = ColumnLayout::parse(reference.columns).owners();
  std::vector<std::string> ignored;
  for (std::size_t c = 0; c < run.table.columns.size(); ++c) {
    const std::string& name = run.table.columns[c];
    if (c == t_col) continue;
    const Column n = parse_column(name);
    const bool in_reference = reference.column(name) >= 0;
    if (!in_reference && is_standard(n)) {
      if (std::find(bodies.begin(), bodies.end(), n.owner) == bodies.end()) {
        throw core::InputError(run.source, run.header_line, name,
                               "unknown body '" + n.owner +
                                   "' (the reference's bodies and joints: " + join(bodies) + ")");
      }
      throw core::InputError(run.source, run.header_line, name,
                             "body " + n.owner + " has no such " +
                                 (n.point.empty() ? "column" : "point '" + n.point + "'") +
                                 " in the reference");
    }
    if (!in_reference || !is_measured(n.kind)) ignored.push_back(name);
  }
  const std::vector<Group> groups = measured_groups(run);
  if (groups.empty()) {
    throw core::InputError(run.source, run.header_line, "",
                           "no column to measure: the contract's columns are B.x..B.z, "
                           "B.e0..B.e3, B.vx..B.vz, B.W1..B.W3, B.P.x..B.P.z, B.q1.., "
                           "J.fx..J.fz, J.tx..J.tz, J.phi (columns: " +
                               join(run.table.columns) + ")");
  }

  // Rows: each at one of the reference's output times.
  const std::size_t n_ref = reference.size();
  double step = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < n_ref; ++k)
    step = std::min(step, reference.time(k) - reference.time(k - 1));
  if (!std::isfinite(step)) step = std::max(1.0, std::abs(reference.time(0)));
  const double tolerance = options.time_tolerance * step;
  // A clock accumulated as t += h (ContractOptions::run_step): ε t² / h at time t.
  const auto tolerance_at = [&](double t) {
    if (!(options.run_step > 0.0)) return tolerance;
    return std::max(tolerance, std::numeric_limits<double>::epsilon() * t * t / options.run_step);
  };
  std::vector<std::size_t> matched(run.table.size());
  std::map<std::size_t, std::size_t> used;  // reference row -> run row
  double max_offset = 0.0;
  for (std::size_t r = 0; r < run.table.size(); ++r) {
    const double t = checked_value(run, r, t_col);
    std::size_t k = 0;
    {
      const auto it = std::lower_bound(
          reference.rows.begin(), reference.rows.end(), t,
          [](const std::vector<double>& row, double value) { return row[0] < value; });
      k = static_cast<std::size_t>(it - reference.rows.begin());
      if (k == n_ref ||
          (k > 0 && std::abs(reference.time(k - 1) - t) <= std::abs(reference.time(k) - t))) {
        --k;
      }
    }
    const double offset = std::abs(reference.time(k) - t);
    const double allowed = tolerance_at(reference.time(k));
    if (!(offset <= allowed)) {
      const std::string why =
          allowed > tolerance
              ? " = eps t^2/h, the drift of a clock accumulated at the step h = " +
                    g3(options.run_step)
              : " = " + g3(options.time_tolerance) + " x the output step " + g3(step);
      throw error_at(run, r, "t",
                     "t = " + g17(t) + " is not an output time of the reference (nearest " +
                         g17(reference.time(k)) + ", off by " + g3(offset) + " > " + g3(allowed) +
                         why + ")");
    }
    const auto [it, fresh] = used.emplace(k, r);
    if (!fresh) {
      throw error_at(run, r, "t",
                     "t = " + g17(t) + " is the output time " + g17(reference.time(k)) +
                         " again (row " + std::to_string(it->second + 1) + ")");
    }
    matched[r] = k;
    max_offset = std::max(max_offset, offset);
  }
  check_values(run, groups, options);

  // Both sides restricted to the measured columns (in reference order) and the matched rows.
  TrajectoryTable a, b;
  a.columns.push_back("t");
  std::vector<std::size_t> run_cols{t_col}, ref_cols{0};
  for (std::size_t c = 1; c < reference.columns.size(); ++c) {
    const int i = run.table.column(reference.columns[c]);
    if (i < 0 || std::find(ignored.begin(), ignored.end(), reference.columns[c]) != ignored.end()) {
      continue;
    }
    a.columns.push_back(reference.columns[c]);
    run_cols.push_back(static_cast<std::size_t>(i));
    ref_cols.push_back(c);
  }
  b.columns = a.columns;
  // Rows in time order (a run's rows need not be sorted).
  std::vector<std::size_t> order(run.table.size());
  for (std::size_t r = 0; r < order.size(); ++r) order[r] = r;
  std::sort(order.begin(), order.end(),
            [&](std::size_t x, std::size_t y) { return matched[x] < matched[y]; });
  for (std::size_t r : order) {
    std::vector<double> ra, rb;
    for (std::size_t j = 0; j < run_cols.size(); ++j) {
      ra.push_back(run.table.rows[r][run_cols[j]]);
      rb.push_back(reference.rows[matched[r]][ref_cols[j]]);
    }
    ra[0] = rb[0];  // matched within the tolerance: measured at the reference's time
    a.rows.push_back(std::move(ra));
    b.rows.push_back(std::move(rb));
  }
  ComparisonReport report = compare_trajectories(a, b);
  report.ignored_columns = std::move(ignored);
  report.max_time_offset = max_offset;
  return report;
}

}  // namespace flexref::trajectory
