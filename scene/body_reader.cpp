/// \file body_reader.cpp
/// [[body]] tables (scenes/README.md): mass and inertia, motion (free, pivot, prescribed), the
/// initial state, tracked points, and a flexible body's modes from [body.beam] or a modal-data
/// file (docs/modal_data.md), into a BodySpec.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "flexible/beam_model.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/modal_data_reader.hpp"
#include "scene/reader_parts.hpp"

namespace flexref::scene::detail {
namespace {

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

/// [body.beam]: the built-in beam finite-element model (flexible/beam_model.hpp).
flexible::ModalData read_beam(const Table& body, BeamSpec& spec) {
  const std::optional<Table> b =
      body.table("beam", "a table [body.beam] with length, elements, EA, EI, rho_A and modes");
  b->check_keys({"length", "elements", "EA", "EI", "EI_y", "EI_z", "GJ", "rho_A", "boundary",
                 "origin", "modes", "families", "damping_ratio", "geometric_stiffening"});
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
  constexpr std::array<flexible::BeamBoundary, 4> boundaries = {
      flexible::BeamBoundary::kClampedFree, flexible::BeamBoundary::kFreeFree,
      flexible::BeamBoundary::kClampedPinned, flexible::BeamBoundary::kClampedClamped};
  p.boundary = boundaries[static_cast<std::size_t>(b->choice(
      "boundary", {"clamped-free", "free-free", "clamped-pinned", "clamped-clamped"}, 0))];
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
  spec.geometric_stiffening = b->boolean_or(
      "geometric_stiffening", false,
      "true or false (geometric stiffening by foreshortening; docs/geometric_stiffening.md)");
  if (spec.geometric_stiffening && p.boundary != flexible::BeamBoundary::kClampedFree) {
    b->fail("geometric_stiffening",
            "geometric stiffening needs boundary = \"clamped-free\" (the foreshortening is "
            "measured from the clamped root; docs/geometric_stiffening.md)");
  }
  flexible::ModalData data;
  try {
    data = flexible::make_beam_modal_data(p, modes, filter,
                                          flexible::BeamModeNormalization::kUnitModalMass,
                                          spec.geometric_stiffening);
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
      spec.damping_ratio = data.damping_ratio;
    } else {
      data.damping_ratio.setConstant(data.mode_count(),
                                     b->to_number(v, "damping_ratio", Sign::kNonNegative,
                                                  expected + " or an array of one per mode"));
      spec.damping_ratio = Eigen::VectorXd::Constant(1, data.damping_ratio(0));
    }
  }
  spec.parameters = p;
  spec.modes = modes;
  spec.filter = filter;
  return data;
}
/// `modal = "file.toml"`: a modal-data file (docs/modal_data.md), relative to the scene.
flexible::ModalData read_modal_file(const Table& body, std::string& resolved) {
  const std::string given = body.string("modal", "the path of a modal-data file (TOML)");
  if (given.empty()) body.fail("modal", "expected the path of a modal-data file, got \"\"");
  const std::string path = relative_to(body.file(), given);
  resolved = path;
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

}  // namespace

BodySpec read_body(const Table& t, BodyNames& names) {
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
  BodySpec spec;
  spec.source = source_of(t);
  if (t.has("beam")) {
    spec.beam.emplace();
    flexible.emplace(core::FlexiblePart{read_beam(t, *spec.beam), {}, {}});
  }
  if (t.has("modal")) {
    flexible.emplace(core::FlexiblePart{read_modal_file(t, spec.modal_file), {}, {}});
  }
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

  // Constructing the body (build_model.hpp) checks what remains: the inertia's derived data
  // and a flexible body's undeformed inertia.
  spec.description = std::move(d);
  return spec;
}

}  // namespace flexref::scene::detail
