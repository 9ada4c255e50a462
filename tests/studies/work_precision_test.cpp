#include "studies/work_precision.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/output_times.hpp"
#include "tests/support/test_problems.hpp"

namespace flexref::studies {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// book_toss (the torque pulse on [0, 0.1) and the start of the flip) over one second, output
// every 0.1 s: every step h0/2^l divides 0.1, and the whole study takes well under a second.
WorkPrecisionOptions small_study(int jobs) {
  WorkPrecisionOptions options;
  options.schemes = {"c1", "c2", "nmb"};
  options.h0 = 1e-2;
  options.levels = 3;
  options.solvers = {"cvode", "ida"};
  options.tolerances = {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  options.repeats = 1;
  options.jobs = jobs;
  return options;
}

const WorkPrecisionResult& study(int jobs) {
  static const core::Model model = testing::book_toss();
  static const std::vector<double> times = core::output_times(1.0, 0.1);
  static const WorkPrecisionResult serial = run_work_precision(model, times, small_study(1));
  static const WorkPrecisionResult parallel = run_work_precision(model, times, small_study(2));
  return jobs == 1 ? serial : parallel;
}

std::vector<double> errors_of(const WorkPrecisionResult& r, const std::string& method) {
  std::vector<double> errors;
  for (const auto& run : r.runs) {
    if (run.method == method) errors.push_back(run.error);
  }
  return errors;
}

WorkPrecisionRun row(std::string method, std::string kind, double setting, double error, double cpu,
                     std::string status = "ok") {
  return {std::move(method), std::move(kind), setting, error, cpu, std::move(status)};
}

TEST_CASE("work-precision has one row per scheme x step and per solver x tolerance") {
  const WorkPrecisionResult& r = study(1);
  REQUIRE(r.runs.size() == 3 * 3 + 2 * 6);
  for (std::size_t s = 0; s < 3; ++s) {
    for (std::size_t l = 0; l < 3; ++l) {
      const WorkPrecisionRun& run = r.runs[3 * s + l];
      CHECK(run.method == small_study(1).schemes[s]);
      CHECK(run.kind == "scheme");
      CHECK(run.setting == 1e-2 / std::ldexp(1.0, static_cast<int>(l)));
    }
  }
  for (std::size_t k = 9; k < r.runs.size(); ++k) {
    CHECK(r.runs[k].kind == "solver");
    CHECK(r.runs[k].setting == small_study(1).tolerances[(k - 9) % 6]);
  }
  for (const auto& run : r.runs) {
    INFO(run.method << " " << run.setting << ": " << run.status);
    CHECK((run.status == "ok" || run.status == "uncertified"));
    CHECK(run.cpu_seconds >= 0.0);
  }
  CHECK(r.cheapest.size() == default_target_errors().size());
}

TEST_CASE("work-precision errors decrease with the step of each scheme") {
  const WorkPrecisionResult& r = study(1);
  for (const std::string scheme : {"c1", "c2", "nmb"}) {
    const std::vector<double> e = errors_of(r, scheme);
    REQUIRE(e.size() == 3);
    for (std::size_t l = 1; l < e.size(); ++l) {
      INFO(scheme << " level " << l << ": " << e[l] << " vs " << e[l - 1]);
      // Halving the step divides the error by 2^p ≥ 2 for the first-order schemes in the
      // asymptotic range; 0.75 leaves room for pre-asymptotic levels.
      CHECK(e[l] < 0.75 * e[l - 1]);
    }
  }
}

TEST_CASE("work-precision errors decrease with the CVODE tolerance, within a factor") {
  const std::vector<double> e = errors_of(study(1), "cvode");
  REQUIRE(e.size() == 6);
  for (std::size_t k = 1; k < e.size(); ++k) {
    INFO("rtol index " << k << ": " << e[k] << " vs " << e[k - 1]);
    // The global error of an adaptive solver is only roughly proportional to its tolerance:
    // a tenfold tighter tolerance may gain less than tenfold, or occasionally lose a little,
    // so each step is allowed a factor 3 of growth ...
    CHECK(e[k] < 3.0 * e[k - 1]);
  }
  // ... while five decades of tolerance must gain at least two decades of error.
  CHECK(e.back() < 1e-2 * e.front());
}

TEST_CASE("work-precision parallel and serial runs give identical errors") {
  const WorkPrecisionResult& serial = study(1);
  const WorkPrecisionResult& parallel = study(2);
  REQUIRE(serial.runs.size() == parallel.runs.size());
  for (std::size_t k = 0; k < serial.runs.size(); ++k) {
    INFO(serial.runs[k].method << " " << serial.runs[k].setting);
    CHECK(serial.runs[k].method == parallel.runs[k].method);
    CHECK(serial.runs[k].setting == parallel.runs[k].setting);
    CHECK(serial.runs[k].error == parallel.runs[k].error);
    CHECK(serial.runs[k].status == parallel.runs[k].status);
  }
}

TEST_CASE("work-precision cheapest method on the study meets its target at minimum cost") {
  const WorkPrecisionResult& r = study(1);
  REQUIRE_FALSE(r.cheapest.empty());
  CHECK(std::any_of(r.cheapest.begin(), r.cheapest.end(), [](const auto& c) { return c.found; }));
  for (const auto& c : r.cheapest) {
    INFO("target " << c.target);
    if (!c.found) {
      for (const auto& run : r.runs) CHECK_FALSE((run.status == "ok" && run.error <= c.target));
      continue;
    }
    CHECK(c.run.error <= c.target);
    CHECK(c.run.status == "ok");
    for (const auto& run : r.runs) {
      if (run.status == "ok" && run.error <= c.target) CHECK(c.run.cpu_seconds <= run.cpu_seconds);
    }
  }
}

TEST_CASE("cheapest_methods picks the cheapest run meeting each target, on synthetic rows") {
  const std::vector<WorkPrecisionRun> runs{
      row("c1", "scheme", 1e-2, 5e-2, 0.001),
      row("c2", "scheme", 1e-2, 3e-3, 0.004),
      row("nmb", "scheme", 1e-2, 8e-3, 0.002),  // cheapest for 1e-2
      row("c2", "scheme", 5e-3, 9e-5, 0.050),
      row("cvode", "solver", 1e-6, 5e-5, 0.020),                    // cheapest for 1e-4
      row("ida", "solver", 1e-8, 2e-7, 0.030),                      // cheapest for 1e-6
      row("odeint", "solver", 1e-12, 1e-9, 0.0001, "uncertified"),  // never eligible
      row("c1", "scheme", 1e-4, kInf, kNaN, "failed: diverged"),    // never eligible
  };
  const std::vector<CheapestMethod> c = cheapest_methods(runs, {1e-2, 1e-4, 1e-6, 1e-8});
  REQUIRE(c.size() == 4);
  REQUIRE(c[0].found);
  CHECK(c[0].run.method == "nmb");
  CHECK(c[0].run.cpu_seconds == 0.002);
  REQUIRE(c[1].found);
  CHECK(c[1].run.method == "cvode");
  REQUIRE(c[2].found);
  CHECK(c[2].run.method == "ida");
  CHECK(c[2].target == 1e-6);
  CHECK_FALSE(c[3].found);  // only the uncertified run goes below 1e-8: none reaches it

  CHECK_FALSE(cheapest_methods({}, {1e-2})[0].found);
  // An error exactly at the target meets it.
  CHECK(cheapest_methods({row("c2", "scheme", 1e-3, 1e-4, 0.1)}, {1e-4})[0].found);
}

TEST_CASE("work-precision table names the cheapest method or says none reaches it") {
  WorkPrecisionResult r;
  r.runs = {row("c2", "scheme", 1e-2, 3e-3, 0.004)};
  r.cheapest = cheapest_methods(r.runs, default_target_errors());
  const std::string table = format_work_precision_table(r);
  CHECK(table.find("none reaches it") != std::string::npos);
  CHECK(table.find("h = 1.00e-02") != std::string::npos);
  const std::string csv = work_precision_csv(r);
  CHECK(csv.rfind("method,kind,setting,error,cpu_seconds,status,evaluations\n", 0) == 0);
  CHECK(csv.find("c2,scheme,0.01") != std::string::npos);
}

TEST_CASE("every reference solver draws a real work-precision curve on free_spin and book_toss") {
  // The solvers' step sequences are set by their tolerances (Odeint and ARKODE no longer by the
  // output grid): from rtol 1e-4 to 1e-12 the cost (right-hand-side evaluations, the
  // machine-independent cost; CPU times are for the benchmarks) rises as the error against the
  // study's certified reference falls (the exact solution on free_spin; CVODE at rtol 1e-13
  // with its estimate on book_toss). Over the certified runs of each solver: from the loosest
  // to the tightest the error falls at least 100× and the cost at least doubles (measured:
  // 1.7e3–1.8e8× and 2.4–11×); between neighbouring tolerances the error may grow at most 3× and
  // the cost fall at most 5% (adaptive controllers are not monotone at loose tolerances: measured
  // −2% for CVODE and ARKODE, and up to 2× error growth on the chaotic book toss). The table
  // names the cheapest reference for each target error down to 1e-6 on both scenes. Short
  // spans keep it fast: free_spin 20 s, book_toss 3 s (the pulse and the first flip).
  struct Case {
    const char* name;
    core::Model model;
    double end_time;
    double output_step;
    double reference_rtol;
  };
  std::vector<Case> cases;
  cases.push_back({"free_spin", testing::free_spin(), 20.0, 0.1, 1e-12});
  cases.push_back({"book_toss", testing::book_toss(), 3.0, 0.01, 1e-13});
  for (const Case& c : cases) {
    WorkPrecisionOptions options;
    options.schemes = {};
    options.solvers = {"cvode", "ida", "arkode", "odeint"};
    options.tolerances = {1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
    options.repeats = 1;
    options.reference_rtol = c.reference_rtol;
    options.jobs = 2;
    const WorkPrecisionResult r =
        run_work_precision(c.model, core::output_times(c.end_time, c.output_step), options);
    for (const std::string& solver : options.solvers) {
      std::vector<const WorkPrecisionRun*> curve;
      for (const auto& run : r.runs) {
        if (run.method == solver && run.status == "ok") curve.push_back(&run);
      }
      CAPTURE(c.name, solver, curve.size());
      REQUIRE(curve.size() >= 4);
      for (std::size_t k = 1; k < curve.size(); ++k) {
        CAPTURE(curve[k]->setting, curve[k]->error, curve[k - 1]->error, curve[k]->evaluations,
                curve[k - 1]->evaluations);
        CHECK(curve[k]->error < 3.0 * curve[k - 1]->error);
        CHECK(static_cast<double>(curve[k]->evaluations) >=
              0.95 * static_cast<double>(curve[k - 1]->evaluations));
      }
      CHECK(curve.back()->error < 1e-2 * curve.front()->error);
      CHECK(curve.back()->evaluations > 2 * curve.front()->evaluations);
    }
    REQUIRE(r.cheapest_references.size() == reference_target_errors().size());
    int targets_checked = 0;
    for (const CheapestMethod& m : r.cheapest_references) {
      if (m.target < 1e-6) continue;
      ++targets_checked;
      CAPTURE(c.name, m.target);
      CHECK(m.found);
      CHECK(m.run.kind == "solver");
    }
    CHECK(targets_checked > 0);
    CHECK(format_work_precision_table(r).find("cheapest reference solver per target error") !=
          std::string::npos);
  }
}

TEST_CASE("work-precision rejects bad options") {
  const core::Model model = testing::free_spin();
  const std::vector<double> times = core::output_times(0.1, 0.1);
  WorkPrecisionOptions options = small_study(1);
  options.repeats = 0;
  CHECK_THROWS_AS(run_work_precision(model, times, options), std::invalid_argument);
  options = small_study(1);
  options.solvers = {"rk4"};
  CHECK_THROWS_AS(run_work_precision(model, times, options), std::invalid_argument);
  options = small_study(1);
  options.tolerances = {1e-3, -1.0};
  CHECK_THROWS_AS(run_work_precision(model, times, options), std::invalid_argument);
}

}  // namespace
}  // namespace flexref::studies
