#pragma once
/// \file reader_parts.hpp
/// The scene reader's parts (internal to scene/): one reader per concept — bodies
/// (body_reader.cpp), loads and potentials (load_reader.cpp), contacts and joints
/// (contact_reader.cpp) — each turning its TOML tables into the specs of scene_spec.hpp, and the
/// checked helpers they share (reader_support.cpp). Every problem is a core::InputError at the
/// file, line and key (scene_toml.hpp).
#include <Eigen/Core>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/scene_spec.hpp"
#include "scene/scene_toml.hpp"

namespace flexref::scene::detail {

using scene_toml::Sign;
using scene_toml::Table;

// Orientations and unit vectors within this distance of unit norm are renormalized (decimal
// input of a unit quaternion is off by ~1e-16; hand-typed ones like [0.7071, 0.7071, 0, 0] by
// ~1e-5 are not, they are rejected with the norm they have).
inline constexpr double kOrientationTolerance = 1e-6;

/// A number in messages (10 significant digits).
std::string format(double x);

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

/// A required (or, with fallback >= 0, optional) TOML integer in [1, max].
int read_count(const Table& t, std::string_view key, int max, const std::string& expected,
               int fallback = -1);
/// An array of exactly n finite numbers (modal coordinates, damping ratios).
Eigen::VectorXd read_vector(const Table& t, std::string_view key, Eigen::Index n, Sign sign,
                            const std::string& expected);
/// The scene file's directory joined with a path given in it (absolute paths stay).
std::string relative_to(const std::string& scene_file, const std::string& path);
/// A unit vector: renormalized when within kOrientationTolerance of unit norm, else an error.
Eigen::Vector3d read_unit(const Table& t, std::string_view key, const Eigen::Vector3d* fallback,
                          const std::string& expected);
/// `single` (one 3-vector) or `plural` (an array of 3-vectors), exactly one of them.
std::vector<Eigen::Vector3d> read_vector_list(const Table& t, std::string_view single,
                                              std::string_view plural, const std::string& expected);
/// Rejects keys that do not apply to the chosen kind or law (check_keys accepts every key
/// that some kind uses).
void reject_keys(const Table& t, std::initializer_list<std::string_view> keys,
                 const std::string& why);
/// The table's file, line and path, for specs.
SpecSource source_of(const Table& t);

/// Refuses body_a = "ground" in a [[joint]] or [[spring]] table (`what`: "joint", "spring"):
/// the first end is always a body (a joint's reactions are reported on it), and "ground" names
/// the world only as the second end. The message says to swap the ends.
void refuse_ground_first_end(const Table& t, const std::string& what);

/// The node of `body`'s modal data that `key` names (a node name), failing at the key when the
/// body is rigid or has no such node.
int read_node(const Table& t, std::string_view key, const BodySpec& body);

BodySpec read_body(const Table& t, BodyNames& names);
LoadSpec read_load(const Table& t, const BodyNames& names, const std::vector<BodySpec>& bodies);
/// Checks the charges' initial positions against the bodies' initial states.
PotentialSpec read_potential(const Table& t, const BodyNames& names,
                             const std::vector<BodySpec>& bodies);
ContactSpec read_contact(const Table& t, const BodyNames& names,
                         const std::vector<BodySpec>& bodies);
JointSpec read_joint(const Table& t, const BodyNames& names);
/// A [[joint]] table with model = "ideal"; `index` is its position among the [[joint]] tables
/// (from 1), the default name "joint<index>".
IdealJointSceneSpec read_ideal_joint(const Table& t, const BodyNames& names,
                                     const std::vector<BodySpec>& bodies, int index);
SpringSpec read_spring(const Table& t, const BodyNames& names);

}  // namespace flexref::scene::detail
