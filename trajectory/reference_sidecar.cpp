#include "trajectory/reference_sidecar.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <toml.hpp>
#include <utility>

#include "core/error.hpp"
#include "io/input_file.hpp"
#include "io/output_file.hpp"

namespace flexref::trajectory {

ReferenceSidecar read_reference_sidecar(const std::string& csv_path) {
  ReferenceSidecar out;
  std::error_code ec;
  std::string beside_target = csv_path + ".meta.toml";
  try {
    beside_target = io::follow_links(csv_path).string() + ".meta.toml";
  } catch (const io::OutputError&) {
    // A loop of links: the CSV itself cannot be read either, and says so.
  }
  out.path = std::filesystem::exists(beside_target, ec) ? beside_target : csv_path + ".meta.toml";
  if (!std::filesystem::exists(out.path, ec)) return out;
  out.found = true;
  io::InputFile in(out.path, "a metadata sidecar (TOML)");
  if (!in.is_open()) throw core::InputError(out.path, 0, "", in.error());
  toml::value doc;
  try {
    // From a string: toml11 measures a stream by seeking, which a descriptor's stream cannot.
    std::istringstream text(in.read_all());
    doc = toml::parse(text, out.path);
  } catch (const std::exception& e) {
    throw core::InputError(out.path, 0, "", std::string("not a readable TOML file: ") + e.what());
  }
  if (!doc.is_table()) return out;
  const auto& root = doc.as_table();
  if (const auto it = root.find("scene"); it != root.end() && it->second.is_table()) {
    const auto& t = it->second.as_table();
    for (auto [key, field] :
         {std::pair{"name", &out.scene.name}, std::pair{"hash", &out.scene.hash},
          std::pair{"file", &out.scene.file}, std::pair{"model", &out.scene.model}}) {
      if (const auto v = t.find(key); v != t.end() && v->second.is_string()) {
        *field = v->second.as_string().str;
      }
    }
  }
  if (const auto it = root.find("integrator"); it != root.end() && it->second.is_table()) {
    const auto& t = it->second.as_table();
    if (const auto k = t.find("kind"); k != t.end() && k->second.is_string()) {
      out.kind = k->second.as_string().str;
    }
    if (const auto s = t.find("solver"); s != t.end() && s->second.is_string()) {
      out.solver = s->second.as_string().str;
    }
    if (const auto r = t.find("rtol"); r != t.end() && r->second.is_floating()) {
      out.rtol = r->second.as_floating();
    }
    if (const auto p = t.find("precision"); p != t.end()) {
      const std::string name = p->second.is_string() ? p->second.as_string().str : "";
      if (name != "double" && name != "extended" && name != "quad") {
        throw core::InputError(out.path, 0, "integrator.precision",
                               "expected \"double\", \"extended\" or \"quad\"");
      }
      out.precision = name;
    }
  }
  const auto it = root.find("error_estimate");
  if (it == root.end()) return out;
  if (!it->second.is_table()) {
    throw core::InputError(out.path, 0, "error_estimate", "expected a table");
  }
  const auto& e = it->second.as_table();
  const auto est = e.find("estimate");
  const auto metric = e.find("metric");
  if (est == e.end() || !(est->second.is_floating() || est->second.is_integer())) {
    throw core::InputError(out.path, 0, "error_estimate.estimate", "expected a number");
  }
  out.estimate = est->second.is_floating() ? est->second.as_floating()
                                           : static_cast<double>(est->second.as_integer());
  // +inf is what `flexref reference` writes when no check was usable (the error is unknown).
  if (std::isnan(out.estimate) || out.estimate < 0.0) {
    throw core::InputError(out.path, 0, "error_estimate.estimate",
                           "expected a non-negative error estimate (inf: unknown)");
  }
  if (metric == e.end() || !metric->second.is_string()) {
    throw core::InputError(out.path, 0, "error_estimate.metric", "expected the metric's name");
  }
  out.metric = metric->second.as_string().str;
  if (const auto m = e.find("method"); m != e.end() && m->second.is_string()) {
    out.estimate_method = m->second.as_string().str;
  }
  for (const auto& [key, target] :
       {std::pair<const char*, double*>{"energy_balance", &out.energy_balance},
        std::pair<const char*, double*>{"energy_estimate", &out.energy_estimate}}) {
    const auto v = e.find(key);
    if (v == e.end()) continue;
    if (!(v->second.is_floating() || v->second.is_integer())) {
      throw core::InputError(out.path, 0, std::string("error_estimate.") + key,
                             "expected a number");
    }
    *target = v->second.is_floating() ? v->second.as_floating()
                                      : static_cast<double>(v->second.as_integer());
  }
  out.has_estimate = true;
  return out;
}

std::string scene_mismatch(const SceneIdentity& a, const std::string& a_what,
                           const SceneIdentity& b, const std::string& b_what) {
  if (a.name.empty() || b.name.empty()) return "";
  const bool hashes = !a.hash.empty() && !b.hash.empty();
  if (hashes ? a.hash == b.hash : a.name == b.name) return "";
  const auto describe = [](const SceneIdentity& s) {
    std::string details = s.hash.empty() ? "no hash recorded" : s.hash;
    if (!s.file.empty()) details += ", " + s.file;
    return s.name + " (" + details + ")";
  };
  return a_what + " is of scene " + describe(a) + " but " + b_what + " of scene " + describe(b) +
         (a.name == b.name ? ": the same name, different physics (the scene was edited)"
                           : ": different scenes");
}

bool is_certified(double error, double estimate) {
  return error >= kCertificationFactor * estimate;
}

}  // namespace flexref::trajectory
