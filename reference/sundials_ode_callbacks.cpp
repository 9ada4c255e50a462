#include "reference/sundials_ode_callbacks.hpp"

#include <sunmatrix/sunmatrix_dense.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <exception>
#include <span>

namespace flexref::reference::sundials {

void bind_scratch(OdeCallbackData& d) {
  d.scratch = d.form->make_scratch();
  d.tracker = d.form->model().make_constraint_tracker();
  d.scratch.tracker = &d.tracker;
}

void accept_tracker(OdeCallbackData& d, double t, const double* y) {
  const core::Model& model = d.form->model();
  if (!model.has_constraints()) return;
  d.form->unpack(t, y, d.scratch.state);
  model.advance_tracker(t, d.scratch.state, d.tracker, d.scratch.workspace);
  d.rows_chosen = false;
}

void accept_step(OdeCallbackData& d, double t, const double* y) {
  if (!d.rows_chosen) return;
  d.form->unpack(t, y, d.scratch.state);
  d.form->model().advance_tracker(t, d.scratch.state, d.tracker, d.scratch.workspace,
                                  core::TrackerAdvance::kChooseRows);
  d.rows_chosen = false;
}

void accept_output(OdeCallbackData& d, double t, const core::State& state) {
  const core::Model& model = d.form->model();
  if (!model.has_constraints()) return;
  model.advance_tracker(t, state, d.tracker, d.scratch.workspace,
                        output_advance(model.joint_multipliers(d.scratch.workspace)));
}

int ode_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
  auto& d = *static_cast<OdeCallbackData*>(user_data);
  ++d.evaluations;
  try {
    d.form->rhs(core::LoadContext{t, d.t_segment}, data(y), data(ydot), d.scratch);
    const core::Model& model = d.form->model();
    if (model.has_constraints() && model.joint_multipliers(d.scratch.workspace).rows_chosen()) {
      d.rows_chosen = true;
    }
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;  // unrecoverable; the driver rethrows the message
  }
  if (!all_finite(data(ydot), d.form->size())) {
    // Recoverable: a trial step may have reached a singular load (a charge on the wall); the
    // solver retries with a smaller step and gives up with its own message if that does not help.
    d.last_nonfinite_time = t;
    return 1;
  }
  if (d.watch_start != nullptr) {
    if (ode_switching(t, y, d.watch_values.data(), user_data) != 0) return -1;
    for (std::size_t k = 0; k < d.watch_start->size(); ++k) {
      if (((*d.watch_start)[k] > 0.0) != (d.watch_values[k] > 0.0)) d.other_side = true;
    }
  }
  return 0;
}

int ode_switching(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data) {
  auto& d = *static_cast<OdeCallbackData*>(user_data);
  try {
    d.form->unpack(t, data(y), d.scratch.state);
    const core::Model& model = d.form->model();
    model.switching_functions(
        core::LoadContext{t, d.t_segment}, d.scratch.state, d.scratch.workspace,
        std::span<double>(g, static_cast<std::size_t>(model.switching_function_count())));
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;
  }
  return 0;
}

int ode_jacobian(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix jacobian, void* user_data,
                 N_Vector /*tmp1*/, N_Vector /*tmp2*/, N_Vector /*tmp3*/) {
  auto& d = *static_cast<OdeCallbackData*>(user_data);
  const int n = d.form->size();
  try {
    Eigen::Map<Eigen::MatrixXd> j(SUNDenseMatrix_Data(jacobian), n, n);
    d.jacobian->evaluate(*d.form, core::LoadContext{t, d.t_segment}, data(y), data(fy), j,
                         d.scratch);
    if (!all_finite(j.data(), static_cast<long>(n) * n)) {
      d.last_nonfinite_time = t;
      return 1;  // recoverable: the solver retries with a smaller step
    }
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;
  }
  return 0;
}

int structured_ode_jacobian(sunrealtype t, N_Vector y, N_Vector /*fy*/, SUNMatrix jacobian,
                            void* user_data, N_Vector /*tmp1*/, N_Vector /*tmp2*/,
                            N_Vector /*tmp3*/) {
  auto& d = *static_cast<OdeCallbackData*>(user_data);
  const int n = d.form->size();
  try {
    d.structured->evaluate(core::LoadContext{t, d.t_segment}, data(y),
                           SUNDenseMatrix_Data(jacobian),
                           static_cast<int>(SUNDenseMatrix_Rows(jacobian)), d.structured_scratch);
  } catch (...) {
    d.callback_error = std::current_exception();
    return -1;
  }
  if (!all_finite(SUNDenseMatrix_Data(jacobian), static_cast<long>(n) * n)) {
    d.last_nonfinite_time = t;
    return 1;  // recoverable: the solver retries with a smaller step
  }
  return 0;
}

int project_euler_parameters(sunrealtype /*t*/, N_Vector ycur, N_Vector corr,
                             sunrealtype /*eps_proj*/, N_Vector err, void* user_data) {
  const auto& d = *static_cast<const OdeCallbackData*>(user_data);
  N_VConst(0.0, corr);
  const double* y = data(ycur);
  double* c = data(corr);
  double* e = err != nullptr ? data(err) : nullptr;
  for (int offset : d.form->theta_offsets()) {
    const Eigen::Map<const Eigen::Vector4d> theta(y + offset);
    const double norm = theta.norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) return 1;  // recoverable: retry a smaller step
    const Eigen::Vector4d unit = theta / norm;
    Eigen::Map<Eigen::Vector4d>(c + offset) = unit - theta;
    if (e != nullptr) {
      Eigen::Map<Eigen::Vector4d> error(e + offset);
      error -= unit.dot(error) * unit;
    }
  }
  return 0;
}

int project_constraints(sunrealtype t, N_Vector ycur, N_Vector corr, sunrealtype eps_proj,
                        N_Vector err, void* user_data) {
  auto& d = *static_cast<OdeCallbackData*>(user_data);
  const int n = d.form->size();
  const double* y = data(ycur);
  try {
    std::copy(y, y + n, d.projected.begin());
    d.form->project(t, d.projected.data(), d.scratch);
  } catch (...) {
    return 1;  // a trial step far off the manifold (or singular): retry a smaller step
  }
  double* c = data(corr);
  for (int i = 0; i < n; ++i) c[i] = d.projected[static_cast<std::size_t>(i)] - y[i];
  if (!all_finite(c, n)) return 1;
  // The error's θ components tangent to the sphere, as for the Euler parameters alone.
  if (err != nullptr) {
    double* e = data(err);
    for (int offset : d.form->theta_offsets()) {
      const Eigen::Map<const Eigen::Vector4d> theta(d.projected.data() + offset);
      Eigen::Map<Eigen::Vector4d> error(e + offset);
      error -= theta.dot(error) * theta;
    }
  }
  (void)eps_proj;
  return 0;
}

}  // namespace flexref::reference::sundials
