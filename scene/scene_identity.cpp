#include "scene/scene_identity.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <utility>

namespace flexref::scene {
namespace {

void append_canonical(const toml::value& value, std::string& out, bool scene_root);

void append_table(const toml::table& table, std::string& out, bool scene_root) {
  std::vector<const std::pair<const std::string, toml::value>*> entries;
  for (const auto& entry : table) entries.push_back(&entry);
  std::sort(entries.begin(), entries.end(),
            [](const auto* a, const auto* b) { return a->first < b->first; });
  out += '{';
  for (const auto* entry : entries) {
    const bool scene_table = scene_root && entry->first == "scene" && entry->second.is_table();
    out += std::to_string(entry->first.size()) + ':' + entry->first + '=';
    if (scene_table) {
      // The run settings of [scene] are not the physics (see the header).
      toml::table physics = entry->second.as_table();
      for (const char* key : {"name", "description", "end_time", "output_step"}) {
        physics.erase(key);
      }
      append_table(physics, out, false);
    } else {
      append_canonical(entry->second, out, false);
    }
    out += ';';
  }
  out += '}';
}

void append_number(double x, std::string& out) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%a", x);
  out += 'n';
  out += buffer;
}

void append_canonical(const toml::value& value, std::string& out, bool scene_root) {
  switch (value.type()) {
    case toml::value_t::table:
      append_table(value.as_table(), out, scene_root);
      return;
    case toml::value_t::array:
      out += '[';
      for (const toml::value& element : value.as_array()) {
        append_canonical(element, out, false);
        out += ',';
      }
      out += ']';
      return;
    case toml::value_t::integer:
      // The reader takes integers as numbers wherever a number is expected (`mass = 2`), and
      // refuses those a double cannot hold exactly.
      append_number(static_cast<double>(value.as_integer()), out);
      return;
    case toml::value_t::floating:
      append_number(value.as_floating(), out);
      return;
    case toml::value_t::boolean:
      out += value.as_boolean() ? "true" : "false";
      return;
    case toml::value_t::string: {
      const std::string& s = value.as_string().str;
      out += 's' + std::to_string(s.size()) + ':' + s;
      return;
    }
    case toml::value_t::empty:
      out += "empty";
      return;
    default: {
      // Dates and times (no scene key takes one): their TOML text.
      const std::string text = toml::format(value);
      out += 'd' + std::to_string(text.size()) + ':' + text;
      return;
    }
  }
}

std::uint64_t fnv1a(const std::string& text, std::uint64_t hash) {
  constexpr std::uint64_t kPrime = 0x100000001b3ULL;
  for (const char c : text) {
    hash ^= static_cast<unsigned char>(c);
    hash *= kPrime;
  }
  return hash;
}

}  // namespace

std::string canonical_text(const toml::value& value) {
  std::string out;
  append_canonical(value, out, false);
  return out;
}

std::string scene_hash(const toml::value& scene_document,
                       const std::vector<toml::value>& modal_documents) {
  constexpr std::uint64_t kOffsetBasis = 0xcbf29ce484222325ULL;
  std::string text;
  append_canonical(scene_document, text, true);
  for (const toml::value& modal : modal_documents) {
    text += "|modal:";
    append_canonical(modal, text, false);
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "fnv1a64:%016llx",
                static_cast<unsigned long long>(fnv1a(text, kOffsetBasis)));
  return buffer;
}

}  // namespace flexref::scene
