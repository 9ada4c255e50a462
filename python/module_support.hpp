#pragma once
/// \file module_support.hpp
/// What the Python module's bindings (python/flexref_module.cpp) share: the Python-side scene,
/// trajectory and comparison types, and the conversions from Python's arguments to flexref's
/// (docs/external.md, "Python").
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/model.hpp"
#include "core/output_times.hpp"
#include "lie/method_options.hpp"
#include "scene/scene_reader.hpp"
#include "studies/reference_precision.hpp"
#include "studies/reference_solver_name.hpp"
#include "trajectory/certified_reference.hpp"
#include "trajectory/trajectory_contract.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::python {

namespace py = pybind11;

struct PyScene {
  std::shared_ptr<scene::Scene> scene;
  std::vector<double> times() const {
    return core::output_times(scene->end_time, scene->output_step);
  }
};

/// A trajectory as columns; a reference also carries its error estimate.
struct PyTrajectory {
  trajectory::TrajectoryTable table;
  std::string integrator;  ///< scheme or solver
  double setting = 0.0;    ///< step or rtol
  bool has_estimate = false;
  trajectory::CertifiedReference reference;  ///< valid when has_estimate (and for references)
  bool is_reference = false;

  py::array_t<double> column(const std::string& name) const {
    const int c = table.column(name);
    if (c < 0) throw py::key_error("no column '" + name + "'");
    py::array_t<double> out(static_cast<py::ssize_t>(table.size()));
    auto v = out.mutable_unchecked<1>();
    for (std::size_t r = 0; r < table.size(); ++r) {
      v(static_cast<py::ssize_t>(r)) = table.rows[r][static_cast<std::size_t>(c)];
    }
    return out;
  }
};

struct PyComparison {
  trajectory::ComparisonReport report;
  std::string metric;
  double value = 0.0;
  std::vector<std::string> measured;
  std::string unit;   ///< trajectory::metric_unit
  std::string terms;  ///< trajectory::metric_terms
  py::object estimated_error = py::none();
  py::object certified = py::none();
};

/// "coupled" or "lte".
core::FlexibleFormulation formulation(const std::string& model);

/// The run as the contract reads it: a PyTrajectory, or a mapping of column name to 1-D array.
trajectory::RunData run_data(const py::handle& run, const std::string& source);

/// `ref` when it is a reference (flexref.reference), else std::invalid_argument.
const PyTrajectory& as_reference(const PyTrajectory& ref);

/// The run measured against the reference by `metric`, with its estimate where the reference has
/// one for that metric.
PyComparison compare(const trajectory::RunData& run, const PyTrajectory& reference,
                     const std::string& metric);

/// A study's reference solver and precision from Python's strings (the CLI's parsers), checked
/// against the model: no exact solution for flexible bodies, a budget ≥ 0.
std::pair<studies::ReferenceSolver, studies::ReferencePrecision> reference_choice(
    const core::Model& model, const std::string& reference_solver, const std::string& precision,
    double reference_budget);

/// The lie::MethodOptions of a call that runs `schemes`, from its keyword arguments: rho_inf
/// and perturbed_start (genalpha's; None: not given), options (a registered method's own,
/// name -> number). As on the command line, genalpha's options given without genalpha among the
/// schemes, a ρ∞ outside [0, 1] and a name no scheme reads are refused (ValueError).
lie::MethodOptions method_options(const std::vector<std::string>& schemes,
                                  const py::object& rho_inf, const py::object& perturbed_start,
                                  const std::map<std::string, double>& options);

}  // namespace flexref::python
