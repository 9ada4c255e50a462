/// The trajectory contract (docs/external.md): files of other codes are measured by column
/// name, in any column order, with comments, spaces, extra columns and a subset of the output
/// times, giving the same error values as flexref's own file; everything that could fool the
/// measurement is refused naming the file, row (line) and column.
#include "trajectory/trajectory_contract.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/test_problems.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::trajectory {
namespace {

using Catch::Matchers::Contains;

/// `name` in this program's folder for the contract's files (removed at exit).
std::string contract_temp_path(const std::string& name) {
  static const testing::TempDir dir("trajectory-contract");
  return (dir / name).string();
}

/// A run (C2, h = 1e-2) and a reference (C2, h = 1e-3) of the Coulomb wall on [0, 2], output
/// every 0.1 s: translation, rotation and a tracked point all carry an error.
struct Fixture {
  core::Model model = testing::coulomb_wall();
  std::vector<double> times = core::output_times(2.0, 0.1);
  TrajectoryTable run, reference;
  Fixture() {
    auto run_with = [&](double h) {
      const auto stepper = lie::make_stepper("c2", model, {});
      return tabulate(model, lie::run_scheme(model, *stepper, h, times));
    };
    run = run_with(1e-2);
    reference = run_with(1e-3);
  }
};

/// Writes the table's columns `names` (in that order) for the rows where keep(row) holds,
/// through `format` of each value; `prefix` lines go first.
std::string write_variant(const std::string& file, const TrajectoryTable& table,
                          const std::vector<std::string>& names,
                          const std::function<bool(std::size_t)>& keep,
                          const std::string& separator = ",", const std::string& prefix = "",
                          const std::string& line_end = "\n") {
  std::ostringstream out;
  out.precision(17);
  out << prefix;
  for (std::size_t i = 0; i < names.size(); ++i) out << (i ? separator : "") << names[i];
  out << line_end;
  for (std::size_t r = 0; r < table.size(); ++r) {
    if (!keep(r)) continue;
    for (std::size_t i = 0; i < names.size(); ++i) {
      out << (i ? separator : "");
      const int c = table.column(names[i]);
      if (c < 0) {
        out << "own" << r;  // a column of the writer's own: text, never parsed
      } else {
        out << table.rows[r][static_cast<std::size_t>(c)];
      }
    }
    out << line_end;
  }
  const std::string path = contract_temp_path(file);
  std::ofstream(path) << out.str();
  return path;
}

const QuantityError& quantity(const ComparisonReport& report, const std::string& name) {
  for (const auto& q : report.quantities) {
    if (q.name == name) return q;
  }
  FAIL("no quantity " << name);
  return report.quantities.front();
}

TEST_CASE("contract: any column order, subsets, extra columns, comments, spaces, subsets of rows",
          "[studies][contract]") {
  Fixture f;
  const ComparisonReport full = compare_trajectories(f.run, f.reference);
  const auto all = [](std::size_t) { return true; };
  const std::string b = f.run.columns[1].substr(0, f.run.columns[1].find('.'));

  SECTION("flexref's own file read under the contract gives the same report") {
    const std::string path = contract_temp_path("own.csv");
    write_csv(f.run, path);
    const ComparisonReport r = compare_run(read_run_csv(path), f.reference);
    REQUIRE(r.quantities.size() == full.quantities.size());
    for (std::size_t i = 0; i < r.quantities.size(); ++i) {
      CHECK(r.quantities[i].name == full.quantities[i].name);
      // 17 significant digits round-trip a double exactly: identical norms.
      CHECK(r.quantities[i].norms.linf == full.quantities[i].norms.linf);
      CHECK(r.quantities[i].norms.rms == full.quantities[i].norms.rms);
    }
    CHECK(r.ignored_columns == std::vector<std::string>{"energy"});
    CHECK(metric_value(r, "rotation+points") == metric_value(full, "rotation+points"));
    std::filesystem::remove(path);
  }
  SECTION("shuffled columns, spaces, comment lines, CRLF and an extra column of text") {
    std::vector<std::string> names = f.run.columns;
    std::reverse(names.begin(), names.end());
    names.insert(names.begin() + 3, "iterations");
    const std::string path =
        write_variant("shuffled.csv", f.run, names, all, " , ",
                      "# written by another code\n  # indented comment\n\n", "\r\n");
    const ComparisonReport r = compare_run(read_run_csv(path), f.reference);
    REQUIRE_FALSE(full.quantities.empty());
    for (const auto& q : full.quantities) CHECK(quantity(r, q.name).norms.linf == q.norms.linf);
    CHECK(std::find(r.ignored_columns.begin(), r.ignored_columns.end(), "iterations") !=
          r.ignored_columns.end());
    std::filesystem::remove(path);
  }
  SECTION("a subset of columns: t, Euler parameters and angular velocity only") {
    const std::vector<std::string> names{b + ".W2", b + ".e3", "t",       b + ".e0",
                                         b + ".W1", b + ".e1", b + ".e2", b + ".W3"};
    const std::string path = write_variant("subset.csv", f.run, names, all);
    const ComparisonReport r = compare_run(read_run_csv(path), f.reference);
    REQUIRE(r.quantities.size() == 2);
    CHECK(quantity(r, b + ".rotation").norms.linf == quantity(full, b + ".rotation").norms.linf);
    CHECK(quantity(r, b + ".angular_velocity").norms.rms ==
          quantity(full, b + ".angular_velocity").norms.rms);
    // The default metric measures what is there, and says so; a metric with nothing to
    // measure is an error, never 0.
    CHECK(metric_value(r, "rotation+points") == full.max_rotation_linf);
    CHECK(metric_quantities(r, "rotation+points") == std::vector<std::string>{b + ".rotation"});
    CHECK_THROWS_WITH(metric_value(r, "points"), Contains("nothing to measure"));
    CHECK_THROWS_WITH(metric_value(r, "position"), Contains("nothing to measure"));
    std::filesystem::remove(path);
  }
  SECTION("every other output time, with the row of the largest error and the last one") {
    const QuantityError& rot = quantity(full, b + ".rotation");
    const std::size_t worst = static_cast<std::size_t>(std::lround(rot.linf_time / 0.1));
    const std::size_t last = f.run.size() - 1;
    const std::string path = write_variant("rows.csv", f.run, f.run.columns, [&](std::size_t r) {
      return r % 2 == 0 || r == worst || r == last;
    });
    const ComparisonReport r = compare_run(read_run_csv(path), f.reference);
    CHECK(r.rows < f.run.size());
    CHECK(quantity(r, b + ".rotation").norms.linf == rot.norms.linf);
    CHECK(quantity(r, b + ".rotation").norms.final == rot.norms.final);
    std::filesystem::remove(path);
  }
  SECTION("times off by 1e-9 (within 1e-6 x the output step) match, and the offset is reported") {
    TrajectoryTable shifted = f.run;
    for (auto& row : shifted.rows) row[0] += 1e-9;
    const std::string path = write_variant("shifted.csv", shifted, shifted.columns, all);
    const ComparisonReport r = compare_run(read_run_csv(path), f.reference);
    CHECK(r.max_time_offset == Approx(1e-9).epsilon(1e-3));
    CHECK(quantity(r, b + ".rotation").norms.linf == quantity(full, b + ".rotation").norms.linf);
    std::filesystem::remove(path);
  }
  SECTION("a numpy.savetxt file: the header is the comment line before the data") {
    std::ostringstream text;
    text.precision(17);
    text << "# t," << b << ".e0," << b << ".e1," << b << ".e2," << b << ".e3\n";
    for (const auto& row : f.run.rows) {
      text << row[0];
      for (const char* s : {".e0", ".e1", ".e2", ".e3"}) {
        text << ',' << row[static_cast<std::size_t>(f.run.column(b + s))];
      }
      text << '\n';
    }
    const std::string path = contract_temp_path("savetxt.csv");
    std::ofstream(path) << text.str();
    const ComparisonReport r = compare_run(read_run_csv(path), f.reference);
    CHECK(metric_value(r, "rotation") == full.max_rotation_linf);
    std::filesystem::remove(path);
  }
}

/// Requires compare_run (or the reader) to throw an InputError at `line`, column `key`, whose
/// message contains `fragment` and the file name.
void require_refused(const std::string& path, const TrajectoryTable& reference, int line,
                     const std::string& key, const std::string& fragment) {
  try {
    (void)compare_run(read_run_csv(path), reference);
  } catch (const core::InputError& e) {
    INFO(e.what());
    CHECK(e.file() == path);
    CHECK(e.line() == line);
    CHECK(e.key() == key);
    CHECK_THAT(std::string(e.what()), Contains(fragment));
    std::filesystem::remove(path);
    return;
  }
  std::filesystem::remove(path);
  FAIL("accepted " << path);
}

TEST_CASE("contract: what could fool the measurement is refused naming row and column",
          "[studies][contract]") {
  Fixture f;
  const auto all = [](std::size_t) { return true; };
  const std::string b = f.run.columns[1].substr(0, f.run.columns[1].find('.'));
  const std::size_t e0 = static_cast<std::size_t>(f.run.column(b + ".e0"));

  SECTION("a NaN in a measured column (row 27 is line 28)") {
    TrajectoryTable bad = f.run;
    bad.rows[19][static_cast<std::size_t>(f.run.column(b + ".W2"))] = std::nan("");
    require_refused(write_variant("nan.csv", bad, bad.columns, all), f.reference, 21, b + ".W2",
                    "row 20: non-finite value nan");
  }
  SECTION("text in a measured column") {
    const std::string path = write_variant("text.csv", f.run, f.run.columns, all);
    std::ifstream in(path);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    const auto line3 = text.find('\n', text.find('\n') + 1) + 1;
    const auto comma = text.find(',', line3);
    text.replace(line3, comma - line3, "zero");  // t of row 2
    std::ofstream(path) << text;
    require_refused(path, f.reference, 3, "t", "'zero' is not a number");
  }
  SECTION("no t column") {
    std::vector<std::string> names(f.run.columns.begin() + 1, f.run.columns.end());
    require_refused(write_variant("no_t.csv", f.run, names, all), f.reference, 1, "t",
                    "no 't' column");
  }
  SECTION("a body the reference does not have") {
    std::vector<std::string> names = f.run.columns;
    names.push_back("plate.e0");
    require_refused(write_variant("body.csv", f.run, names, all), f.reference, 1, "plate.e0",
                    "unknown body 'plate'");
  }
  SECTION("a point the reference does not have") {
    std::vector<std::string> names = f.run.columns;
    names.push_back(b + ".handle.x");
    require_refused(write_variant("point.csv", f.run, names, all), f.reference, 1, b + ".handle.x",
                    "no such point 'handle'");
  }
  SECTION("an incomplete group of columns") {
    std::vector<std::string> names = f.run.columns;
    names.erase(std::find(names.begin(), names.end(), b + ".e2"));
    require_refused(write_variant("partial.csv", f.run, names, all), f.reference, 1, b + ".e2",
                    "missing: Euler parameters");
  }
  SECTION("a time off the reference's grid") {
    TrajectoryTable bad = f.run;
    bad.rows[5][0] += 1e-4;  // 1e-3 of the output step, above the 1e-6 tolerance
    require_refused(write_variant("off.csv", bad, bad.columns, all), f.reference, 7, "t",
                    "is not an output time of the reference (nearest 0.5");
  }
  SECTION("two rows at one output time") {
    TrajectoryTable bad = f.run;
    bad.rows[6][0] = bad.rows[5][0] + 1e-9;
    require_refused(write_variant("dup.csv", bad, bad.columns, all), f.reference, 8, "t",
                    "again (row 6)");
  }
  SECTION("all-zero Euler parameters (a missing attitude would otherwise score 0)") {
    TrajectoryTable bad = f.run;
    for (auto& row : bad.rows) {
      for (std::size_t k = 0; k < 4; ++k) row[e0 + k] = 0.0;
    }
    require_refused(write_variant("zero.csv", bad, bad.columns, all), f.reference, 2, b + ".e0",
                    "norm 0 ");
  }
  SECTION("Euler parameters scaled by 1.001 are not silently normalized") {
    TrajectoryTable bad = f.run;
    for (std::size_t k = 0; k < 4; ++k) bad.rows[3][e0 + k] *= 1.001;
    require_refused(write_variant("scaled.csv", bad, bad.columns, all), f.reference, 5, b + ".e0",
                    "off 1 by 0.001 > tolerance 1e-06");
  }
  SECTION("a reference with a NaN is refused as well") {
    TrajectoryTable bad = f.reference;
    bad.rows[2][e0 + 1] = std::nan("");
    const std::string path = write_variant("badref.csv", bad, bad.columns, all);
    CHECK_THROWS_WITH(checked_reference(read_run_csv(path)),
                      Contains(path + ":4: key '" + b + ".e1'") && Contains("non-finite"));
    std::filesystem::remove(path);
  }
}

TEST_CASE("contract: arrays in memory name their source and row", "[studies][contract]") {
  Fixture f;
  std::vector<std::vector<double>> columns(2);
  for (std::size_t r = 0; r < f.run.size(); ++r) {
    columns[0].push_back(f.run.time(r));
    columns[1].push_back(r == 4 ? std::nan("") : 1.0);
  }
  const RunData data = run_from_columns("my arrays", {"t", "charged.e0"}, columns);
  CHECK_THROWS_WITH(compare_run(data, f.reference),
                    Contains("missing: Euler parameters of charged"));
  std::vector<std::vector<double>> q(5, columns[0]);
  for (std::size_t r = 0; r < f.run.size(); ++r) {
    for (std::size_t k = 0; k < 4; ++k) {
      q[k + 1][r] = f.run.rows[r][static_cast<std::size_t>(f.run.column("charged.e0")) + k];
    }
  }
  q[2][4] = std::nan("");
  const RunData nan_data = run_from_columns(
      "my arrays", {"t", "charged.e0", "charged.e1", "charged.e2", "charged.e3"}, q);
  CHECK_THROWS_WITH(compare_run(nan_data, f.reference),
                    Contains("my arrays:5: key 'charged.e1': row 5: non-finite"));
}

TEST_CASE("contract: a clock accumulated at the run's step may drift by eps t^2 / h",
          "[studies][contract]") {
  // A reference written every 1e-3 s on [0, 50] (times k·1e-3 exactly), and a run whose clock
  // is t += h with h = 1e-5 over 5e6 steps, written every second: its rounding drift (a few
  // 1e-9 s near t = 50) exceeds the default 1e-6 output steps (1e-9 s) but stays below
  // eps t² / h (5.6e-8 s at t = 50).
  const double h = 1e-5;
  TrajectoryTable reference;
  reference.columns = {"t", "b.W1", "b.W2", "b.W3"};
  for (long k = 0; k <= 50000; ++k) {
    reference.rows.push_back({static_cast<double>(k) * 1e-3, 1.0, 0.0, 0.0});
  }
  std::vector<std::vector<double>> columns(4);
  double t = 0.0;
  double drift = 0.0;
  for (long n = 1; n <= 5'000'000; ++n) {
    t += h;
    if (n % 100'000 == 0) {
      columns[0].push_back(t);
      for (std::size_t c = 1; c < 4; ++c) columns[c].push_back(c == 1 ? 1.0 : 0.0);
      drift = std::max(drift, std::abs(t - static_cast<double>(n) * h));
    }
  }
  REQUIRE(drift > 1e-6 * 1e-3);  // the case this is about: beyond the default tolerance
  const RunData run = run_from_columns("engine", {"t", "b.W1", "b.W2", "b.W3"}, columns);
  CHECK_THROWS_WITH(compare_run(run, reference), Contains("is not an output time"));
  ContractOptions with_step;
  with_step.run_step = h;
  const ComparisonReport report = compare_run(run, reference, with_step);
  // n·h and k·1e-3 are rounded separately: the offsets agree to an ulp of t ≤ 50 (7.1e-15).
  CHECK(report.max_time_offset == Approx(drift).margin(1e-14));
  // A row between two output times (0.4 output steps off) is still refused, the bound named.
  columns[0][10] += 4e-4;
  const RunData off = run_from_columns("engine", {"t", "b.W1", "b.W2", "b.W3"}, columns);
  CHECK_THROWS_WITH(compare_run(off, reference, with_step),
                    Contains("engine:11: key 't': row 11") && Contains("eps t^2/h"));
}

TEST_CASE("contract: a program's CPU report is a comment line, read and checked",
          "[studies][contract]") {
  const std::string path = contract_temp_path("cpu_report.csv");
  std::ofstream(path) << "# written by an engine\n# cpu_seconds = 0.25\nt,b.W1\n0,1\n";
  const RunData data = read_run_csv(path);
  CHECK(data.reported_cpu_seconds == 0.25);
  CHECK(data.reported_cpu_line == 2);
  CHECK(data.table.columns == std::vector<std::string>{"t", "b.W1"});
  // numpy.savetxt's header comment stays the header when the report follows it.
  std::ofstream(path) << "# t,b.W1\n#cpu_seconds=1e-3\n0,1\n";
  const RunData numpy = read_run_csv(path);
  CHECK(numpy.table.columns == std::vector<std::string>{"t", "b.W1"});
  CHECK(numpy.reported_cpu_seconds == 1e-3);
  std::ofstream(path) << "t,b.W1\n0,1\n# cpu_seconds = -1\n";
  CHECK_THROWS_WITH(read_run_csv(path), Contains(":3: key 'cpu_seconds'"));
  std::ofstream(path) << "t,b.W1\n# cpu_seconds = 1\n0,1\n# cpu_seconds = 2\n";
  CHECK_THROWS_WITH(read_run_csv(path), Contains(":4: key 'cpu_seconds': given twice"));
  std::ofstream(path) << "t,b.W1\n0,1\n";
  CHECK(std::isnan(read_run_csv(path).reported_cpu_seconds));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace flexref::trajectory

namespace flexref::trajectory {
namespace {

/// This test's own folder (tests/support/temp_dir.hpp).
using OwnFolder = testing::TempDir;

TEST_CASE("contract: a UTF-8 byte-order mark is skipped, a directory is named as one",
          "[studies][contract]") {
  const OwnFolder folder;
  const std::string csv = (folder.path() / "bom.csv").string();
  std::ofstream(csv) << "\xEF\xBB\xBFt,b.x,b.y,b.z\n0,1,2,3\n0.1,1,2,3\n";
  const RunData data = read_run_csv(csv);
  REQUIRE_FALSE(data.table.columns.empty());
  CHECK(data.table.columns.front() == "t");
  CHECK(data.table.size() == 2);
  CHECK_THROWS_WITH(read_run_csv(folder.path().string()), Contains("is a directory"));
}

TEST_CASE("contract: a joint's reaction and violation columns are measured, phi_dot is not",
          "[studies][contract][joints]") {
  // The reference: joint J's columns (docs/output.md, "Joints") on two output times.
  TrajectoryTable reference;
  reference.columns = {"t", "J.fx", "J.fy", "J.fz", "J.tx", "J.ty", "J.tz", "J.phi", "J.phi_dot"};
  reference.rows = {{0.0, 1, 2, 3, 4, 5, 6, 0.0, 0.0}, {0.1, 1, 2, 3, 4, 5, 6, 0.0, 0.0}};
  // A user's run with the force off by (0, 0, 2) N at t = 0.1, a violation of 1e-6 and its own
  // phi_dot; the torque group is left out (any subset of the groups).
  const RunData run =
      run_from_columns("engine", {"t", "J.fx", "J.fy", "J.fz", "J.phi", "J.phi_dot"},
                       {{0.0, 0.1}, {1, 1}, {2, 2}, {3, 5}, {0.0, 1e-6}, {0.0, 0.5}});
  const ComparisonReport report = compare_run(run, reference);
  // Small integers and their differences are exact in double.
  CHECK(metric_value(report, "reaction_force") == 2.0);
  CHECK(metric_value(report, "violation") == 1e-6);
  CHECK_THROWS_WITH(metric_value(report, "reaction_torque"), Contains("nothing to measure"));
  CHECK(report.ignored_columns == std::vector<std::string>{"J.phi_dot"});
  // An incomplete reaction group is refused naming the missing column.
  const RunData partial =
      run_from_columns("engine", {"t", "J.fx", "J.fy"}, {{0.0, 0.1}, {1, 1}, {2, 2}});
  CHECK_THROWS_WITH(compare_run(partial, reference), Contains("J.fz"));
}

}  // namespace
}  // namespace flexref::trajectory
