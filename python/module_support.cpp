#include "python/module_support.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "lie/genalpha_parameters.hpp"
#include "lie/method_registry.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/reference_sidecar.hpp"

namespace flexref::python {

core::FlexibleFormulation formulation(const std::string& model) {
  if (model == "coupled") return core::FlexibleFormulation::kCoupled;
  if (model == "lte") return core::FlexibleFormulation::kLte;
  throw std::invalid_argument("model must be 'coupled' or 'lte', not '" + model + "'");
}

trajectory::RunData run_data(const py::handle& run, const std::string& source) {
  if (py::isinstance<PyTrajectory>(run)) {
    const auto& t = run.cast<const PyTrajectory&>();
    std::vector<std::vector<double>> columns(t.table.columns.size());
    for (const auto& row : t.table.rows) {
      for (std::size_t c = 0; c < row.size(); ++c) columns[c].push_back(row[c]);
    }
    return trajectory::run_from_columns(source, t.table.columns, columns);
  }
  if (!py::isinstance<py::dict>(run)) {
    throw py::type_error(
        "a run is a dict of column name -> 1-D array (with 't'), or a "
        "flexref.Trajectory");
  }
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  for (const auto& [key, value] : run.cast<py::dict>()) {
    names.push_back(py::str(key));
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || a.ndim() != 1) {
      throw core::InputError(source, 0, names.back(), "expected a 1-D array of numbers");
    }
    columns.emplace_back(a.data(), a.data() + a.size());
  }
  return trajectory::run_from_columns(source, std::move(names), columns);
}

const PyTrajectory& as_reference(const PyTrajectory& ref) {
  if (!ref.is_reference) {
    throw std::invalid_argument("the second argument must be a reference (flexref.reference)");
  }
  return ref;
}

PyComparison compare(const trajectory::RunData& run, const PyTrajectory& reference,
                     const std::string& metric) {
  const PyTrajectory& ref = as_reference(reference);
  PyComparison out;
  out.report = trajectory::compare_run(run, ref.table);
  out.metric = metric;
  out.measured = trajectory::metric_quantities(out.report, metric);
  out.value = trajectory::metric_value(out.report, metric);
  out.unit = trajectory::metric_unit(metric);
  out.terms = trajectory::metric_terms(out.report, metric);
  if (ref.has_estimate && ref.reference.estimate.metric == metric) {
    const double e = ref.reference.estimate.estimate();
    out.estimated_error = py::float_(e);
    out.certified = py::bool_(trajectory::is_certified(out.value, e));
  }
  return out;
}

std::pair<studies::ReferenceSolver, studies::ReferencePrecision> reference_choice(
    const core::Model& model, const std::string& reference_solver, const std::string& precision,
    double reference_budget) {
  const studies::ReferenceSolver solver = studies::parse_reference_solver(reference_solver);
  if (model.has_flexible_bodies() && solver == studies::ReferenceSolver::kExact) {
    throw std::invalid_argument("a model with flexible bodies has no exact solution");
  }
  if (!(reference_budget >= 0.0)) {
    throw std::invalid_argument("reference_budget must be 0 (no bound) or positive");
  }
  return {solver, studies::parse_reference_precision(precision)};
}

lie::MethodOptions method_options(const std::vector<std::string>& schemes,
                                  const py::object& rho_inf, const py::object& perturbed_start,
                                  const std::map<std::string, double>& options) {
  const bool genalpha = std::find(schemes.begin(), schemes.end(), "genalpha") != schemes.end();
  for (const auto& [name, given] : {std::pair<const char*, const py::object&>{"rho_inf", rho_inf},
                                    {"perturbed_start", perturbed_start}}) {
    if (!given.is_none() && !genalpha) {
      throw std::invalid_argument(std::string(name) +
                                  " applies only to genalpha, which is not among the schemes");
    }
  }
  lie::MethodOptions out;
  if (!rho_inf.is_none()) {
    out.rho_inf = rho_inf.cast<double>();
    (void)lie::GenAlphaParameters::from_rho_inf(out.rho_inf);  // refuses ρ∞ outside [0, 1]
  }
  if (!perturbed_start.is_none()) out.perturbed_start = perturbed_start.cast<bool>();
  out.values.insert(options.begin(), options.end());
  lie::check_method_options(out, schemes);
  return out;
}

}  // namespace flexref::python
