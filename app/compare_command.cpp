/// \file compare_command.cpp
/// `flexref compare RUN REF`: a run of any code against a reference under the trajectory
/// contract (docs/external.md), the measured error beside the reference's own estimated error
/// (its sidecar REF.meta.toml), as a table or as JSON for scripts; with the scene known (--scene,
/// or the reference's sidecar), each ideal joint's violation measured from the run's positions
/// and whether the run is off its joints (trajectory/joint_violation.hpp).
#include "app/compare_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "app/cli_options.hpp"
#include "app/cli_validators.hpp"
#include "app/command_registry.hpp"
#include "app/exit_codes.hpp"
#include "app/input_checks.hpp"
#include "app/scene_metadata.hpp"
#include "core/error.hpp"
#include "precision/precise_comparison.hpp"
#include "trajectory/error_metrics.hpp"
#include "trajectory/joint_violation.hpp"
#include "trajectory/reference_sidecar.hpp"
#include "trajectory/trajectory_contract.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::app {
namespace {

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string json_number(double x) {
  if (!std::isfinite(x)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::string json_strings(const std::vector<std::string>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i > 0) out += ", ";
    out += json_string(v[i]);
  }
  return out + "]";
}

/// What the reference's estimate says about the measured value.
struct Certification {
  bool comparable = false;  ///< the sidecar has an estimate in the compared metric
  bool certified = false;
  std::string text;
};

Certification certify(const trajectory::ReferenceSidecar& sidecar, const std::string& metric,
                      double value) {
  Certification c;
  std::ostringstream out;
  out << std::scientific << std::setprecision(2);
  if (!sidecar.found) {
    out << "no sidecar " << sidecar.path << ": the reference's own error is unknown";
  } else if (!sidecar.has_estimate) {
    out << "the reference has no error estimate ("
        << (sidecar.kind == "reference" ? std::string("made with --no-estimate")
            : sidecar.kind.empty()      ? "its sidecar has no [error_estimate]"
                                        : "a " + sidecar.kind + " run, not a reference")
        << "): its own error is unknown";
  } else if (sidecar.metric != metric) {
    out << "the reference's estimated error " << sidecar.estimate << " is in metric "
        << sidecar.metric << ", not " << metric << ": not checked";
  } else if (std::isinf(sidecar.estimate)) {
    c.comparable = true;
    out << "the reference's own error is unknown (" << sidecar.estimate_method
        << "): NOT CERTIFIED (make a reference whose estimate has a usable check)";
  } else {
    c.comparable = true;
    c.certified = trajectory::is_certified(value, sidecar.estimate);
    const std::string unit = " [" + trajectory::metric_unit(metric) + "]";
    out << "reference estimated error " << sidecar.estimate << unit << "; measured " << value
        << unit;
    if (c.certified) {
      out << " is " << (sidecar.estimate > 0.0 ? value / sidecar.estimate : INFINITY)
          << "x above it: certified";
    } else {
      out << " is NOT " << trajectory::kCertificationFactor
          << "x above it: NOT CERTIFIED (the reference is not accurate enough to measure this "
             "error; use a tighter reference)";
    }
  }
  c.text = out.str();
  return c;
}

/// The joints of the run measured on the scene: --scene, else the file the reference's sidecar
/// names when it still holds the reference's physics (the same hash). `note` says why they
/// were not measured.
struct JointCheck {
  bool measured = false;
  std::vector<trajectory::JointViolation> joints;
  trajectory::JointVerdict verdict;
  std::string note;
};

JointCheck check_joints(const CompareOptions& options, const trajectory::ReferenceSidecar& sidecar,
                        const trajectory::RunData& run, const trajectory::TrajectoryTable& ref,
                        const trajectory::ComparisonReport& report) {
  JointCheck check;
  const core::FlexibleFormulation formulation =
      sidecar.scene.model.empty() ? kDefaultFormulation : parse_formulation(sidecar.scene.model);
  std::optional<scene::Scene> scene;
  if (!options.scene.empty()) {
    scene = load_scene(options.scene, formulation);
    check_same_scene(scene_identity(options.scene, *scene), "--scene " + options.scene,
                     sidecar.scene, options.reference, options.allow_scene_mismatch);
  } else if (sidecar.scene.file.empty()) {
    check.note = "not measured: the scene is unknown (" +
                 std::string(sidecar.found ? "the reference's sidecar names no scene file"
                                           : "the reference has no sidecar") +
                 "); give --scene SCENE to measure its ideal joints in the run";
    return check;
  } else {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(sidecar.scene.file, ec)) {
      check.note = "not measured: the reference's scene file " + sidecar.scene.file +
                   " is not there any more; give --scene SCENE";
      return check;
    }
    try {
      scene = load_scene(sidecar.scene.file, formulation);
    } catch (const std::exception& e) {
      check.note = "not measured: the reference's scene file " + sidecar.scene.file +
                   " cannot be read now (" + e.what() + "); give --scene SCENE";
      return check;
    }
    if (!sidecar.scene.hash.empty() && scene->hash != sidecar.scene.hash) {
      check.note = "not measured: the reference's scene file " + sidecar.scene.file +
                   " has changed since the reference was made (hash " + scene->hash + ", not " +
                   sidecar.scene.hash + "); give --scene SCENE";
      return check;
    }
  }
  check.measured = true;
  check.joints = trajectory::measure_joints(*scene->model, run.table);
  // The reference's estimated error bounds what can be told apart from it (+inf or absent:
  // nothing known, 0).
  const double noise =
      sidecar.has_estimate && std::isfinite(sidecar.estimate) ? sidecar.estimate : 0.0;
  check.verdict = trajectory::judge_joints(
      *scene->model, check.joints, trajectory::measure_joints(*scene->model, ref), report, noise);
  return check;
}

}  // namespace

int compare_command(const CompareOptions& options) {
  trajectory::ContractOptions contract;
  contract.time_tolerance = options.time_tolerance;
  contract.euler_norm_tolerance = options.euler_tolerance;
  // The two files' scenes first (their sidecars), before any reading of values.
  const trajectory::ReferenceSidecar sidecar =
      trajectory::read_reference_sidecar(options.reference);
  const std::string mismatch =
      check_same_scene(trajectory::read_reference_sidecar(options.run).scene, options.run,
                       sidecar.scene, options.reference, options.allow_scene_mismatch);
  const trajectory::RunData run = trajectory::read_run_csv(options.run);
  const trajectory::TrajectoryTable ref =
      trajectory::checked_reference(trajectory::read_run_csv(options.reference), contract);
  trajectory::ComparisonReport report = trajectory::compare_run(run, ref, contract);
  // An extended or quad file on the same columns and times: the norms again, in its precision
  // from the files' digits (docs/precision.md, "compare"); the contract's checks stand.
  std::string compared_in = "double";
  {
    const precision::PreciseTable a = precision::read_precise_table(options.run);
    const precision::PreciseTable b = precision::read_precise_table(options.reference);
    if (precision::precisely_comparable(a, b)) {
      trajectory::ComparisonReport precise = precision::compare_precisely(a, b);
      precise.ignored_columns = report.ignored_columns;
      precise.max_time_offset = report.max_time_offset;
      report = std::move(precise);
      compared_in = precision::to_string(std::max(a.precision, b.precision));
    }
  }
  double value = 0.0;
  std::vector<std::string> used;
  std::string unit, terms;
  try {
    used = trajectory::metric_quantities(report, options.metric);
    value = trajectory::metric_value(report, options.metric);
    unit = trajectory::metric_unit(options.metric);
    terms = trajectory::metric_terms(report, options.metric);
  } catch (const std::invalid_argument& e) {
    throw core::InputError(options.run, 0, "", e.what());
  }
  // The files hold finite values (the contract refuses others), so a non-finite norm is a
  // difference beyond double precision (values near 1e308 of opposite signs): a result that
  // turned non-finite (exit 3), never a table or a JSON null with exit 0.
  for (const auto& q : report.quantities) {
    for (const double norm : {q.norms.linf, q.norms.rms, q.norms.final}) {
      if (std::isfinite(norm)) continue;
      std::ostringstream why;
      why << "the error of " << q.name << " (" << q.kind << ", " << q.unit
          << ") is not finite near t = " << q.linf_time
          << " s: the difference of the two files' values overflows double precision";
      throw std::overflow_error(why.str());
    }
  }
  if (!std::isfinite(value)) {
    throw std::overflow_error("the metric " + options.metric +
                              " is not finite: its sum overflows double precision");
  }
  const JointCheck joints = check_joints(options, sidecar, run, ref, report);
  Certification cert = certify(sidecar, options.metric, value);
  if (joints.verdict.off) {
    // A run off its joints is a run of another system: its error certifies nothing.
    cert.certified = false;
    cert.text = "NOT CERTIFIED: the run is OFF ITS JOINTS: " + joints.verdict.why +
                " (reference: " + cert.text + ")";
  }

  if (options.json) {
    std::ostringstream out;
    out << "{\n  \"run\": " << json_string(options.run)
        << ",\n  \"reference\": " << json_string(options.reference)
        << ",\n  \"precision\": " << json_string(compared_in)
        << ",\n  \"rows_compared\": " << report.rows << ",\n  \"reference_rows\": " << ref.size()
        << ",\n  \"max_time_offset\": " << json_number(report.max_time_offset)
        << ",\n  \"ignored_columns\": " << json_strings(report.ignored_columns)
        << ",\n  \"quantities\": [";
    for (std::size_t i = 0; i < report.quantities.size(); ++i) {
      const auto& q = report.quantities[i];
      out << (i ? "," : "") << "\n    {\"name\": " << json_string(q.name)
          << ", \"kind\": " << json_string(q.kind) << ", \"unit\": " << json_string(q.unit)
          << ", \"columns\": " << json_strings(q.columns)
          << ", \"linf\": " << json_number(q.norms.linf)
          << ", \"rms\": " << json_number(q.norms.rms)
          << ", \"final\": " << json_number(q.norms.final)
          << ", \"linf_time\": " << json_number(q.linf_time) << "}";
    }
    out << "\n  ],\n  \"metric\": {\"name\": " << json_string(options.metric)
        << ", \"value\": " << json_number(value) << ", \"unit\": " << json_string(unit)
        << ", \"terms\": " << json_string(terms) << ", \"quantities\": " << json_strings(used)
        << "},\n  \"reference_estimate\": ";
    if (sidecar.has_estimate) {
      out << "{\"metric\": " << json_string(sidecar.metric)
          << ", \"value\": " << json_number(sidecar.estimate)
          << ", \"method\": " << json_string(sidecar.estimate_method)
          << ", \"solver\": " << json_string(sidecar.solver) << "}";
    } else {
      out << "null";
    }
    out << ",\n  \"certified\": "
        << (cert.comparable ? (cert.certified ? "true" : "false") : "null")
        << ",\n  \"note\": " << json_string(cert.text)
        << ",\n  \"scene_mismatch\": " << (mismatch.empty() ? "null" : json_string(mismatch))
        << ",\n  \"joints\": [";
    for (std::size_t i = 0; i < joints.joints.size(); ++i) {
      const trajectory::JointViolation& j = joints.joints[i];
      out << (i ? "," : "") << "\n    {\"name\": " << json_string(j.name)
          << ", \"measured\": " << (j.measured ? "true" : "false");
      if (j.measured) {
        out << ", \"violation\": " << json_number(j.value())
            << ", \"length\": " << json_number(j.length) << ", \"angle\": " << json_number(j.angle)
            << ", \"time\": " << json_number(j.time);
      } else {
        out << ", \"missing\": " << json_string(j.missing);
      }
      out << "}";
    }
    out << (joints.joints.empty() ? "]" : "\n  ]") << ",\n  \"off_joints\": "
        << (joints.measured ? (joints.verdict.off ? "true" : "false") : "null")
        << ",\n  \"joints_note\": "
        << json_string(joints.measured ? joints.verdict.why : joints.note) << "\n}\n";
    std::cout << out.str();
    return kExitOk;
  }

  std::cout << "compared " << report.rows << " of " << ref.size() << " output times";
  if (report.max_time_offset > 0.0) {
    std::cout << " (largest time offset " << std::scientific << std::setprecision(2)
              << report.max_time_offset << " s)";
  }
  if (compared_in != "double") {
    std::cout << "; values compared in " << compared_in
              << " precision (every digit of the files, no rounding to double)";
  }
  std::cout << "\n";
  std::cout << std::left << std::setw(28) << "quantity" << std::setw(7) << "unit" << std::right
            << std::setw(13) << "L-inf" << std::setw(13) << "RMS" << std::setw(13) << "final"
            << std::setw(13) << "t(L-inf)"
            << "\n";
  for (const auto& q : report.quantities) {
    std::cout << std::left << std::setw(28) << q.name << std::setw(7) << q.unit << std::right
              << std::scientific << std::setprecision(4) << std::setw(13) << q.norms.linf
              << std::setw(13) << q.norms.rms << std::setw(13) << q.norms.final << std::defaultfloat
              << std::setprecision(6) << std::setw(13) << q.linf_time << "\n";
  }
  if (!report.ignored_columns.empty()) {
    std::cout << "ignored columns (not measured):";
    for (const auto& c : report.ignored_columns) std::cout << " " << c;
    std::cout << "\n";
  }
  std::cout << "metric " << options.metric << " [" << unit << "]: " << std::scientific
            << std::setprecision(6) << value << "  (" << terms << ")\n";
  if (!joints.joints.empty()) {
    std::cout << "joint violations |Phi| from the run's positions (largest over its rows; "
                 "length rows in m, rotation rows as the sine of an angle):\n";
    for (const trajectory::JointViolation& j : joints.joints) {
      std::cout << "  joint " << std::left << std::setw(14) << j.name << std::right;
      if (!j.measured) {
        std::cout << "not measured: the run has no " << j.missing << "\n";
        continue;
      }
      std::cout << "violation " << std::scientific << std::setprecision(4) << j.value() << " ("
                << j.length << " m, " << j.angle << " rad) at t = " << std::defaultfloat
                << std::setprecision(6) << j.time << "\n";
    }
  } else if (!joints.measured) {
    std::cout << "joints: " << joints.note << "\n";
  }
  std::cout << cert.text << "\n";
  return kExitOk;
}

RegisteredCommand register_compare_command(CLI::App& app) {
  auto options = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand("compare", "error norms of a run against a reference");
  cmd->add_option("run", options->run, "CSV of the run")->required();
  cmd->add_option("reference", options->reference, "CSV of the reference")->required();
  cmd->add_option("--metric", options->metric, metric_help("metric for the summary line"))
      ->check(CLI::IsMember(trajectory::metric_names()))
      ->capture_default_str();
  cmd->add_flag("--json", options->json, "print the comparison as JSON");
  add_allow_scene_mismatch(cmd, options->allow_scene_mismatch);
  cmd->add_option("--scene", options->scene,
                  "the scene whose ideal joints are measured in the run (default: the "
                  "reference's sidecar's scene file, when it is unchanged)");
  cmd->add_option("--time-tolerance", options->time_tolerance,
                  "row times match output times within this x the output step")
      ->check(number_in(0.0, 0.5))
      ->capture_default_str();
  cmd->add_option("--euler-tolerance", options->euler_tolerance,
                  "largest accepted | |theta| - 1 | of Euler parameters")
      ->check(number_in(0.0, 0.1))
      ->capture_default_str();

  return {cmd, [options] { return compare_command(*options); }};
}

}  // namespace flexref::app
