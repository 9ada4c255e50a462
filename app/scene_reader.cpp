#include "app/scene_reader.hpp"

#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "app/scene_toml.hpp"
#include "core/applied_load.hpp"
#include "core/body.hpp"
#include "core/error.hpp"
#include "core/euler_parameters.hpp"
#include "core/gravity.hpp"
#include "core/point_charge_potential.hpp"
#include "core/time_profile.hpp"

namespace flexref::app {
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

std::vector<core::TrackedPoint> read_points(const Table& body) {
  std::vector<core::TrackedPoint> points;
  const std::string expected = "an array of points { name = \"...\", at = [x, y, z] }";
  for (const Table& p : body.tables("points", expected)) {
    p.check_keys({"name", "at"});
    core::TrackedPoint point;
    point.name = p.name("name", "a point name");
    for (const core::TrackedPoint& other : points) {
      if (other.name == point.name) {
        p.fail("name",
               "duplicate point name \"" + point.name + "\" in this body; expected a unique name");
      }
    }
    point.p_BoP_B = p.vector3("at", "the point [x, y, z] in m from the frame origin, body frame");
    points.push_back(std::move(point));
  }
  return points;
}

core::Body read_body(const Table& t, BodyNames& names) {
  t.check_keys({"name", "mass", "inertia", "center_of_mass", "motion", "pivot", "position",
                "orientation", "velocity", "angular_velocity", "points"},
               {"beam", "modal"});
  core::RigidBodyDescription d;
  d.name = t.name("name", "a body name");
  names.add(t, d.name);
  d.mass = t.number("mass", Sign::kPositive, "a positive mass in kg");
  if (!std::isfinite(1.0 / d.mass)) {
    t.fail("mass", "expected a positive mass in kg, got " + format(d.mass) +
                       " (too small: 1/mass overflows)");
  }
  d.I_Bcm_B = read_inertia(t);
  d.p_BoBcm_B = t.vector3_or("center_of_mass", Eigen::Vector3d::Zero(),
                             "the centre of mass [x, y, z] in m, body frame");
  const bool pivot = t.choice("motion", {"free", "pivot"}, 0, {"prescribed"}) == 1;
  d.motion = pivot ? core::MotionKind::kPivot : core::MotionKind::kFree;
  if (pivot) {
    d.p_BoPivot_B = t.vector3("pivot", "the pivot [x, y, z] in m, body frame (motion = \"pivot\")");
  } else if (t.has("pivot")) {
    t.fail("pivot", "applies only to motion = \"pivot\"; expected no pivot for a free body");
  }
  d.initial.p_WBo = t.vector3_or("position", Eigen::Vector3d::Zero(),
                                 "the frame origin's position [x, y, z] in m, world frame");
  const Eigen::Vector4d theta =
      t.vector4_or("orientation", core::identity_euler_parameters(),
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
  d.initial.w_WB_B = t.vector3_or("angular_velocity", Eigen::Vector3d::Zero(),
                                  "the angular velocity [wx, wy, wz] in rad/s, body frame");
  d.points = read_points(t);

  std::optional<core::Body> body;
  try {
    body.emplace(std::move(d));
  } catch (const core::InertiaRangeError&) {
    // The reference-point data core::Body derives (the parallel-axis shift to the pivot and
    // the inverse) can overflow for extreme but finite input: report it at the inertia.
    t.fail("inertia", std::string("the inertia about the ") + (pivot ? "pivot" : "centre of mass") +
                          " or its inverse is not finite (values too large or too small)");
  } catch (const std::exception& e) {
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
    const Eigen::Vector3d p_WP = init.p_WBo + core::rotation_matrix(init.theta_WB) * charge.p_BoP_B;
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
        !a.alpha_WB_B.allFinite()) {
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

Scene read_document(const toml::value& document, const std::string& file) {
  const Table root(document, file, "");
  root.check_keys({"scene", "body", "load", "potential"}, {"contact", "joint"});
  SceneSettings settings = read_settings(root);

  const std::vector<Table> body_tables = root.tables("body", "[[body]] tables");
  if (body_tables.empty()) root.fail("body", "expected at least one [[body]] table");
  BodyNames names;
  std::vector<core::Body> bodies;
  bodies.reserve(body_tables.size());
  for (const Table& t : body_tables) bodies.push_back(read_body(t, names));

  std::vector<std::unique_ptr<const core::ForceElement>> elements;
  if (!settings.g_W.isZero(0.0)) {
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

  Scene scene;
  scene.name = std::move(settings.name);
  scene.file = file;
  scene.description = std::move(settings.description);
  scene.end_time = settings.end_time;
  scene.output_step = settings.output_step;
  scene.model = std::make_unique<core::Model>(std::move(bodies), std::move(elements));
  check_initial_evaluation(*scene.model, root, body_tables);
  return scene;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file_name) {
  try {
    const toml::value document = scene_toml::parse(text, file_name);
    return read_document(document, file_name);
  } catch (const core::InputError&) {
    throw;
  } catch (const toml::exception& e) {
    // Not expected (every access is type-checked first): keep toml11's line.
    throw core::InputError(file_name, static_cast<int>(e.location().line()), "", e.what());
  } catch (const std::exception& e) {
    throw core::InputError(file_name, 0, "", std::string("cannot read the scene: ") + e.what());
  }
}

Scene read_scene(const std::string& path) {
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
  return parse_scene(text, path);
}

}  // namespace flexref::app
