/// \file precise_comparison_test.cpp
/// `compare` of extended/quad files in their precision (precision/precise_comparison.hpp): a
/// difference far below double's resolution is measured, the files' precision comes from their
/// sidecars, and bad rows are reported with file and line.
#include "precision/precise_comparison.hpp"

#include <boost/multiprecision/float128.hpp>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "precision/high_precision_reference.hpp"
#include "tests/precision/precision_order.hpp"
#include "tests/support/temp_dir.hpp"

namespace flexref::precision {
namespace {

using Quad = boost::multiprecision::float128;

PreciseTable table_of(const HighPrecisionRun& run, Precision p) {
  PreciseTable t;
  t.precision = p;
  t.columns = run.columns;
  for (const auto& row : run.table.rows) t.times.push_back(row.front());
  t.text = run.text;
  return t;
}

std::string quad_text(const Quad& x) {
  std::ostringstream out;
  out << std::setprecision(36) << x;
  return out.str();
}

TEST_CASE("compare measures a quad difference far below double's resolution", "[precision]") {
  scene::SceneSpec spec = spec_of("scenes/book_toss.toml");
  spec.end_time = 0.5;
  const std::vector<double> times = core::output_times(spec.end_time, spec.output_step);
  const HighPrecisionRun run = solve_high_precision(spec, times, Precision::kQuad, 1e-26);
  const PreciseTable reference = table_of(run, Precision::kQuad);
  PreciseTable shifted = reference;
  // Move one tracked point's x by 1e-25 m at one output time (the point's coordinates are
  // ~0.1 m: in double both values round to the same number).
  std::size_t point_x = 0;
  for (std::size_t c = 1; c < run.columns.size(); ++c) {
    if (std::count(run.columns[c].begin(), run.columns[c].end(), '.') == 2 &&
        run.columns[c].ends_with(".x")) {
      point_x = c - 1;
      break;
    }
  }
  REQUIRE(point_x > 0);
  const std::size_t row = 7;
  const Quad moved = Quad(reference.text[row][point_x]) + Quad(1e-25);
  shifted.text[row][point_x] = quad_text(moved);
  REQUIRE(static_cast<double>(moved) == static_cast<double>(Quad(reference.text[row][point_x])));
  const trajectory::ComparisonReport precise = compare_precisely(shifted, reference);
  // 1e-25 to the rounding of the decimal texts (36 digits of ~0.1: 1e-37) and of the double
  // 1e-25 itself in quad (1e-41): 1e-6 relative is loose.
  CHECK(std::abs(precise.max_point_linf - 1e-25) <= 1e-6 * 1e-25);
  INFO("rotation " << std::setprecision(17) << precise.max_rotation_linf << ", point "
                   << precise.max_point_linf);
  CHECK(precise.max_rotation_linf == 0.0);
  // The same files through double: the difference is gone (what compare did before).
  trajectory::TrajectoryTable a = run.table, b = run.table;
  a.rows[row][point_x + 1] = static_cast<double>(moved);
  CHECK(trajectory::compare_trajectories(a, b).max_point_linf == 0.0);
  // Extended against quad, each parsed in its own precision: the same as precision::distance
  // (which parses the same way), to the rounding of the reductions (1e-12 relative is loose).
  const HighPrecisionRun ext = solve_high_precision(spec, times, Precision::kExtended, 1e-16);
  const trajectory::ComparisonReport mixed =
      compare_precisely(table_of(ext, Precision::kExtended), reference);
  for (const char* metric : {"rotation+points", trajectory::kDefaultMetric}) {
    const double value = trajectory::metric_value(mixed, metric);
    const double expected = distance(ext, run, metric);
    INFO(metric << ": compare " << std::setprecision(17) << value << ", distance " << expected);
    CHECK(std::abs(value - expected) <= 1e-12 * expected);
  }
}

TEST_CASE("precise tables take their precision from the sidecar and name bad rows", "[precision]") {
  const testing::TempDir dir("precise-comparison");
  const std::string csv = (dir / "q.csv").string();
  std::ofstream(csv) << "t,b.x\n0,0.1000000000000000000000000000000001\n0.1,0.2\n";
  CHECK(read_precise_table(csv).precision == Precision::kDouble);  // no sidecar
  std::ofstream(csv + ".meta.toml") << "[integrator]\nprecision = \"quad\"\n";
  const PreciseTable t = read_precise_table(csv);
  CHECK(t.precision == Precision::kQuad);
  CHECK(t.text[0][0] == "0.1000000000000000000000000000000001");
  CHECK(t.times == std::vector<double>{0.0, 0.1});
  std::ofstream(csv + ".meta.toml") << "[integrator]\nprecision = \"octuple\"\n";
  CHECK_THROWS_WITH(read_precise_table(csv), Catch::Contains("integrator.precision"));
  std::ofstream(csv + ".meta.toml") << "[integrator]\nprecision = \"quad\"\n";
  std::ofstream(csv) << "t,b.x\n0,0.1\n0.1,0.2,0.3\n";
  try {
    (void)read_precise_table(csv);
    FAIL("a row with three cells for two columns was accepted");
  } catch (const core::InputError& e) {
    CHECK(std::string(e.what()).find(":3") != std::string::npos);
  }
}

}  // namespace
}  // namespace flexref::precision
