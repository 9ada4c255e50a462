#include "scene/scene_reader.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "contact/bushing.hpp"
#include "contact/contact.hpp"
#include "core/applied_load.hpp"
#include "core/body.hpp"
#include "core/error.hpp"
#include "core/gravity.hpp"
#include "core/point_charge_potential.hpp"
#include "core/time_profile.hpp"
#include "flexible/beam_model.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/modal_data_reader.hpp"
#include "scene/scene_toml.hpp"

namespace flexref::scene {
namespace {

using scene_toml::Sign;
using scene_toml::Table;

// Orientations within this distance of unit norm are renormalized (decimal input of a unit
// quaternion is off by ~1e-16; hand-typed ones like [0.7071, 0.7071, 0, 0] by ~1e-5 are
// not, they are rejected with the norm they have).
constexpr double kOrientationTolerance = 1e-6;
// More output intervals than this is a typing error (end_time/output_step): 1e7 rows of a
// CSV are gigabytes, and the output-time grid is allocated up front.
constexpr double kMaxOutputIntervals = 1e7;

std::string format(double x) {
  std::ostringstream out;
  out.precision(10);
  out << x;
  return out.str();
}

/// Names of the bodies and the line where each was defined, in file order.
class BodyNames {
 public:
  /// Registers a body name; fails on a duplicate.
  void add(const Table& body, const std::string& name) {
    for (const auto& [other, line] : names_) {
      if (other == name) {
        body.fail("name", "duplicate body name \"" + name + "\" (first defined at line " +
                              std::to_string(line) + "); expected a unique name");
      }
    }
    names_.emplace_back(name, body.line_of("name"));
  }

  /// Index of the body a load or charge names in `key`.
  int resolve(const Table& table, std::string_view key) const {
    const std::string name = table.string(key, "the name of a [[body]]");
    for (std::size_t i = 0; i < names_.size(); ++i) {
      if (names_[i].first == name) return static_cast<int>(i);
    }
    std::string known;
    for (const auto& entry : names_) known += (known.empty() ? "\"" : ", \"") + entry.first + "\"";
    table.fail(key, "no [[body]] named \"" + name + "\"; expected one of " + known);
  }

 private:
  std::vector<std::pair<std::string, int>> names_;
};

// --- [scene] -------------------------------------------------------------------------------

struct SceneSettings {
  std::string name;
  std::string description;
  double end_time = 0.0;
  double output_step = 0.0;
  Eigen::Vector3d g_W = Eigen::Vector3d::Zero();
};

SceneSettings read_settings(const Table& root) {
  const std::optional<Table> scene = root.table("scene", "a [scene] table");
  if (!scene) {
    root.fail("scene",
              "required table is missing; expected a [scene] table with name, end_time and "
              "output_step");
  }
  scene->check_keys({"name", "description", "end_time", "output_step", "gravity"});
  SceneSettings s;
  s.name = scene->name("name", "the scene name, a string");
  s.description = scene->optional_string("description", "a string").value_or("");
  s.end_time = scene->number("end_time", Sign::kPositive, "a positive end time in s");
  s.output_step = scene->number("output_step", Sign::kPositive, "a positive output step in s");
  if (s.output_step > s.end_time) {
    scene->fail("output_step", "expected an output step no larger than end_time = " +
                                   format(s.end_time) + " s, got " + format(s.output_step));
  }
  if (s.end_time / s.output_step > kMaxOutputIntervals) {
    scene->fail("output_step", "expected at most 1e7 output intervals in end_time, got " +
                                   format(s.end_time / s.output_step));
  }
  s.g_W = scene->vector3_or("gravity", Eigen::Vector3d::Zero(),
                            "gravity [gx, gy, gz] in m/s^2, world frame");
  return s;
}

// --- [[body]] ------------------------------------------------------------------------------

const std::string kInertiaExpected =
    "the inertia about the centre of mass in kg*m^2, body frame: principal values "
    "[J1, J2, J3] or a symmetric 3x3 table [[Ixx, Ixy, Ixz], [Iyx, Iyy, Iyz], [Izx, Izy, Izz]]";

Eigen::Matrix3d read_inertia(const Table& body) {
  const toml::value* v = body.find("inertia");
  if (v == nullptr) body.fail("inertia", "required key is missing; expected " + kInertiaExpected);
  if (!v->is_array() || v->as_array().size() != 3) {
    body.fail("inertia", "expected " + kInertiaExpected + ", got " + scene_toml::describe(*v));
  }
  const toml::array& rows = v->as_array();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  const bool table = rows[0].is_array() || rows[1].is_array() || rows[2].is_array();
  for (std::size_t i = 0; i < 3; ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    if (!table) {
      inertia(r, r) = body.to_number(rows[i], "inertia", Sign::kAny, kInertiaExpected);
      continue;
    }
    if (!rows[i].is_array() || rows[i].as_array().size() != 3) {
      body.fail_at(rows[i], "inertia",
                   "expected " + kInertiaExpected + ", but row " + std::to_string(i + 1) + " is " +
                       scene_toml::describe(rows[i]));
    }
    for (std::size_t j = 0; j < 3; ++j) {
      inertia(r, static_cast<Eigen::Index>(j)) =
          body.to_number(rows[i].as_array()[j], "inertia", Sign::kAny, kInertiaExpected);
    }
  }
  if (const std::string problem = core::inertia_problem(inertia); !problem.empty()) {
    body.fail("inertia", problem +
                             "; expected a symmetric positive definite inertia in kg*m^2 with "
                             "J1 + J2 >= J3 for every permutation, got " +
                             scene_toml::describe(*v));
  }
  return inertia;
}

// Largest element and mode counts of a [body.beam]: the generalized eigenproblem is dense, so
// larger values are almost certainly typing errors (and would take minutes).
constexpr int kMaxBeamElements = 500;
constexpr int kMaxModes = 1000;

/// A required (or, with fallback >= 0, optional) TOML integer in [1, max].
int read_count(const Table& t, std::string_view key, int max, const std::string& expected,
               int fallback = -1) {
  const toml::value* v = t.find(key);
  if (v == nullptr) {
    if (fallback >= 0) return fallback;
    t.fail(key, "required key is missing; expected " + expected);
  }
  if (!v->is_integer()) t.fail(key, "expected " + expected + ", got " + scene_toml::describe(*v));
  const std::int64_t n = v->as_integer();
  if (n < 1 || n > max) {
    t.fail(key, "expected " + expected + " (1 to " + std::to_string(max) + "), got " +
                    scene_toml::describe(*v));
  }
  return static_cast<int>(n);
}

/// An array of exactly n finite numbers (modal coordinates, damping ratios).
Eigen::VectorXd read_vector(const Table& t, std::string_view key, Eigen::Index n, Sign sign,
                            const std::string& expected) {
  const toml::value* v = t.find(key);
  const std::string full = "an array of " + std::to_string(n) + " " + expected;
  if (v == nullptr) t.fail(key, "required key is missing; expected " + full);
  if (!v->is_array() || static_cast<Eigen::Index>(v->as_array().size()) != n) {
    t.fail(key, "expected " + full + " (one per mode), got " + scene_toml::describe(*v));
  }
  Eigen::VectorXd out(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    out(i) = t.to_number(v->as_array()[static_cast<std::size_t>(i)], key, sign, expected);
  }
  return out;
}

/// [body.beam]: the built-in beam finite-element model (flexible/beam_model.hpp).
flexible::ModalData read_beam(const Table& body) {
  const std::optional<Table> b =
      body.table("beam", "a table [body.beam] with length, elements, EA, EI, rho_A and modes");
  b->check_keys({"length", "elements", "EA", "EI", "EI_y", "EI_z", "GJ", "rho_A", "boundary",
                 "origin", "modes", "families", "damping_ratio"});
  flexible::BeamParameters p;
  p.origin =
      b->vector3_or("origin", Eigen::Vector3d::Zero(),
                    "the beam root [x, y, z] in m from the frame origin, body frame (the beam "
                    "runs along the body x axis from there)");
  p.length = b->number("length", Sign::kPositive, "a positive beam length in m");
  p.elements = read_count(*b, "elements", kMaxBeamElements, "a positive integer element count");
  p.EA = b->number("EA", Sign::kPositive, "a positive axial stiffness EA in N");
  if (b->has("EI")) {
    for (const std::string_view key : {"EI_y", "EI_z"}) {
      if (b->has(key)) {
        b->fail(key,
                "EI already gives both bending stiffnesses; expected either EI or EI_y "
                "and EI_z");
      }
    }
    p.EI_y = p.EI_z = b->number("EI", Sign::kPositive, "a positive bending stiffness EI in N*m^2");
  } else {
    if (!b->has("EI_y") && !b->has("EI_z")) {
      b->fail("EI",
              "required key is missing; expected a positive bending stiffness EI in N*m^2 "
              "(both planes), or EI_y and EI_z");
    }
    p.EI_y = b->number("EI_y", Sign::kPositive,
                       "a positive bending stiffness EI_y in N*m^2 (about y, deflection along z)");
    p.EI_z = b->number("EI_z", Sign::kPositive,
                       "a positive bending stiffness EI_z in N*m^2 (about z, deflection along y)");
  }
  if (b->has("GJ")) {
    p.GJ = b->number("GJ", Sign::kPositive, "a positive torsional stiffness GJ in N*m^2");
  }
  p.rho_A = b->number("rho_A", Sign::kPositive, "a positive mass per length rho_A in kg/m");
  p.boundary = b->choice("boundary", {"clamped-free", "free-free"}, 0) == 0
                   ? flexible::BeamBoundary::kClampedFree
                   : flexible::BeamBoundary::kFreeFree;
  const int modes = read_count(*b, "modes", kMaxModes, "a positive integer mode count");
  flexible::BeamModeFilter filter;
  if (const toml::value* f = b->find("families")) {
    const std::string expected =
        "an array of mode families from \"bending-xy\", \"bending-xz\", \"axial\"";
    if (!f->is_array() || f->as_array().empty()) {
      b->fail("families", "expected " + expected + ", got " + scene_toml::describe(*f));
    }
    filter = flexible::BeamModeFilter{false, false, false};
    for (const toml::value& item : f->as_array()) {
      const std::string name = item.is_string() ? item.as_string().str : std::string();
      bool* flag = name == "bending-xy"   ? &filter.bending_xy
                   : name == "bending-xz" ? &filter.bending_xz
                   : name == "axial"      ? &filter.axial
                                          : nullptr;
      if (flag == nullptr) {
        b->fail_at(item, "families",
                   "expected " + expected +
                       (name == "torsion" ? " (torsion modes do not move the beam axis and are "
                                            "not part of the modal data)"
                                          : "") +
                       ", got " + scene_toml::describe(item));
      }
      if (*flag) b->fail_at(item, "families", "family \"" + name + "\" is listed twice");
      *flag = true;
    }
  }
  if (const std::string problem = flexible::beam_parameters_problem(p); !problem.empty()) {
    b->fail_table(problem);
  }
  flexible::ModalData data;
  try {
    data = flexible::make_beam_modal_data(p, modes, filter);
  } catch (const std::invalid_argument& e) {
    b->fail("modes", std::string("cannot make the beam's modal data: ") + e.what());
  } catch (const std::exception& e) {
    // The eigen-solve fails for extreme but finite parameters (a length of 1e-320 m).
    b->fail_table(std::string("cannot make the beam's modal data (extreme parameters?): ") +
                  e.what());
  }
  if (b->has("damping_ratio")) {
    const toml::value& v = *b->find("damping_ratio");
    const std::string expected = "a modal damping ratio >= 0 (dimensionless)";
    if (v.is_array()) {
      data.damping_ratio =
          read_vector(*b, "damping_ratio", data.mode_count(), Sign::kNonNegative, expected);
    } else {
      data.damping_ratio.setConstant(data.mode_count(),
                                     b->to_number(v, "damping_ratio", Sign::kNonNegative,
                                                  expected + " or an array of one per mode"));
    }
  }
  return data;
}

/// The scene file's directory joined with a path given in it (absolute paths stay).
std::string relative_to(const std::string& scene_file, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  return (std::filesystem::path(scene_file).parent_path() / p).lexically_normal().string();
}

/// `modal = "file.toml"`: a modal-data file (docs/modal_data.md), relative to the scene.
flexible::ModalData read_modal_file(const Table& body) {
  const std::string given = body.string("modal", "the path of a modal-data file (TOML)");
  if (given.empty()) body.fail("modal", "expected the path of a modal-data file, got \"\"");
  const std::string path = relative_to(body.file(), given);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    body.fail("modal", "cannot open the modal-data file " + path +
                           " (paths are relative to the scene file's directory)");
  }
  try {
    return read_modal_data(path);
  } catch (const core::InputError& e) {
    // The error is in the modal-data file: keep its file, line and key, and say which scene
    // body reads it.
    std::string what = e.what();
    std::string prefix = e.file();
    if (e.line() > 0) prefix += ":" + std::to_string(e.line());
    prefix += ": ";
    if (!e.key().empty()) prefix += "key '" + e.key() + "': ";
    if (what.starts_with(prefix)) what.erase(0, prefix.size());
    throw core::InputError(e.file(), e.line(), e.key(),
                           what + " (modal data of " + body.key_path("modal") + ", " + body.file() +
                               ":" + std::to_string(body.line_of("modal")) + ")");
  }
}

std::vector<core::TrackedPoint> read_points(const Table& body, const flexible::ModalData* modal) {
  std::vector<core::TrackedPoint> points;
  const std::string expected =
      "an array of points { name = \"...\", at = [x, y, z] } (or node = \"...\" on a flexible "
      "body)";
  for (const Table& p : body.tables("points", expected)) {
    p.check_keys({"name", "at", "node"});
    core::TrackedPoint point;
    point.name = p.name("name", "a point name");
    for (const core::TrackedPoint& other : points) {
      if (other.name == point.name) {
        p.fail("name",
               "duplicate point name \"" + point.name + "\" in this body; expected a unique name");
      }
    }
    if (p.has("node")) {
      if (modal == nullptr) {
        p.fail("node",
               "applies only to flexible bodies (beam or modal); expected at = [x, y, z] on a "
               "rigid body");
      }
      if (p.has("at")) {
        p.fail("at", "a node point is at its node; expected either at or node, not both");
      }
      const std::string node = p.string("node", "the name of a node of the body's modal data");
      const auto& names = modal->node_names;
      const auto it = std::find(names.begin(), names.end(), node);
      if (it == names.end()) {
        std::string known;
        if (names.empty()) {
          known = " (the modal data has no node names)";
        } else {
          known =
              "; expected a node name such as \"" + names.front() + "\" … \"" + names.back() + "\"";
        }
        p.fail("node", "no node named \"" + node + "\" in the body's modal data" + known);
      }
      point.node = static_cast<int>(it - names.begin());
      point.p_BoP_B = modal->p_BoNode_B.col(point.node);
    } else {
      point.p_BoP_B = p.vector3("at", "the point [x, y, z] in m from the frame origin, body frame");
    }
    points.push_back(std::move(point));
  }
  return points;
}

/// [body.prescribed]: the angle law of motion = "prescribed".
core::PrescribedRotation read_prescribed(const Table& body) {
  const std::optional<Table> t = body.table(
      "prescribed", "a table [body.prescribed] with axis, law and rate (motion = \"prescribed\")");
  if (!t) {
    body.fail("prescribed",
              "required table is missing; expected [body.prescribed] with axis, law and rate "
              "for motion = \"prescribed\"");
  }
  t->check_keys({"axis", "law", "rate", "spin_up_time"});
  core::PrescribedRotation r;
  const Eigen::Vector3d axis =
      t->vector3("axis", "the rotation axis [x, y, z], a unit vector, world frame");
  const double norm = axis.norm();
  if (!(std::abs(norm - 1.0) <= kOrientationTolerance)) {
    t->fail("axis",
            "expected a unit axis [x, y, z] (norm 1 within 1e-6), got norm " + format(norm));
  }
  r.axis_W = axis / norm;
  const bool spin_up = t->choice("law", {"constant-rate", "spin-up"}, -1) == 1;
  r.law.kind = spin_up ? core::AngleLaw::Kind::kSpinUp : core::AngleLaw::Kind::kConstantRate;
  r.law.rate = t->number(
      "rate", Sign::kAny,
      spin_up ? "the final angular rate Omega_s in rad/s" : "the angular rate Omega in rad/s");
  if (spin_up) {
    r.law.spin_up_time =
        t->number("spin_up_time", Sign::kPositive, "a positive spin-up time T_s in s");
  } else if (t->has("spin_up_time")) {
    t->fail("spin_up_time",
            "applies only to law = \"spin-up\"; expected no spin_up_time with "
            "law = \"constant-rate\"");
  }
  return r;
}

core::Body read_body(const Table& t, BodyNames& names) {
  t.check_keys({"name", "mass", "inertia", "center_of_mass", "motion", "pivot", "prescribed",
                "position", "orientation", "velocity", "angular_velocity", "points", "beam",
                "modal", "q0", "qd0"});
  core::RigidBodyDescription d;
  d.name = t.name("name", "a body name");
  names.add(t, d.name);

  // The flexible part first: it decides what the mass keys mean (the hub's).
  std::optional<core::FlexiblePart> flexible;
  if (t.has("beam") && t.has("modal")) {
    t.fail("modal",
           "a flexible body has one source of modal data; expected either [body.beam] or "
           "modal = \"file.toml\", not both");
  }
  if (t.has("beam")) flexible.emplace(core::FlexiblePart{read_beam(t), {}, {}});
  if (t.has("modal")) flexible.emplace(core::FlexiblePart{read_modal_file(t), {}, {}});
  if (flexible) {
    const Eigen::Index n = flexible->modal.mode_count();
    if (t.has("q0")) {
      flexible->q0 = read_vector(t, "q0", n, Sign::kAny, "initial modal coordinates q0");
    }
    if (t.has("qd0")) {
      flexible->qd0 = read_vector(t, "qd0", n, Sign::kAny, "initial modal velocities qd0 in 1/s");
    }
  } else {
    for (const std::string_view key : {"q0", "qd0"}) {
      if (t.has(key)) {
        t.fail(key, "applies only to flexible bodies; expected no " + std::string(key) +
                        " without [body.beam] or modal");
      }
    }
  }

  if (flexible) {
    // The hub: optional; mass 0 (the default) is no hub, and then no inertia.
    d.mass = t.number_or("mass", 0.0, Sign::kNonNegative,
                         "a hub mass >= 0 in kg (0: no hub) for a flexible body");
    if (d.mass == 0.0) {
      if (t.has("inertia")) {
        t.fail("inertia",
               "a flexible body without hub mass has no hub inertia; expected no inertia with "
               "mass = 0 (or a positive hub mass)");
      }
      d.I_Bcm_B.setZero();
    } else {
      d.I_Bcm_B = read_inertia(t);
    }
  } else {
    const toml::value* m = t.find("mass");
    if (m != nullptr && (m->is_floating() || m->is_integer()) &&
        t.to_number(*m, "mass", Sign::kAny, "a positive mass in kg") == 0.0) {
      t.fail("mass", "expected a positive mass in kg, got " + scene_toml::describe(*m) +
                         " (mass 0 is allowed only for the hub of a flexible body: [body.beam] "
                         "or modal)");
    }
    d.mass = t.number("mass", Sign::kPositive, "a positive mass in kg");
    d.I_Bcm_B = read_inertia(t);
  }
  if (d.mass > 0.0 && !std::isfinite(1.0 / d.mass)) {
    t.fail("mass", "expected a positive mass in kg, got " + format(d.mass) +
                       " (too small: 1/mass overflows)");
  }
  d.p_BoBcm_B = t.vector3_or("center_of_mass", Eigen::Vector3d::Zero(),
                             "the centre of mass [x, y, z] in m, body frame");
  const int motion = t.choice("motion", {"free", "pivot", "prescribed"}, 0);
  const bool pivot = motion == 1;
  const bool prescribed = motion == 2;
  d.motion = pivot        ? core::MotionKind::kPivot
             : prescribed ? core::MotionKind::kPrescribed
                          : core::MotionKind::kFree;
  if (prescribed && !flexible) {
    t.fail("motion",
           "motion = \"prescribed\" applies only to flexible bodies (a prescribed rigid body has "
           "no degrees of freedom); expected \"free\" or \"pivot\"");
  }
  if (pivot) {
    d.p_BoPivot_B = t.vector3("pivot", "the pivot [x, y, z] in m, body frame (motion = \"pivot\")");
  } else if (t.has("pivot")) {
    t.fail("pivot", "applies only to motion = \"pivot\"; expected no pivot for a free body");
  }
  if (prescribed) {
    d.prescribed = read_prescribed(t);
  } else if (t.has("prescribed")) {
    t.fail("prescribed",
           "applies only to motion = \"prescribed\"; expected no [body.prescribed] here");
  }
  d.initial.p_WBo = t.vector3_or("position", Eigen::Vector3d::Zero(),
                                 "the frame origin's position [x, y, z] in m, world frame");
  const Eigen::Vector4d theta =
      t.vector4_or("orientation", rotation::identity_euler_parameters(),
                   "Euler parameters [e0, e1, e2, e3] (scalar first) of the body-to-world "
                   "rotation");
  const double norm = theta.norm();
  if (!(std::abs(norm - 1.0) <= kOrientationTolerance)) {
    const std::string expected =
        "expected unit Euler parameters [e0, e1, e2, e3] (norm 1 within 1e-6)";
    t.fail("orientation", expected + ", got norm " + format(norm));
  }
  d.initial.theta_WB = theta / norm;
  d.initial.v_WBo = t.vector3_or("velocity", Eigen::Vector3d::Zero(),
                                 "the frame origin's velocity [vx, vy, vz] in m/s, world frame");
  if (pivot && !d.initial.v_WBo.isZero(0.0)) {
    t.fail("velocity",
           "a pivot body's velocities follow from its angular velocity; expected no "
           "velocity (or [0, 0, 0]) with motion = \"pivot\"");
  }
  if (prescribed && t.has("velocity")) {
    t.fail("velocity",
           "a prescribed body's frame origin is fixed; expected no velocity with "
           "motion = \"prescribed\"");
  }
  if (prescribed && t.has("angular_velocity")) {
    t.fail("angular_velocity",
           "a prescribed body's angular velocity follows from its law; expected no "
           "angular_velocity with motion = \"prescribed\"");
  }
  d.initial.w_WB_B = t.vector3_or("angular_velocity", Eigen::Vector3d::Zero(),
                                  "the angular velocity [wx, wy, wz] in rad/s, body frame");
  d.points = read_points(t, flexible ? &flexible->modal : nullptr);
  d.flexible = std::move(flexible);
  const bool is_flexible = d.flexible.has_value();

  std::optional<core::Body> body;
  try {
    body.emplace(std::move(d));
  } catch (const core::InertiaRangeError&) {
    // The reference-point data core::Body derives (the parallel-axis shift to the pivot and
    // the inverse) can overflow for extreme but finite input: report it at the inertia.
    t.fail("inertia", std::string("the inertia about the ") + (pivot ? "pivot" : "centre of mass") +
                          " or its inverse is not finite (values too large or too small)");
  } catch (const std::exception& e) {
    // Flexible bodies: everything but the undeformed inertia of a free or pivot body (a beam
    // without hub has none about its axis) is checked above.
    if (is_flexible) t.fail(t.has("inertia") ? "inertia" : "mass", e.what());
    t.fail_table(e.what());
  }
  return *std::move(body);
}

// --- [[load]] ------------------------------------------------------------------------------

core::TimeProfile read_profile(const Table& load) {
  const std::optional<Table> p =
      load.table("profile",
                 "a profile { shape = \"constant\" | \"sin2_pulse\" | \"rectangular_pulse\", "
                 "start, duration }");
  if (!p) return core::TimeProfile::constant();
  p->check_keys({"shape", "start", "duration"});
  const int shape = p->choice("shape", {"constant", "sin2_pulse", "rectangular_pulse"}, -1);
  if (shape == 0) {
    for (const std::string_view key : {"start", "duration"}) {
      if (p->has(key)) {
        p->fail(key, "applies only to pulses; expected no " + std::string(key) +
                         " with shape = \"constant\"");
      }
    }
    return core::TimeProfile::constant();
  }
  const double start = p->number_or("start", 0.0, Sign::kAny, "a pulse start time in s");
  const double duration = p->number("duration", Sign::kPositive, "a positive pulse duration in s");
  if (!std::isfinite(start + duration)) {
    p->fail("duration", "expected a pulse that ends at a finite time, got start + duration = " +
                            format(start + duration));
  }
  try {
    return shape == 1 ? core::TimeProfile::sin2_pulse(start, duration)
                      : core::TimeProfile::rectangular_pulse(start, duration);
  } catch (const std::exception& e) {
    p->fail_table(e.what());
  }
}

std::unique_ptr<const core::ForceElement> read_load(const Table& t, const BodyNames& names) {
  t.check_keys({"kind", "body", "value", "frame", "at", "profile"});
  const bool torque = t.choice("kind", {"torque", "force"}, -1) == 0;
  const int body = names.resolve(t, "body");
  const Eigen::Vector3d value =
      t.vector3("value", torque ? "the torque [x, y, z] in N*m" : "the force [x, y, z] in N");
  const core::LoadFrame frame = t.choice("frame", {"world", "body"}, 0) == 0
                                    ? core::LoadFrame::kWorld
                                    : core::LoadFrame::kBody;
  if (torque && t.has("at")) {
    t.fail("at", "applies only to forces (a torque is a couple); expected no at for a torque");
  }
  const Eigen::Vector3d at = t.vector3_or("at", Eigen::Vector3d::Zero(),
                                          "the point of application [x, y, z] in m, body frame");
  const core::TimeProfile profile = read_profile(t);
  if (torque) return std::make_unique<core::AppliedTorque>(body, value, frame, profile);
  return std::make_unique<core::AppliedForce>(body, value, frame, at, profile);
}

// --- [[potential]] -------------------------------------------------------------------------

std::unique_ptr<const core::ForceElement> read_potential(const Table& t, const BodyNames& names,
                                                         const std::vector<core::Body>& bodies) {
  t.check_keys({"kind", "alpha", "beta", "attractor", "charges"});
  t.choice("kind", {"point_charge"}, -1);
  const double alpha =
      t.number("alpha", Sign::kNonNegative, "a non-negative attraction strength alpha in J*m");
  const double beta =
      t.number("beta", Sign::kNonNegative, "a non-negative wall repulsion strength beta in J*m");
  const Eigen::Vector3d p_WM =
      t.vector3("attractor", "the attracting point [x, y, z] in m, world frame");
  const std::vector<Table> tables =
      t.tables("charges", "an array of charges { body = \"...\", at = [x, y, z], weight = c }");
  if (tables.empty()) {
    t.fail("charges", "expected at least one charge { body = \"...\", at = [x, y, z], weight }");
  }
  std::vector<core::PointChargePotential::Charge> charges;
  for (const Table& c : tables) {
    c.check_keys({"body", "at", "weight"});
    core::PointChargePotential::Charge charge;
    charge.body = names.resolve(c, "body");
    charge.p_BoP_B = c.vector3("at", "the charge position [x, y, z] in m, body frame");
    charge.weight = c.number_or("weight", 1.0, Sign::kPositive, "a positive charge weight");
    // The potential is singular on the wall z = 0 and at the attractor, and defined above
    // the wall only: the charge must start there.
    const core::BodyInitialState& init =
        bodies[static_cast<std::size_t>(charge.body)].description().initial;
    const Eigen::Vector3d p_WP =
        init.p_WBo + rotation::rotation_matrix(init.theta_WB) * charge.p_BoP_B;
    if (!(p_WP.z() > 0.0)) {
      c.fail("at", "the charge starts at z = " + format(p_WP.z()) +
                       "; expected a charge above the wall z = 0");
    }
    if (!((p_WP - p_WM).norm() > 0.0)) {
      c.fail("at", "the charge starts on the attractor; expected a charge away from it");
    }
    charges.push_back(charge);
  }
  return std::make_unique<core::PointChargePotential>(alpha, beta, p_WM, std::move(charges));
}

// --- [[contact]] ---------------------------------------------------------------------------

/// A unit vector: renormalized when within 1e-6 of unit norm, else an error.
Eigen::Vector3d read_unit(const Table& t, std::string_view key, const Eigen::Vector3d* fallback,
                          const std::string& expected) {
  const Eigen::Vector3d v =
      fallback != nullptr ? t.vector3_or(key, *fallback, expected) : t.vector3(key, expected);
  const double norm = v.norm();
  if (!(std::abs(norm - 1.0) <= kOrientationTolerance)) {
    t.fail(key, "expected " + expected + " (norm 1 within 1e-6), got norm " + format(norm));
  }
  return v / norm;
}

/// `single` (one 3-vector) or `plural` (an array of 3-vectors), exactly one of them.
std::vector<Eigen::Vector3d> read_vector_list(const Table& t, std::string_view single,
                                              std::string_view plural,
                                              const std::string& expected) {
  if (t.has(single) && t.has(plural)) {
    t.fail(plural,
           "expected either " + std::string(single) + " or " + std::string(plural) + ", not both");
  }
  if (t.has(single)) return {t.vector3(single, expected)};
  const toml::value* v = t.find(plural);
  const std::string list = "an array of " + expected + " vectors [[x, y, z], ...]";
  if (v == nullptr) {
    t.fail(single, "required key is missing; expected " + std::string(single) + " = " + expected +
                       " or " + std::string(plural) + " = " + list);
  }
  if (!v->is_array() || v->as_array().empty()) {
    t.fail(plural, "expected " + list + " (at least one), got " + scene_toml::describe(*v));
  }
  std::vector<Eigen::Vector3d> out;
  for (const toml::value& e : v->as_array()) {
    if (!e.is_array() || e.as_array().size() != 3) {
      t.fail_at(e, plural, "expected " + list + ", got an element " + scene_toml::describe(e));
    }
    Eigen::Vector3d p;
    for (int i = 0; i < 3; ++i) {
      p(i) = t.to_number(e.as_array()[static_cast<std::size_t>(i)], plural, Sign::kAny, expected);
    }
    out.push_back(p);
  }
  return out;
}

/// The keys every contact and joint law shares are checked by check_keys; this rejects the
/// ones that do not apply to the chosen kind or law.
void reject_keys(const Table& t, std::initializer_list<std::string_view> keys,
                 const std::string& why) {
  for (const std::string_view key : keys) {
    if (t.has(key)) t.fail(key, why + "; expected no " + std::string(key) + " here");
  }
}

std::unique_ptr<const core::ForceElement> read_contact(const Table& t, const BodyNames& names,
                                                       const std::vector<core::Body>& bodies) {
  t.check_keys({"kind",
                "body",
                "center",
                "centers",
                "radius",
                "point",
                "points",
                "body_b",
                "center_b",
                "radius_b",
                "plane_point",
                "plane_normal",
                "law",
                "stiffness",
                "exponent",
                "restitution",
                "reference_speed",
                "damping",
                "friction",
                "regularization_speed",
                "effective_mass"});
  const int kind = t.choice("kind", {"sphere-plane", "point-plane", "sphere-sphere"}, -1);
  const int body = names.resolve(t, "body");
  std::vector<contact::ContactPair> pairs;
  double mass = bodies[static_cast<std::size_t>(body)].mass();
  if (kind == 2) {
    reject_keys(t, {"centers", "point", "points", "plane_point", "plane_normal"},
                "applies only to sphere-plane and point-plane contacts");
    const int body_b = names.resolve(t, "body_b");
    if (body_b == body) {
      t.fail("body_b",
             "a sphere-sphere contact joins two different bodies; expected a body "
             "other than body");
    }
    const Eigen::Vector3d c_a =
        t.vector3("center", "the centre [x, y, z] of body's sphere in m, body frame");
    const double r_a = t.number("radius", Sign::kNonNegative, "a sphere radius >= 0 in m");
    const Eigen::Vector3d c_b =
        t.vector3("center_b", "the centre [x, y, z] of body_b's sphere in m, body_b's frame");
    const double r_b = t.number("radius_b", Sign::kNonNegative, "a sphere radius >= 0 in m");
    pairs.push_back(contact::ContactPair::sphere_sphere(body, c_a, r_a, body_b, c_b, r_b));
    const double m_b = bodies[static_cast<std::size_t>(body_b)].mass();
    mass = mass * m_b / (mass + m_b);
  } else {
    reject_keys(t, {"body_b", "center_b", "radius_b"}, "applies only to sphere-sphere contacts");
    const Eigen::Vector3d p_WQ = t.vector3_or("plane_point", Eigen::Vector3d::Zero(),
                                              "a point [x, y, z] of the plane in m, world frame");
    const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d n_W =
        read_unit(t, "plane_normal", &up,
                  "the plane's unit normal [x, y, z] toward the free side, world frame");
    if (kind == 0) {
      reject_keys(t, {"point", "points"},
                  "a sphere-plane contact is given by center(s) and radius");
      const std::vector<Eigen::Vector3d> centers =
          read_vector_list(t, "center", "centers", "the sphere centre [x, y, z] in m, body frame");
      const double r = t.number("radius", Sign::kNonNegative, "a sphere radius >= 0 in m");
      for (const Eigen::Vector3d& c : centers) {
        pairs.push_back(contact::ContactPair::sphere_plane(body, c, r, p_WQ, n_W));
      }
    } else {
      reject_keys(t, {"center", "centers", "radius"}, "a point-plane contact is given by point(s)");
      const std::vector<Eigen::Vector3d> points =
          read_vector_list(t, "point", "points", "the contact point [x, y, z] in m, body frame");
      for (const Eigen::Vector3d& p : points) {
        pairs.push_back(contact::ContactPair::point_plane(body, p, p_WQ, n_W));
      }
    }
  }
  const double m_eff = t.number_or("effective_mass", mass / static_cast<double>(pairs.size()),
                                   Sign::kPositive, "a positive effective mass in kg");

  const bool linear = t.choice("law", {"hunt-crossley", "linear"}, 0) == 1;
  const double k =
      t.number_or("stiffness", 1e6, Sign::kPositive,
                  linear ? "a positive stiffness in N/m" : "a positive stiffness in N/m^n");
  std::optional<contact::NormalLaw> law;
  const auto restitution = [&] {
    const double e =
        t.number_or("restitution", 0.5, Sign::kPositive, "a restitution coefficient in (0, 1]");
    if (e > 1.0) {
      t.fail("restitution", "expected a restitution coefficient in (0, 1], got " + format(e));
    }
    return e;
  };
  try {
    if (linear) {
      reject_keys(t, {"exponent", "reference_speed"}, "applies only to law = \"hunt-crossley\"");
      if (t.has("damping") && t.has("restitution")) {
        t.fail("damping",
               "the linear law takes either damping or restitution; expected one "
               "of them, not both");
      }
      if (t.has("damping")) {
        law = contact::NormalLaw::linear(
            k, t.number("damping", Sign::kNonNegative, "a damping >= 0 in N*s/m"));
      } else {
        law = contact::NormalLaw::linear_from_restitution(k, restitution(), m_eff);
      }
    } else {
      reject_keys(t, {"damping"},
                  "applies only to law = \"linear\" (Hunt-Crossley damping follows from "
                  "restitution and reference_speed)");
      const double n = t.number_or("exponent", 1.5, Sign::kPositive, "an exponent >= 1");
      if (n < 1.0) t.fail("exponent", "expected an exponent >= 1, got " + format(n));
      const double e = restitution();
      const double v_ref = t.number_or("reference_speed", 1.0, Sign::kPositive,
                                       "a positive reference impact speed in m/s");
      law = contact::NormalLaw::hunt_crossley(k, n, e, v_ref);
    }
  } catch (const core::InputError&) {
    throw;
  } catch (const std::exception& e) {
    // Every parameter is checked above; what remains are extreme values (a restitution of
    // 1e-320) for which the law's damping cannot be computed.
    t.fail(t.has("restitution") ? "restitution" : "stiffness",
           std::string("cannot build the contact law: ") + e.what() +
               "; expected less extreme law parameters");
  }
  contact::FrictionLaw friction;
  friction.mu = t.number_or("friction", 0.0, Sign::kNonNegative,
                            "a friction coefficient mu >= 0 (0: frictionless)");
  friction.v_reg = t.number_or("regularization_speed", 1e-3, Sign::kPositive,
                               "a positive regularization speed in m/s");
  try {
    return std::make_unique<contact::ContactElement>(std::move(pairs), *law, friction, m_eff);
  } catch (const std::invalid_argument& e) {
    t.fail_table(e.what());
  }
}

// --- [[joint]] -----------------------------------------------------------------------------

std::unique_ptr<const core::ForceElement> read_joint(const Table& t, const BodyNames& names) {
  t.check_keys({"kind", "body_a", "body_b", "point_a", "point_b", "axis_a", "axis_b", "stiffness",
                "damping", "angular_stiffness", "angular_damping"});
  const bool revolute = t.choice("kind", {"spherical", "revolute"}, -1) == 1;
  contact::BushingEnd a;
  contact::BushingEnd b;
  a.body = names.resolve(t, "body_a");
  const toml::value* vb = t.find("body_b");
  if (vb != nullptr && vb->is_string() && vb->as_string() == "ground") {
    b.body = contact::kGround;
  } else {
    b.body = names.resolve(t, "body_b");
    if (b.body == a.body) {
      t.fail("body_b",
             "a joint joins two different bodies; expected another body or "
             "\"ground\"");
    }
  }
  const bool ground = b.body == contact::kGround;
  a.point = t.vector3("point_a", "the joint point [x, y, z] in m on body_a, body frame");
  b.point = t.vector3("point_b", ground ? "the joint point [x, y, z] in m, world frame (ground)"
                                        : "the joint point [x, y, z] in m on body_b, body frame");
  contact::BushingParameters p;
  p.stiffness = t.number_or("stiffness", contact::BushingParameters::kDefaultStiffness,
                            Sign::kPositive, "a positive stiffness in N/m");
  p.damping = t.number_or("damping", 0.0, Sign::kNonNegative, "a damping >= 0 in N*s/m");
  if (revolute) {
    a.axis =
        read_unit(t, "axis_a", nullptr, "the hinge axis [x, y, z], a unit vector, body_a frame");
    b.axis = read_unit(t, "axis_b", nullptr,
                       ground ? "the hinge axis [x, y, z], a unit vector, world frame (ground)"
                              : "the hinge axis [x, y, z], a unit vector, body_b frame");
    p.angular_stiffness =
        t.number_or("angular_stiffness", contact::BushingParameters::kDefaultAngularStiffness,
                    Sign::kNonNegative, "an angular stiffness >= 0 in N*m/rad");
    p.angular_damping = t.number_or("angular_damping", 0.0, Sign::kNonNegative,
                                    "an angular damping >= 0 in N*m*s/rad");
  } else {
    reject_keys(t, {"axis_a", "axis_b", "angular_stiffness", "angular_damping"},
                "applies only to kind = \"revolute\"");
  }

  try {
    if (revolute) return std::make_unique<contact::RevoluteBushing>(a, b, p);
    return std::make_unique<contact::SphericalBushing>(a, b, p);
  } catch (const std::invalid_argument& e) {
    t.fail_table(e.what());
  }
}

// Finite input can still overflow (a spin of 1e308 rad/s, a charge 1e-300 m above the wall):
// evaluate the model once at the initial state so that no integrator starts from inf or NaN.
void check_initial_evaluation(const core::Model& model, const Table& root,
                              const std::vector<Table>& body_tables) {
  const core::State state = model.initial_state();
  core::Workspace ws = model.make_workspace();
  core::Accelerations accelerations = model.make_accelerations();
  model.compute_accelerations(core::LoadContext{0.0, 0.0}, state, ws, accelerations);
  for (std::size_t i = 0; i < state.size(); ++i) {
    const core::BodyState& s = state[i];
    const core::BodyAcceleration& a = accelerations[i];
    if (!s.p_WBr.allFinite() || !s.v_WBr.allFinite() || !a.a_WBr.allFinite() ||
        !a.alpha_WB_B.allFinite() || !a.qdd_f.allFinite()) {
      body_tables[i].fail_table(
          "the initial state or accelerations of this body are not finite (values too large or "
          "too small); expected values whose products stay within the range of a double");
    }
  }
  const double energy = model.kinetic_energy(state) + model.potential_energy({}, state, ws);
  if (!std::isfinite(energy)) {
    root.fail("scene",
              "the initial energy is not finite (values too large or too small); "
              "expected values whose products stay within the range of a double");
  }
}

Scene read_document(const toml::value& document, const std::string& file,
                    core::FlexibleFormulation formulation) {
  const Table root(document, file, "");
  root.check_keys({"scene", "body", "load", "potential", "contact", "joint"});
  SceneSettings settings = read_settings(root);

  const std::vector<Table> body_tables = root.tables("body", "[[body]] tables");
  if (body_tables.empty()) root.fail("body", "expected at least one [[body]] table");
  BodyNames names;
  std::vector<core::Body> bodies;
  bodies.reserve(body_tables.size());
  for (const Table& t : body_tables) bodies.push_back(read_body(t, names));

  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  if (!settings.g_W.isZero(0.0)) {
    // Flexible bodies take their gravity loads from the inertia invariants (m g, s̃_t Aᵀ g,
    // Sᵀ Aᵀ g; core/gravity.cpp); the mass and centre given here are used for rigid bodies.
    std::vector<core::UniformGravity::BodyMass> masses;
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      masses.push_back({static_cast<int>(i), bodies[i].mass(), bodies[i].description().p_BoBcm_B});
    }
    elements.push_back(std::make_unique<core::UniformGravity>(settings.g_W, std::move(masses)));
  }
  for (const Table& t : root.tables("load", "[[load]] tables")) {
    elements.push_back(read_load(t, names));
  }
  for (const Table& t : root.tables("potential", "[[potential]] tables")) {
    elements.push_back(read_potential(t, names, bodies));
  }
  for (const Table& t : root.tables("contact", "[[contact]] tables")) {
    elements.push_back(read_contact(t, names, bodies));
  }
  for (const Table& t : root.tables("joint", "[[joint]] tables")) {
    elements.push_back(read_joint(t, names));
  }

  Scene scene;
  scene.name = std::move(settings.name);
  scene.file = file;
  scene.description = std::move(settings.description);
  scene.end_time = settings.end_time;
  scene.output_step = settings.output_step;
  scene.model = std::make_unique<core::Model>(std::move(bodies), std::move(elements), formulation);
  check_initial_evaluation(*scene.model, root, body_tables);
  return scene;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file_name,
                  core::FlexibleFormulation formulation) {
  try {
    const toml::value document = scene_toml::parse(text, file_name);
    return read_document(document, file_name, formulation);
  } catch (const core::InputError&) {
    throw;
  } catch (const toml::exception& e) {
    // Not expected (every access is type-checked first): keep toml11's line.
    throw core::InputError(file_name, static_cast<int>(e.location().line()), "", e.what());
  } catch (const std::exception& e) {
    throw core::InputError(file_name, 0, "", std::string("cannot read the scene: ") + e.what());
  }
}

Scene read_scene(const std::string& path, core::FlexibleFormulation formulation) {
  std::string text;
  try {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
      throw core::InputError(path, 0, "", "is a directory; expected a scene file (TOML)");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw core::InputError(path, 0, "", "cannot open the scene file");
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw core::InputError(path, 0, "", "cannot read the scene file");
    text = std::move(buffer).str();
  } catch (const core::InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw core::InputError(path, 0, "", std::string("cannot read the scene file: ") + e.what());
  }
  return parse_scene(text, path, formulation);
}

}  // namespace flexref::scene
