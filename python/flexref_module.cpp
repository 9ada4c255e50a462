/// \file flexref_module.cpp
/// The Python module `flexref` (pybind11): verify an integrator written in Python against
/// flexref's references (docs/external.md, "Python").
///
///     scene = flexref.load_scene("scenes/free_spin.toml")
///     ref = flexref.reference(scene, solver="auto", rtol=1e-10)     # with its estimated error
///     ref["body.e0"], ref.times, ref.estimated_error                 # numpy arrays, floats
///     flexref.compare({"t": t, "body.e0": e0, ...}, ref).value        # the contract's metric
///     flexref.convergence(ref, [(h, run), ...]).observed_order        # runs: dicts of arrays
///     flexref.run_scheme(scene, "c2", 1e-3)                          # any registered scheme
///     flexref.run_scheme(scene, "genalpha", 1e-3, rho_inf=0.5)       # with its options
///     flexref.converge(scene, ["c1", "nmb"], dt=1e-2, levels=6)        # the `converge` study
///     flexref.work_precision(scene, ["nmb"], solvers=["cvode"])        # `work-precision`
///
/// flexref's errors become Python exceptions with flexref's messages: flexref.InputError (a
/// ValueError: bad scene, bad arrays — naming the file or "run", row and column) and
/// flexref.SolverError (a RuntimeError: where and why an integrator failed).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/output_times.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/method_options.hpp"
#include "lie/method_registry.hpp"
#include "lie/run_scheme.hpp"
#include "lie/stepper.hpp"
#include "python/module_support.hpp"
#include "reference/solve_reference.hpp"
#include "scene/scene_reader.hpp"
#include "studies/convergence.hpp"
#include "studies/high_precision_references.hpp"
#include "studies/parallel.hpp"
#include "studies/reference_policy.hpp"
#include "studies/reference_solver_name.hpp"
#include "studies/work_precision.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/reference_sidecar.hpp"
#include "trajectory/trajectory_contract.hpp"
#include "trajectory/trajectory_table.hpp"

namespace py = pybind11;
using namespace flexref;
using namespace flexref::python;

PYBIND11_MODULE(flexref, m) {
  m.doc() =
      "flexref: trusted references for rigid and flexible bodies in large rotation, and "
      "the verification of time integrators against them (docs/external.md)";
  m.attr("__version__") = "0.1.0";
  static py::exception<core::InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<core::SolverError> solver_error(m, "SolverError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const core::InputError& e) {
      input_error(e.what());
    } catch (const core::SolverError& e) {
      solver_error(e.what());
    }
  });

  py::class_<PyScene>(m, "Scene", "a scene read from its TOML file")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene->name; })
      .def_property_readonly("file", [](const PyScene& s) { return s.scene->file; })
      .def_property_readonly("end_time", [](const PyScene& s) { return s.scene->end_time; })
      .def_property_readonly("output_step", [](const PyScene& s) { return s.scene->output_step; })
      .def_property_readonly("output_times",
                             [](const PyScene& s) {
                               const auto t = s.times();
                               return py::array_t<double>(static_cast<py::ssize_t>(t.size()),
                                                          t.data());
                             })
      .def_property_readonly("bodies",
                             [](const PyScene& s) {
                               std::vector<std::string> names;
                               for (const auto& b : s.scene->model->bodies()) {
                                 names.push_back(b.name());
                               }
                               return names;
                             })
      .def_property_readonly(
          "columns",
          [](const PyScene& s) { return trajectory::trajectory_columns(*s.scene->model); })
      .def("__repr__", [](const PyScene& s) { return "<flexref.Scene '" + s.scene->name + "'>"; });

  py::class_<PyTrajectory>(m, "Trajectory",
                           "a trajectory as columns (docs/output.md); t['body.e0'] is a numpy "
                           "array")
      .def_property_readonly("columns", [](const PyTrajectory& t) { return t.table.columns; })
      .def_property_readonly("times", [](const PyTrajectory& t) { return t.column("t"); })
      .def("__getitem__", &PyTrajectory::column)
      .def("__contains__",
           [](const PyTrajectory& t, const std::string& c) { return t.table.column(c) >= 0; })
      .def("__len__", [](const PyTrajectory& t) { return t.table.size(); })
      .def("to_dict",
           [](const PyTrajectory& t) {
             py::dict d;
             for (const auto& c : t.table.columns) d[py::str(c)] = t.column(c);
             return d;
           })
      .def_property_readonly("integrator", [](const PyTrajectory& t) { return t.integrator; })
      .def_property_readonly(
          "setting", [](const PyTrajectory& t) { return t.setting; },
          "step (scheme) or relative tolerance (reference)")
      .def_property_readonly(
          "estimated_error",
          [](const PyTrajectory& t) -> py::object {
            if (!t.has_estimate) return py::none();
            return py::float_(t.reference.estimate.estimate());
          },
          "a reference's estimated error in estimate['metric'] (None without an estimate)")
      .def_property_readonly("estimate",
                             [](const PyTrajectory& t) -> py::object {
                               if (!t.has_estimate) return py::none();
                               const auto& e = t.reference.estimate;
                               py::dict d;
                               d["metric"] = e.metric;
                               d["estimate"] = e.estimate();
                               d["method"] = e.method;
                               d["exact"] = e.exact;
                               py::list checks;
                               for (const trajectory::EstimateCheck& c : e.checks) {
                                 py::dict check;
                                 check["role"] = c.role;
                                 check["solver"] = c.solver;
                                 check["method"] = c.method;
                                 check["rtol"] = c.rtol;
                                 check["steps"] = c.steps;
                                 check["distance"] = c.distance;
                                 check["used"] = c.used;
                                 check["note"] = c.note;
                                 checks.append(check);
                               }
                               d["checks"] = checks;
                               return d;
                             })
      .def("__repr__", [](const PyTrajectory& t) {
        return "<flexref.Trajectory " + t.integrator + ", " + std::to_string(t.table.size()) +
               " rows>";
      });

  py::class_<PyComparison>(m, "Comparison", "a run measured against a reference")
      .def_readonly("metric", &PyComparison::metric)
      .def_readonly("value", &PyComparison::value, "the metric's value")
      .def_readonly("measured", &PyComparison::measured, "the quantities the metric used")
      .def_readonly("unit", &PyComparison::unit, "the value's unit: '1' for the default metric")
      .def_readonly("terms", &PyComparison::terms,
                    "what the value is taken from: the default metric's ranges, e.g. 'largest "
                    "of body.rotation / pi rad, body.corner / 2 m'")
      .def_readonly("estimated_error", &PyComparison::estimated_error,
                    "the reference's estimated error in this metric (None if unknown)")
      .def_readonly("certified", &PyComparison::certified,
                    "value >= 100 x estimated_error (None if unknown)")
      .def_property_readonly("rows", [](const PyComparison& c) { return c.report.rows; })
      .def_property_readonly("ignored_columns",
                             [](const PyComparison& c) { return c.report.ignored_columns; })
      .def_property_readonly("quantities", [](const PyComparison& c) {
        py::list out;
        for (const auto& q : c.report.quantities) {
          py::dict d;
          d["name"] = q.name;
          d["kind"] = q.kind;
          d["unit"] = q.unit;
          d["linf"] = q.norms.linf;
          d["rms"] = q.norms.rms;
          d["final"] = q.norms.final;
          d["linf_time"] = q.linf_time;
          out.append(d);
        }
        return out;
      });

  m.def(
      "load_scene",
      [](const std::string& path, const std::string& model) {
        return PyScene{std::make_shared<scene::Scene>(scene::read_scene(path, formulation(model)))};
      },
      py::arg("path"), py::arg("model") = "coupled",
      "Reads a scene file (scenes/README.md); model: flexible bodies' equations, 'coupled' or "
      "'lte'. Raises flexref.InputError naming the file, line and key.");

  m.def(
      "reference",
      [](const PyScene& s, std::string solver, double rtol, py::object atol,
         const std::string& precision, bool estimate, const std::string& metric) {
        if (precision != "double") {
          throw std::invalid_argument("precision '" + precision +
                                      "' is not available yet: only 'double'");
        }
        const core::Model& model = *s.scene->model;
        if (model.has_flexible_bodies() && solver == "exact") {
          throw std::invalid_argument("a model with flexible bodies has no exact solution");
        }
        const std::vector<double> times = s.times();
        solver = trajectory::resolve_reference_solver(solver, model, times);
        reference::SolverOptions options;
        options.rtol = rtol;
        if (!atol.is_none()) options.atol = atol.cast<double>();
        PyTrajectory out;
        out.is_reference = true;
        out.integrator = solver;
        out.setting = rtol;
        {
          py::gil_scoped_release release;
          if (estimate) {
            out.reference = trajectory::certified_reference(model, times, solver, options, metric);
            out.has_estimate = true;
          } else {
            out.reference.run = reference::solve_reference(solver, model, times, options);
            out.reference.table = trajectory::tabulate(model, out.reference.run.trajectory);
          }
        }
        out.table = out.reference.table;
        return out;
      },
      py::arg("scene"), py::arg("solver") = "auto", py::arg("rtol") = 1e-10,
      py::arg("atol") = py::none(), py::arg("precision") = "double", py::arg("estimate") = true,
      py::arg("metric") = trajectory::kDefaultMetric,
      "Computes a reference: solver 'auto' (exact when the scene has an exact solution, else "
      "cvode), 'ida', 'cvode', 'odeint' or 'exact'; with estimate=True its error is estimated "
      "in `metric` (a 100x tighter run and a second solver). precision: only 'double' for now.");

  m.def(
      "run_scheme",
      [](const PyScene& s, const std::string& scheme, double dt, const py::object& rho_inf,
         const py::object& perturbed_start, const std::map<std::string, double>& options) {
        const core::Model& model = *s.scene->model;
        const lie::MethodOptions method =
            method_options({scheme}, rho_inf, perturbed_start, options);
        PyTrajectory out;
        out.integrator = scheme;
        out.setting = dt;
        const std::vector<double> times = s.times();
        py::gil_scoped_release release;
        const auto stepper = lie::make_stepper(scheme, model, method);
        out.table = trajectory::tabulate(model, lie::run_scheme(model, *stepper, dt, times));
        return out;
      },
      py::arg("scene"), py::arg("scheme"), py::arg("dt"), py::kw_only(),
      py::arg("rho_inf") = py::none(), py::arg("perturbed_start") = py::none(),
      py::arg("options") = std::map<std::string, double>{},
      "Integrates the scene with a registered scheme (flexref.schemes()) at the fixed step dt."
      " rho_inf (in [0, 1], default 0.9) and perturbed_start are genalpha's options (only with "
      "genalpha among the schemes); options, a dict of name -> number, a registered method's "
      "own (lie::MethodOptions: a name no scheme reads raises ValueError).");

  m.def(
      "schemes",
      [] {
        std::vector<std::tuple<std::string, int, std::string>> out;
        for (const auto& method : lie::registered_methods()) {
          out.emplace_back(method.name, method.claimed_order, method.description);
        }
        return out;
      },
      "The registered schemes as (name, claimed order, description).");

  m.def(
      "compare",
      [](const py::handle& run, const PyTrajectory& ref, const std::string& metric) {
        return compare(run_data(run, "run"), ref, metric);
      },
      py::arg("run"), py::arg("reference"), py::arg("metric") = trajectory::kDefaultMetric,
      "Measures a run (a dict of column name -> 1-D array with 't', any subset of the standard "
      "columns, rows at any subset of the output times; or a flexref.Trajectory) against a "
      "reference under the trajectory contract (docs/external.md).");

  m.def(
      "convergence",
      [](const PyTrajectory& ref, const py::list& runs, const std::string& metric,
         const std::string& label, int claimed_order) {
        const PyTrajectory& reference = as_reference(ref);
        studies::ConvergenceResult result;
        result.options.metric = metric;
        result.options.schemes = {};
        result.reference = reference.reference;
        std::vector<studies::ConvergenceLevel> levels;
        for (std::size_t i = 0; i < runs.size(); ++i) {
          const auto pair = runs[i].cast<py::tuple>();
          if (pair.size() != 2) throw py::type_error("runs must be (h, run) pairs");
          studies::ConvergenceLevel level;
          level.scheme = label;
          level.h = pair[0].cast<double>();
          if (!(level.h > 0.0)) throw std::invalid_argument("a step h must be positive");
          level.cpu_seconds = std::nan("");
          const trajectory::RunData data =
              run_data(pair[1], "run at h = " + py::repr(pair[0]).cast<std::string>());
          const PyComparison c = compare(data, reference, metric);
          // Steps over the run's own time span (it may cover part of the scene's).
          const int t = data.table.column("t");
          double t_min = INFINITY, t_max = -INFINITY;
          for (const auto& row : data.table.rows) {
            t_min = std::min(t_min, row[static_cast<std::size_t>(t)]);
            t_max = std::max(t_max, row[static_cast<std::size_t>(t)]);
          }
          level.steps = std::lround((t_max - t_min) / level.h);
          level.error = c.value;
          level.status = std::isfinite(level.error) ? "ok" : "failed: non-finite error";
          levels.push_back(level);
        }
        std::sort(levels.begin(), levels.end(),
                  [](const auto& a, const auto& b) { return a.h > b.h; });
        if (levels.size() < 3) {
          throw std::invalid_argument(
              "convergence needs at least three runs (an order is fitted "
              "from three)");
        }
        const double estimate =
            reference.has_estimate && reference.reference.estimate.metric == metric
                ? reference.reference.estimate.estimate()
                : 0.0;
        if (!reference.has_estimate) {
          result.notes.push_back(
              "the reference has no error estimate: no level is checked "
              "against it (use flexref.reference(..., estimate=True))");
        }
        result.summaries.push_back(studies::summarize_levels(label, claimed_order, levels, estimate,
                                                             core::StepLimit{}, result.notes));
        result.levels = levels;
        py::dict out;
        py::list rows;
        for (const auto& lv : result.levels) {
          py::dict d;
          d["h"] = lv.h;
          d["error"] = lv.error;
          d["order"] = lv.order;
          d["status"] = lv.status;
          rows.append(d);
        }
        out["levels"] = rows;
        out["observed_order"] = result.summaries.front().fitted_order;
        out["fitted_levels"] = result.summaries.front().fitted_levels;
        out["notes"] = result.notes;
        out["table"] = studies::format_convergence_table(result);
        return out;
      },
      py::arg("reference"), py::arg("runs"), py::arg("metric") = trajectory::kDefaultMetric,
      py::arg("label") = "mine", py::arg("claimed_order") = 0,
      "Observed order from (h, run) pairs: each run measured against the reference, levels not "
      "100x above its estimated error marked 'uncertified', pairwise orders and the "
      "least-squares order over the certified levels (the `converge` study's analysis). "
      "Returns a dict: levels, observed_order, fitted_levels, notes, table.");

  m.def(
      "converge",
      [](const PyScene& s, const std::vector<std::string>& schemes, double dt, int levels,
         const std::string& metric, const std::string& reference_solver, double reference_rtol,
         const std::string& precision, double reference_budget, int jobs, const py::object& rho_inf,
         const py::object& perturbed_start, const std::map<std::string, double>& method) {
        const core::Model& model = *s.scene->model;
        const auto [solver, wanted] =
            reference_choice(model, reference_solver, precision, reference_budget);
        const std::vector<double> times = s.times();
        studies::ConvergenceOptions options;
        options.schemes = schemes;
        options.method_options = method_options(schemes, rho_inf, perturbed_start, method);
        options.h0 = dt;
        options.levels = levels;
        options.metric = metric;
        options.reference_solver = studies::to_string(solver);
        options.reference_rtol = reference_rtol;
        options.jobs = jobs > 0 ? jobs : studies::default_jobs();
        studies::check_convergence_inputs(model, times, options);
        const studies::StudyReferences references(*s.scene, times, metric, solver, "converge");
        studies::PolicyOutcome<studies::ConvergenceResult> outcome;
        {
          py::gil_scoped_release release;
          outcome = studies::run_convergence_under_policy(model, times, options, wanted,
                                                          reference_budget, references);
        }
        const studies::ConvergenceResult& result = outcome.result;
        py::list rows;
        for (const auto& lv : result.levels) {
          py::dict d;
          d["scheme"] = lv.scheme;
          d["h"] = lv.h;
          d["error"] = lv.error;
          d["order"] = lv.order;
          d["status"] = lv.status;
          rows.append(d);
        }
        py::dict orders;
        for (const auto& summary : result.summaries) {
          orders[py::str(summary.scheme)] = summary.fitted_order;
        }
        py::dict out;
        out["levels"] = rows;
        out["observed_orders"] = orders;
        out["notes"] = result.notes;
        out["table"] = studies::format_convergence_table(result);
        out["reference_precision"] = studies::to_string(outcome.precision_used);
        out["reference_estimate"] = result.reference.estimate.estimate();
        out["reference_refused"] = outcome.refused;
        return out;
      },
      py::arg("scene"), py::arg("schemes") = lie::default_scheme_names(), py::arg("dt") = 1e-2,
      py::arg("levels") = 6, py::arg("metric") = trajectory::kDefaultMetric,
      py::arg("reference_solver") = "auto", py::arg("reference_rtol") = 1e-12,
      py::arg("precision") = "auto", py::arg("reference_budget") = studies::kDefaultReferenceBudget,
      py::arg("jobs") = 0, py::kw_only(), py::arg("rho_inf") = py::none(),
      py::arg("perturbed_start") = py::none(), py::arg("options") = std::map<std::string, double>{},
      "The `converge` study: each scheme at dt, dt/2, ..., dt/2^(levels-1) against a certified "
      "reference, and the observed orders. precision: 'auto' (double; a quad-precision "
      "reference when the double one cannot certify every level and the scene allows it, "
      "within reference_budget seconds, 0: no bound), 'double', 'extended' or 'quad' "
      "(docs/precision.md). rho_inf (in [0, 1], default 0.9) and perturbed_start are "
      "genalpha's options (only with genalpha among the schemes); options, a dict of name -> "
      "number, a registered method's own (lie::MethodOptions: a name no scheme reads raises "
      "ValueError). Returns a dict: levels, observed_orders, notes, table, "
      "reference_precision, reference_estimate, reference_refused.");

  m.def(
      "work_precision",
      [](const PyScene& s, const std::vector<std::string>& schemes, double dt, int levels,
         const std::vector<std::string>& solvers, const std::vector<double>& tolerances,
         int repeats, const std::string& metric, const std::string& reference_solver,
         double reference_rtol, const std::string& precision, double reference_budget, int jobs,
         const py::object& rho_inf, const py::object& perturbed_start,
         const std::map<std::string, double>& method) {
        const core::Model& model = *s.scene->model;
        const auto [solver, wanted] =
            reference_choice(model, reference_solver, precision, reference_budget);
        const std::vector<double> times = s.times();
        studies::WorkPrecisionOptions options;
        options.schemes = schemes;
        options.method_options = method_options(schemes, rho_inf, perturbed_start, method);
        options.h0 = dt;
        options.levels = levels;
        options.solvers = solvers;
        options.tolerances = tolerances;
        options.repeats = repeats;
        options.metric = metric;
        options.reference_solver = studies::to_string(solver);
        options.reference_rtol = reference_rtol;
        options.jobs = jobs > 0 ? jobs : studies::default_jobs();
        studies::check_work_precision_inputs(model, times, options);
        const studies::StudyReferences references(*s.scene, times, metric, solver,
                                                  "work-precision");
        studies::PolicyOutcome<studies::WorkPrecisionResult> outcome;
        {
          py::gil_scoped_release release;
          outcome = studies::run_work_precision_under_policy(model, times, options, wanted,
                                                             reference_budget, references);
        }
        const studies::WorkPrecisionResult& result = outcome.result;
        py::list rows;
        for (const auto& run : result.runs) {
          py::dict d;
          d["method"] = run.method;
          d["kind"] = run.kind;
          d["setting"] = run.setting;
          d["error"] = run.error;
          d["cpu_seconds"] = run.cpu_seconds;
          d["status"] = run.status;
          rows.append(d);
        }
        py::dict out;
        out["runs"] = rows;
        out["notes"] = result.notes;
        out["table"] = studies::format_work_precision_table(result);
        out["reference_precision"] = studies::to_string(outcome.precision_used);
        out["reference_estimate"] = result.reference.estimate.estimate();
        out["reference_refused"] = outcome.refused;
        return out;
      },
      py::arg("scene"), py::arg("schemes") = lie::default_scheme_names(), py::arg("dt") = 1e-2,
      py::arg("levels") = 6,
      py::arg("solvers") = std::vector<std::string>{"ida", "cvode", "arkode", "odeint"},
      py::arg("tolerances") =
          std::vector<double>{1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12},
      py::arg("repeats") = 3, py::arg("metric") = trajectory::kDefaultMetric,
      py::arg("reference_solver") = "auto", py::arg("reference_rtol") = 1e-12,
      py::arg("precision") = "auto", py::arg("reference_budget") = studies::kDefaultReferenceBudget,
      py::arg("jobs") = 0, py::kw_only(), py::arg("rho_inf") = py::none(),
      py::arg("perturbed_start") = py::none(), py::arg("options") = std::map<std::string, double>{},
      "The `work-precision` study: error against CPU time of each scheme level and solver "
      "tolerance, against a certified reference. precision: as flexref.converge's ('auto' "
      "repeats the study against a quad-precision reference when the double one cannot "
      "certify every run). rho_inf, perturbed_start, options: as flexref.converge's. Returns "
      "a dict: runs, notes, table, reference_precision, reference_estimate, reference_refused.");
}
