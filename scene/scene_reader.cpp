#include "scene/scene_reader.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "io/input_file.hpp"
#include "scene/build_model.hpp"
#include "scene/initial_energy.hpp"
#include "scene/reader_parts.hpp"
#include "scene/scene_identity.hpp"
#include "scene/scene_toml.hpp"

namespace flexref::scene {
namespace {

using detail::BodyNames;
using detail::format;
using detail::read_body;
using detail::read_contact;
using detail::read_joint;
using detail::read_load;
using detail::read_potential;
using detail::Sign;
using detail::Table;

// More output intervals than this is a typing error (end_time/output_step): 1e7 rows of a
// CSV are gigabytes, and the output-time grid is allocated up front.
constexpr double kMaxOutputIntervals = 1e7;

struct SceneSettings {
  std::string name;
  std::string description;
  double end_time = 0.0;
  double output_step = 0.0;
  Eigen::Vector3d g_W = Eigen::Vector3d::Zero();
  bool project_initial_state = false;
};

SceneSettings read_settings(const Table& root) {
  const std::optional<Table> scene = root.table("scene", "a [scene] table");
  if (!scene) {
    root.fail("scene",
              "required table is missing; expected a [scene] table with name, end_time and "
              "output_step");
  }
  scene->check_keys(
      {"name", "description", "end_time", "output_step", "gravity", "project_initial_state"});
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
  s.project_initial_state =
      scene->boolean_or("project_initial_state", false,
                        "true or false: project an initial state that violates the ideal joints");
  return s;
}

[[noreturn]] void fail_at_source(const SpecError& e, const Table& root);

void check_initial_evaluation(const SceneSpec& spec, const core::Model& model, const Table& root,
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
    // At the part that makes it: a body's spin, velocity or centre of mass, a potential's
    // constants, the gravity.
    const EnergyPart part = largest_initial_energy(spec, model);
    const std::string why = "the initial " + part.what + " is not finite (" + format(part.energy) +
                            " J: values too large or too small); expected values whose products "
                            "stay within the range of a double";
    if (part.source.path == "scene") {
      const std::optional<Table> scene = root.table("scene", "a [scene] table");
      if (scene) scene->fail(part.key, why);
    }
    if (!part.source.path.empty()) fail_at_source(SpecError(part.source, part.key, why), root);
    root.fail("scene", why);
  }
}

/// A SpecError from build_model, at the key of the table it names.
[[noreturn]] void fail_at_source(const SpecError& e, const Table& root) {
  const SpecSource& where = e.source();
  const std::string& path = where.path;
  // The spec's table path: find the table again to report through scene_toml's messages.
  const auto bracket = path.find('[');
  if (bracket != std::string::npos) {
    const std::string key = path.substr(0, bracket);
    const int index = std::stoi(path.substr(bracket + 1));
    const std::vector<Table> tables = root.tables(key, "[[" + key + "]] tables");
    if (index >= 1 && static_cast<std::size_t>(index) <= tables.size()) {
      const Table& t = tables[static_cast<std::size_t>(index - 1)];
      if (e.key().empty()) t.fail_table(e.what());
      t.fail(e.key(), e.what());
    }
  }
  throw core::InputError(where.file, where.line, path, e.what());
}

SceneSpec read_spec(const toml::value& document, const std::string& file) {
  const Table root(document, file, "");
  root.check_keys({"scene", "body", "load", "potential", "contact", "joint", "spring"});
  SceneSettings settings = read_settings(root);
  SceneSpec spec;
  spec.name = std::move(settings.name);
  spec.file = file;
  spec.description = std::move(settings.description);
  spec.end_time = settings.end_time;
  spec.output_step = settings.output_step;
  spec.g_W = settings.g_W;
  spec.project_initial_state = settings.project_initial_state;

  const std::vector<Table> body_tables = root.tables("body", "[[body]] tables");
  if (body_tables.empty()) root.fail("body", "expected at least one [[body]] table");
  BodyNames names;
  for (const Table& t : body_tables) spec.bodies.push_back(read_body(t, names));
  for (const Table& t : root.tables("load", "[[load]] tables")) {
    spec.loads.push_back(read_load(t, names, spec.bodies));
  }
  for (const Table& t : root.tables("potential", "[[potential]] tables")) {
    spec.potentials.push_back(read_potential(t, names, spec.bodies));
  }
  for (const Table& t : root.tables("contact", "[[contact]] tables")) {
    spec.contacts.push_back(read_contact(t, names, spec.bodies));
    const std::string& name = spec.contacts.back().name;
    for (std::size_t c = 0; c + 1 < spec.contacts.size() && !name.empty(); ++c) {
      if (spec.contacts[c].name == name) {
        t.fail("name", "duplicate contact name \"" + name + "\"; expected a unique name");
      }
    }
  }
  // Joint names (ideal and bushing) are unique among the [[joint]] tables, spring names among
  // the [[spring]] tables: messages name each element by its kind and name.
  const auto unique = [](const Table& t, std::vector<std::string>& taken, const std::string& name,
                         const char* what) {
    if (name.empty()) return;
    if (std::find(taken.begin(), taken.end(), name) != taken.end()) {
      t.fail("name",
             std::string("duplicate ") + what + " name \"" + name + "\"; expected a unique name");
    }
    taken.push_back(name);
  };
  std::vector<std::string> joint_names;
  int joint_index = 0;
  for (const Table& t : root.tables("joint", "[[joint]] tables")) {
    ++joint_index;
    const std::optional<std::string> model =
        t.optional_string("model", "\"bushing\" (a compliant joint) or \"ideal\" (a constraint)");
    if (model && *model == "ideal") {
      spec.ideal_joints.push_back(read_ideal_joint(t, names, spec.bodies, joint_index));
      unique(t, joint_names, spec.ideal_joints.back().joint.name, "joint");
    } else {
      if (model && *model != "bushing") {
        t.fail("model", "expected \"bushing\" or \"ideal\", got \"" + *model + "\"");
      }
      spec.joints.push_back(read_joint(t, names));
      unique(t, joint_names, spec.joints.back().name, "joint");
    }
  }
  std::vector<std::string> spring_names;
  for (const Table& t : root.tables("spring", "[[spring]] tables")) {
    spec.springs.push_back(read_spring(t, names));
    unique(t, spring_names, spec.springs.back().name, "spring");
  }
  return spec;
}

Scene read_document(const toml::value& document, const std::string& file,
                    core::FlexibleFormulation formulation) {
  Scene scene;
  scene.spec = read_spec(document, file);
  const Table root(document, file, "");
  try {
    scene.model = std::make_unique<core::Model>(build_model(scene.spec, formulation));
  } catch (const SpecError& e) {
    fail_at_source(e, root);
  }
  scene.name = scene.spec.name;
  scene.file = file;
  scene.description = scene.spec.description;
  scene.end_time = scene.spec.end_time;
  scene.output_step = scene.spec.output_step;
  check_initial_evaluation(scene.spec, *scene.model, root, root.tables("body", "[[body]] tables"));
  // The modal-data files were read and parsed above (read_modal_data); their documents again
  // for the hash.
  std::vector<toml::value> modal_documents;
  for (const BodySpec& body : scene.spec.bodies) {
    if (body.modal_file.empty()) continue;
    std::ifstream in(body.modal_file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    modal_documents.push_back(scene_toml::parse(text.str(), body.modal_file));
  }
  scene.hash = scene_hash(document, modal_documents);
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
    io::InputFile in(path, "the scene file (TOML)");
    if (!in.is_open()) throw core::InputError(path, 0, "", in.error());
    text = in.read_all();
  } catch (const core::InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw core::InputError(path, 0, "", std::string("cannot read the scene file: ") + e.what());
  }
  return parse_scene(text, path, formulation);
}

}  // namespace flexref::scene
