/// \file reader_support.cpp
/// Checked readers shared by the parts of the scene reader (reader_parts.hpp).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "scene/reader_parts.hpp"

namespace flexref::scene::detail {

std::string format(double x) {
  std::ostringstream out;
  out.precision(10);
  out << x;
  return out.str();
}

/// A required (or, with fallback >= 0, optional) TOML integer in [1, max].
int read_count(const Table& t, std::string_view key, int max, const std::string& expected,
               int fallback) {
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

/// The scene file's directory joined with a path given in it (absolute paths stay).
std::string relative_to(const std::string& scene_file, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute()) return path;
  return (std::filesystem::path(scene_file).parent_path() / p).lexically_normal().string();
}

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

SpecSource source_of(const Table& t) { return SpecSource{t.file(), t.line(), t.path()}; }

void refuse_ground_first_end(const Table& t, const std::string& what) {
  const toml::value* a = t.find("body_a");
  if (a == nullptr || !a->is_string() || a->as_string() != "ground") return;
  const toml::value* b = t.find("body_b");
  const std::string other =
      b != nullptr && b->is_string() ? "\"" + std::string(b->as_string()) + "\"" : "the body";
  std::string swapped = "point_a and point_b";
  for (const char* key : {"node", "axis"}) {
    if (t.has(std::string(key) + "_a") || t.has(std::string(key) + "_b")) {
      swapped += std::string(", ") + key + "_a and " + key + "_b";
    }
  }
  const std::string why = what == "joint" ? " (its reactions are reported on it)" : "";
  t.fail("body_a", "the first end of a " + what + " must be a body" + why +
                       "; the ground can only be the second end: swap the ends, body_a = " + other +
                       " and body_b = \"ground\", exchanging " + swapped);
}

int read_node(const Table& t, std::string_view key, const BodySpec& body) {
  const std::optional<core::FlexiblePart>& part = body.description.flexible;
  if (!part) {
    t.fail(key, "applies only to flexible bodies (beam or modal); body \"" + body.description.name +
                    "\" is rigid");
  }
  const std::string node = t.string(key, "the name of a node of the body's modal data");
  const std::vector<std::string>& names = part->modal.node_names;
  const auto it = std::find(names.begin(), names.end(), node);
  if (it == names.end()) {
    const std::string known = names.empty() ? std::string(" (the modal data has no node names)")
                                            : "; expected a node name such as \"" + names.front() +
                                                  "\" … \"" + names.back() + "\"";
    t.fail(key, "no node named \"" + node + "\" in the modal data of body \"" +
                    body.description.name + "\"" + known);
  }
  return static_cast<int>(it - names.begin());
}

}  // namespace flexref::scene::detail
