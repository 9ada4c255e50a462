/// \file modal_truncation.cpp
/// See modal_truncation.hpp.
#include "studies/modal_truncation.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "core/output_times.hpp"
#include "reference/solve_reference.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/build_model.hpp"
#include "studies/missing_value.hpp"
#include "studies/mpi/distribution.hpp"
#include "trajectory/accuracy_check.hpp"

namespace flexref::studies {
namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("modes: " + what); }

int find_flexible_body(const scene::SceneSpec& spec, int requested) {
  const auto flexible = [&](int i) {
    return spec.bodies[static_cast<std::size_t>(i)].description.flexible.has_value();
  };
  const int count = static_cast<int>(spec.bodies.size());
  if (requested >= 0) {
    if (requested >= count || !flexible(requested)) {
      fail("body " + std::to_string(requested) + " is not a flexible body");
    }
    return requested;
  }
  for (int i = 0; i < count; ++i) {
    if (flexible(i)) return i;
  }
  fail("the scene has no flexible body (a body with [body.beam] or a modal-data file)");
}

/// The named node point, or the node point farthest from Br.
const core::TrackedPoint& find_point(const core::Body& body, const std::string& name) {
  const core::TrackedPoint* best = nullptr;
  double best_distance = -1.0;
  for (const core::TrackedPoint& p : body.description().points) {
    if (!name.empty()) {
      if (p.name != name) continue;
      if (p.node < 0) {
        fail("point '" + name + "' of body '" + body.name() +
             "' is not a node of the flexible part (it does not deform)");
      }
      return p;
    }
    if (p.node < 0) continue;
    const double distance = body.p_BrP_B(p.p_BoP_B).norm();
    if (distance > best_distance) {
      best = &p;
      best_distance = distance;
    }
  }
  if (!name.empty()) fail("body '" + body.name() + "' has no point '" + name + "'");
  if (best == nullptr) {
    fail("body '" + body.name() +
         "' tracks no node point (add one, e.g. { name = \"tip\", node = \"node10\" }): the "
         "metric is a node's deflection");
  }
  return *best;
}

/// The first m entries of v (empty stays empty).
Eigen::VectorXd head_or_empty(const Eigen::VectorXd& v, int m) {
  return v.size() == 0 ? v : Eigen::VectorXd(v.head(m));
}

/// One run: deflections δ(t) (body frame), attitudes, cost.
struct ModalResponse {
  std::vector<Eigen::Vector3d> deflection;
  std::vector<rotation::EulerParameters> attitude;
  long steps = 0;
  double cpu_seconds = 0.0;
};

ModalResponse integrate_modes(const core::Model& model, int body_index,
                              const core::TrackedPoint& point, const std::vector<double>& times,
                              const std::string& solver, double rtol) {
  reference::SolverOptions options;
  options.rtol = rtol;
  const reference::ReferenceRun run = reference::solve_reference(solver, model, times, options);
  const core::Body& body = model.body(body_index);
  const Eigen::Vector3d undeformed = body.p_BrP_B(point, Eigen::VectorXd::Zero(body.mode_count()));
  ModalResponse r;
  for (const core::State& state : run.trajectory.states) {
    const core::BodyState& s = state[static_cast<std::size_t>(body_index)];
    r.deflection.push_back(body.p_BrP_B(point, s.q_f) - undeformed);
    r.attitude.push_back(s.theta_WB);
  }
  r.steps = run.stats.steps;
  r.cpu_seconds = run.stats.cpu_seconds;
  return r;
}

/// A run's response and failure message, for distributed_for (every field: the comparisons
/// after the runs read them on every process).
SlotCodec run_codec(std::vector<ModalResponse>& responses, std::vector<std::string>& failures) {
  require_codec_size<ModalResponse, 64>();
  return {[&responses, &failures](int i, SlotWriter& w) {
            const auto r = static_cast<std::size_t>(i);
            const ModalResponse& out = responses[r];
            w.put(failures[r]);
            w.put(out.steps);
            w.put(out.cpu_seconds);
            w.put(static_cast<long>(out.deflection.size()));
            for (const Eigen::Vector3d& d : out.deflection) {
              for (int c = 0; c < 3; ++c) w.put(d[c]);
            }
            w.put(static_cast<long>(out.attitude.size()));
            for (const rotation::EulerParameters& e : out.attitude) {
              for (int c = 0; c < 4; ++c) w.put(e[c]);
            }
          },
          [&responses, &failures](int i, SlotReader& reader) {
            const auto r = static_cast<std::size_t>(i);
            ModalResponse& out = responses[r];
            reader.get(failures[r]);
            reader.get(out.steps);
            reader.get(out.cpu_seconds);
            out.deflection.assign(static_cast<std::size_t>(reader.get_int()), Eigen::Vector3d());
            for (Eigen::Vector3d& d : out.deflection) {
              for (int c = 0; c < 3; ++c) d[c] = reader.get_double();
            }
            out.attitude.assign(static_cast<std::size_t>(reader.get_int()),
                                rotation::EulerParameters());
            for (rotation::EulerParameters& e : out.attitude) {
              for (int c = 0; c < 4; ++c) e[c] = reader.get_double();
            }
          }};
}

/// The output times with their midpoints inserted: times[i] = fine[2i], bitwise.
double max_deflection_difference(const ModalResponse& a, const ModalResponse& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.deflection.size(); ++i) {
    m = std::max(m, (a.deflection[i] - b.deflection[i]).norm());
  }
  return m;
}

double largest_angle(const ModalResponse& a, const ModalResponse& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.attitude.size(); ++i) {
    m = std::max(m, rotation::geodesic_angle(a.attitude[i], b.attitude[i]));
  }
  return m;
}

/// The integration-error estimates of `run` from its check at a tighter rtol on the same output
/// times: the differences, or +∞ when the check took the run's own number of steps (the same
/// step sequence, not a different solution; docs/references.md "Error estimates"). Both solvers'
/// steps are independent of the output grid (Odeint and the SUNDIALS solvers step past output
/// times and interpolate).
double tip_estimate(const ModalResponse& check, const ModalResponse& run) {
  if (check.steps == run.steps) return std::numeric_limits<double>::infinity();
  return max_deflection_difference(check, run);
}
double attitude_estimate(const ModalResponse& check, const ModalResponse& run) {
  if (check.steps == run.steps) return std::numeric_limits<double>::infinity();
  return largest_angle(check, run);
}

std::string scientific(double x, int digits = 2) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  s << std::scientific << std::setprecision(digits) << x;
  return s.str();
}

}  // namespace

scene::SceneSpec truncate_modes(const scene::SceneSpec& spec, int body, int modes) {
  if (body < 0 || static_cast<std::size_t>(body) >= spec.bodies.size()) {
    fail("no body " + std::to_string(body) + " in the scene");
  }
  if (modes < 1) fail("a mode count must be at least 1, got " + std::to_string(modes));
  scene::SceneSpec out = spec;
  scene::BodySpec& b = out.bodies[static_cast<std::size_t>(body)];
  if (!b.description.flexible) fail("body '" + b.description.name + "' is not flexible");
  core::FlexiblePart& part = *b.description.flexible;
  const int given = part.modal.mode_count();
  const Eigen::VectorXd q0 = part.q0;
  const Eigen::VectorXd qd0 = part.qd0;
  const auto check_initial = [&](const Eigen::VectorXd& v, const char* what) {
    if (modes > given && v.size() != 0 && !v.isZero(0.0)) {
      fail("body '" + b.description.name + "' has " + what + " for " + std::to_string(given) +
           " modes: cannot extend them to " + std::to_string(modes));
    }
  };
  check_initial(q0, "initial modal coordinates");
  check_initial(qd0, "initial modal rates");
  if (b.beam) {
    scene::BeamSpec& beam = *b.beam;
    if (beam.damping_ratio.size() > 1) {
      if (beam.damping_ratio.size() < modes) {
        fail("body '" + b.description.name + "' lists " +
             std::to_string(beam.damping_ratio.size()) + " damping ratios: cannot run " +
             std::to_string(modes) + " modes");
      }
      beam.damping_ratio = Eigen::VectorXd(beam.damping_ratio.head(modes));
    }
    beam.modes = modes;
    try {
      scene::regenerate_beam_modes(b);
    } catch (const std::exception& e) {
      fail("body '" + b.description.name + "': " + std::to_string(modes) + " modes: " + e.what());
    }
  } else {
    if (modes > given) {
      fail("body '" + b.description.name + "' has " + std::to_string(given) +
           " modes in its modal-data file: cannot run " + std::to_string(modes));
    }
    flexible::ModalData& m = part.modal;
    m.phi = Eigen::MatrixXd(m.phi.leftCols(modes));
    m.stiffness = Eigen::VectorXd(m.stiffness.head(modes));
    m.damping_ratio = Eigen::VectorXd(m.damping_ratio.head(modes));
    if (!m.mode_names.empty()) m.mode_names.resize(static_cast<std::size_t>(modes));
  }
  // The first m initial values (zero beyond the scene's, which check_initial allowed).
  const auto truncated = [&](const Eigen::VectorXd& v) {
    if (v.size() == 0 || modes > v.size()) return Eigen::VectorXd();
    return head_or_empty(v, modes);
  };
  part.q0 = truncated(q0);
  part.qd0 = truncated(qd0);
  return out;
}

ModalTruncationResult run_modal_truncation(const scene::SceneSpec& spec,
                                           const ModalTruncationOptions& options) {
  ModalTruncationResult result;
  result.options = options;
  std::vector<int>& counts = result.options.mode_counts;
  std::sort(counts.begin(), counts.end());
  if (counts.size() < 2) fail("need at least two mode counts (the largest is the reference)");
  if (counts.front() < 1) fail("mode counts must be at least 1");
  if (std::adjacent_find(counts.begin(), counts.end()) != counts.end()) {
    fail("mode counts must be distinct");
  }
  if (!(options.rtol > 0.0) || !(options.estimate_factor > 1.0)) {
    fail("need rtol > 0 and an estimate factor > 1");
  }
  trajectory::check_accuracy_check_rtol("modes", options.rtol, options.estimate_factor);
  const int body_index = find_flexible_body(spec, options.body);

  // Every model first (the inputs are checked before any integration).
  std::vector<core::Model> models;
  for (const int m : counts) {
    models.push_back(scene::build_model(truncate_modes(spec, body_index, m), options.formulation));
  }
  const core::Body& reference_body = models.back().body(body_index);
  const core::TrackedPoint point = find_point(reference_body, options.point);
  result.body = reference_body.name();
  result.point = point.name;
  result.reference_modes = counts.back();
  const std::vector<double> times = core::output_times(options.end_time, options.output_step);

  // Runs 2k (the study's) and 2k + 1 (its accuracy check) of count k.
  const int runs = 2 * static_cast<int>(counts.size());
  std::vector<ModalResponse> responses(static_cast<std::size_t>(runs));
  std::vector<std::string> failures(static_cast<std::size_t>(runs));
  ProgressLine progress("modes", "runs", options.progress);
  const auto task = [&](int r) {
    const auto k = static_cast<std::size_t>(r / 2);
    const bool check = r % 2 == 1;
    try {
      ModalResponse& out = responses[static_cast<std::size_t>(r)];
      out = integrate_modes(
          models[k], body_index, point, times, options.solver,
          check ? trajectory::accuracy_check_rtol(options.rtol, options.estimate_factor)
                : options.rtol);
    } catch (const std::exception& e) {
      failures[static_cast<std::size_t>(r)] = e.what();
    }
  };
  distributed_for(runs, options.jobs, task, run_codec(responses, failures), progress.callback());
  progress.finish();

  const std::size_t last = counts.size() - 1;
  const bool reference_ok = failures[2 * last].empty() && failures[2 * last + 1].empty();
  const ModalResponse& ref = responses[2 * last];
  double ref_deflection = 0.0;
  for (const Eigen::Vector3d& d : ref.deflection)
    ref_deflection = std::max(ref_deflection, d.norm());
  if (reference_ok && !(ref_deflection > 0.0)) {
    fail("the tracked point '" + point.name + "' does not deflect in the reference run");
  }
  const double ref_tip_estimate =
      reference_ok ? tip_estimate(responses[2 * last + 1], ref) / ref_deflection : kNaN;
  const double ref_attitude_estimate =
      reference_ok ? attitude_estimate(responses[2 * last + 1], ref) : kNaN;

  int unresolved = 0;
  for (std::size_t k = 0; k < counts.size(); ++k) {
    ModalTruncationRow row;
    row.modes = counts[k];
    const Eigen::VectorXd& omega = models[k].body(body_index).natural_frequencies();
    row.omega_max = omega.size() > 0 ? omega.maxCoeff() : 0.0;
    const std::string& failure = !failures[2 * k].empty() ? failures[2 * k] : failures[2 * k + 1];
    if (!failure.empty() || !reference_ok) {
      row.status = "failed: " + (failure.empty() ? "the reference run failed" : failure);
      row.tip_error = row.tip_error_m = row.attitude_error = kNaN;
      result.rows.push_back(row);
      continue;
    }
    const ModalResponse& tight = responses[2 * k];
    const ModalResponse& check = responses[2 * k + 1];
    for (const Eigen::Vector3d& d : tight.deflection) {
      row.max_deflection = std::max(row.max_deflection, d.norm());
    }
    row.tip_error_m = max_deflection_difference(tight, ref);
    row.tip_error = row.tip_error_m / ref_deflection;
    row.attitude_error = largest_angle(tight, ref);
    row.tip_estimate = tip_estimate(check, tight) / ref_deflection;
    row.attitude_estimate = attitude_estimate(check, tight);
    row.steps = tight.steps;
    row.cpu_seconds = tight.cpu_seconds;
    if (k == last) {
      row.resolved = true;
    } else {
      const double tip_floor = 10.0 * std::max(row.tip_estimate, ref_tip_estimate);
      const double attitude_floor = 10.0 * std::max(row.attitude_estimate, ref_attitude_estimate);
      row.resolved = row.tip_error >= tip_floor && row.attitude_error >= attitude_floor;
      if (!row.resolved) ++unresolved;
    }
    result.rows.push_back(row);
  }
  if (unresolved > 0) {
    result.notes.push_back(std::to_string(unresolved) +
                           " row(s) marked '*' have an error below 10x the estimated integration "
                           "error of the runs compared: the value is an upper bound of the "
                           "truncation error, not a measurement (tighten --rtol)");
  }
  for (const ModalTruncationRow& row : result.rows) {
    if (row.status != "ok") {
      result.notes.push_back(std::to_string(row.modes) + " modes: " + row.status);
    }
  }
  return result;
}

std::string modal_truncation_csv(const ModalTruncationResult& result) {
  std::ostringstream s;
  s.precision(17);
  s << "modes,omega_max,tip_error,tip_error_m,attitude_error,max_deflection,tip_estimate,"
       "attitude_estimate,resolved,steps,cpu_seconds,status\n";
  for (const ModalTruncationRow& r : result.rows) {
    std::string status = r.status;
    std::replace(status.begin(), status.end(), ',', ';');
    std::replace(status.begin(), status.end(), '\n', ' ');
    s << r.modes << ',' << r.omega_max << ',' << r.tip_error << ',' << r.tip_error_m << ','
      << r.attitude_error << ',' << r.max_deflection << ',' << r.tip_estimate << ','
      << r.attitude_estimate << ',' << (r.resolved ? 1 : 0) << ',' << r.steps << ','
      << r.cpu_seconds << ',' << status << '\n';
  }
  return s.str();
}

std::string format_modal_truncation_table(const ModalTruncationResult& result) {
  const ModalTruncationOptions& o = result.options;
  std::ostringstream s;
  s << "body '" << result.body << "', point '" << result.point << "'; reference "
    << result.reference_modes << " modes; " << o.solver << " rtol " << o.rtol
    << " (estimate: against rtol " << trajectory::accuracy_check_rtol(o.rtol, o.estimate_factor)
    << "), " << core::to_string(o.formulation) << " model, " << o.end_time << " s\n";
  s << "errors against the reference, max over the outputs (* = below 10x the integration error "
       "estimate)\n";
  s << std::setw(6) << "modes" << std::setw(14) << "omega_max" << std::setw(13) << "tip error"
    << std::setw(13) << "tip error" << std::setw(13) << "attitude" << std::setw(13) << "max defl."
    << std::setw(13) << "estimate" << std::setw(10) << "steps" << std::setw(10) << "CPU"
    << "\n";
  s << std::setw(6) << "" << std::setw(14) << "[rad/s]" << std::setw(13) << "[rel.]"
    << std::setw(13) << "[m]" << std::setw(13) << "[rad]" << std::setw(13) << "[m]" << std::setw(13)
    << "[rel.]" << std::setw(10) << "" << std::setw(10) << "[s]"
    << "\n";
  for (const ModalTruncationRow& r : result.rows) {
    const bool reference = r.modes == result.reference_modes;
    const std::string mark = r.status == "ok" && !r.resolved ? "*" : "";
    s << std::setw(6) << r.modes << std::setw(14) << scientific(r.omega_max, 3);
    if (reference) {
      s << std::setw(13) << "reference" << std::setw(13) << "-" << std::setw(13) << "-";
    } else {
      s << std::setw(13) << scientific(r.tip_error) + mark << std::setw(13)
        << scientific(r.tip_error_m) + mark << std::setw(13) << scientific(r.attitude_error) + mark;
    }
    std::ostringstream cpu;
    cpu << std::setprecision(3) << r.cpu_seconds;
    s << std::setw(13) << scientific(r.max_deflection) << std::setw(13)
      << scientific(r.tip_estimate) << std::setw(10) << r.steps << std::setw(10) << cpu.str()
      << "\n";
  }
  for (const std::string& note : result.notes) s << "note: " << note << "\n";
  return s.str();
}

}  // namespace flexref::studies
