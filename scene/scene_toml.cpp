#include "scene/scene_toml.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <tuple>
#include <utility>

#include "core/error.hpp"

namespace flexref::scene::scene_toml {
namespace {

// Integers beyond ±2⁵³ are not exactly representable as doubles, and toml11 3.7 silently
// clamps decimal, hex and octal literals beyond ±(2⁶³ − 1) (and wraps long binary ones):
// no physical quantity of a scene needs them, so they are rejected.
constexpr std::int64_t kMaxExactInteger = std::int64_t{1} << 53;

int line_number(const toml::source_location& location) {
  return static_cast<int>(std::min<std::uint_least32_t>(location.line(), INT_MAX));
}

std::string type_name(const toml::value& value) {
  switch (value.type()) {
    case toml::value_t::boolean:
      return "a boolean";
    case toml::value_t::integer:
      return "an integer";
    case toml::value_t::floating:
      return "a number";
    case toml::value_t::string:
      return "a string";
    case toml::value_t::offset_datetime:
    case toml::value_t::local_datetime:
    case toml::value_t::local_date:
    case toml::value_t::local_time:
      return "a date/time";
    case toml::value_t::array: {
      const std::size_t n = value.as_array().size();
      return "an array of " + std::to_string(n) + (n == 1 ? " element" : " elements");
    }
    case toml::value_t::table:
      return "a table";
    case toml::value_t::empty:
      return "nothing";
  }
  return "an unknown value";
}

std::string quoted_list(std::initializer_list<std::string_view> names) {
  std::string out;
  for (const std::string_view n : names) {
    if (!out.empty()) out += ", ";
    out += '"';
    out += n;
    out += '"';
  }
  return out;
}

std::string plain_list(std::initializer_list<std::string_view> names) {
  std::string out;
  for (const std::string_view n : names) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

bool contains(std::initializer_list<std::string_view> names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// toml11's syntax messages read "[error] toml::parse_array: missing array separator ...",
// followed by an excerpt of the file with a caret; keep the excerpt, drop the prefixes.
std::string syntax_message(const std::string& toml_what) {
  std::string first = toml_what.substr(0, toml_what.find('\n'));
  const std::string rest =
      first.size() < toml_what.size() ? toml_what.substr(first.size()) : std::string();
  constexpr std::string_view kError = "[error] ";
  if (first.starts_with(kError)) first.erase(0, kError.size());
  if (const auto colon = first.find(": ");
      colon != std::string::npos && first.find(' ') > colon &&
      (first.starts_with("toml::") || first.starts_with("parse_"))) {
    first.erase(0, colon + 2);
  }
  return "TOML syntax error: " + first + rest;
}

// Skips a string starting at text[i] (a quote) and returns the index of its last character;
// counts newlines of multi-line strings into `line`. Unterminated strings run to the end
// (toml11 then reports the syntax error).
std::size_t skip_string(const std::string& text, std::size_t i, int& line) {
  const char quote = text[i];
  const bool basic = quote == '"';
  const bool multi = text.compare(i, 3, std::string(3, quote)) == 0;
  std::size_t j = i + (multi ? 3 : 1);
  for (; j < text.size(); ++j) {
    const char c = text[j];
    if (c == '\n') {
      if (!multi) return j - 1;  // single-line strings end at the line end (syntax error)
      ++line;
    } else if (basic && c == '\\') {
      ++j;
      if (j < text.size() && text[j] == '\n') ++line;
    } else if (c == quote) {
      if (!multi) return j;
      if (text.compare(j, 3, std::string(3, quote)) == 0) {
        // Up to two quotes may precede the closing delimiter ("""a"""""): take the last three.
        std::size_t end = j + 2;
        while (end + 1 < text.size() && text[end + 1] == quote && end < j + 4) ++end;
        return end;
      }
    }
  }
  return text.size() - 1;
}

// Rejects documents whose nesting (open arrays and inline tables plus the components of the
// dotted keys that lead to them) exceeds kMaxNesting; see parse().
void check_nesting(const std::string& text, const std::string& file) {
  std::vector<int> open_key_dots;  // per open [ or {: dots of the key that opened it
  std::vector<char> open;          // '[' or '{'
  int enclosing_dots = 0;          // sum of open_key_dots
  int dots = 0;                    // dots of the key being read
  bool in_key = true;              // reading a key (line start, after '{' or ',' in a table)
  int line = 1;
  const auto check = [&] {
    if (static_cast<int>(open.size()) + enclosing_dots + dots > kMaxNesting) {
      throw core::InputError(file, line, "",
                             "arrays, inline tables or dotted keys nested deeper than " +
                                 std::to_string(kMaxNesting) + " levels");
    }
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      if (open.empty()) {
        in_key = true;
        dots = 0;
      }
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      i = skip_string(text, i, line);
    } else if (in_key) {
      if (c == '.') {
        ++dots;
        check();
      } else if (c == '=') {
        in_key = false;
      } else if (c == '}' && !open.empty() && open.back() == '{') {  // empty inline table
        dots = open_key_dots.back();
        enclosing_dots -= dots;
        open_key_dots.pop_back();
        open.pop_back();
        in_key = false;
      }
    } else if (c == '[' || c == '{') {
      open.push_back(c);
      open_key_dots.push_back(dots);
      enclosing_dots += dots;
      dots = 0;
      in_key = c == '{';
      check();
    } else if ((c == ']' || c == '}') && !open.empty()) {
      dots = open_key_dots.back();
      enclosing_dots -= dots;
      open_key_dots.pop_back();
      open.pop_back();
    } else if (c == ',' && !open.empty() && open.back() == '{') {
      in_key = true;
      dots = 0;
    }
  }
}

bool is_name_character(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-';
}

}  // namespace

int line_of(const toml::value& value) { return line_number(value.location()); }

std::string source_text(const toml::value& value) {
  const toml::source_location location = value.location();
  const std::string& line = location.line_str();
  const std::size_t begin = location.column() > 0 ? location.column() - 1 : 0;
  const std::size_t size = location.region();
  if (begin > line.size() || size > line.size() - begin) return {};
  return line.substr(begin, size);
}

std::string describe(const toml::value& value) {
  constexpr std::size_t kMaxShown = 40;
  std::string text = source_text(value);
  if (value.is_table() && !text.starts_with("{")) text.clear();  // a [header]
  if (text.empty()) return type_name(value);
  if (text.size() > kMaxShown) text = text.substr(0, kMaxShown) + "...";
  return text + " (" + type_name(value) + ")";
}

toml::value parse(const std::string& text, const std::string& file) {
  check_nesting(text, file);
  std::istringstream in(text);
  try {
    return toml::parse(in, file);
  } catch (const toml::exception& e) {
    throw core::InputError(file, line_number(e.location()), "", syntax_message(e.what()));
  } catch (const std::exception& e) {
    throw core::InputError(file, 0, "", std::string("cannot parse as TOML: ") + e.what());
  }
}

Table::Table(const toml::value& table, const std::string& file, std::string path)
    : table_(&table), file_(&file), path_(std::move(path)) {}

int Table::line() const { return scene_toml::line_of(*table_); }

std::string Table::key_path(std::string_view key) const {
  if (path_.empty()) return std::string(key);
  return path_ + "." + std::string(key);
}

const toml::value* Table::find(std::string_view key) const {
  const toml::table& t = table_->as_table();
  const auto it = t.find(std::string(key));
  return it == t.end() ? nullptr : &it->second;
}

int Table::line_of(std::string_view key) const {
  const toml::value* v = find(key);
  return v != nullptr ? scene_toml::line_of(*v) : line();
}

void Table::fail(std::string_view key, const std::string& what) const {
  throw core::InputError(*file_, line_of(key), key_path(key), what);
}

void Table::fail_table(const std::string& what) const {
  throw core::InputError(*file_, line(), path_, what);
}

void Table::fail_at(const toml::value& value, std::string_view key, const std::string& what) const {
  throw core::InputError(*file_, scene_toml::line_of(value), key_path(key), what);
}

void Table::check_keys(std::initializer_list<std::string_view> known,
                       std::initializer_list<std::string_view> planned) const {
  using Offender = std::tuple<int, std::uint_least32_t, std::string>;
  std::vector<Offender> offenders;
  for (const auto& [key, value] : table_->as_table()) {
    if (!contains(known, key)) {
      offenders.emplace_back(scene_toml::line_of(value), value.location().column(), key);
    }
  }
  if (offenders.empty()) return;
  const std::string& key = std::get<2>(*std::min_element(offenders.begin(), offenders.end()));
  if (contains(planned, key)) {
    fail(key, "is reserved for a later version of flexref and not supported yet");
  }
  fail(key, "unknown key; expected one of: " + plain_list(known));
}

double Table::to_number(const toml::value& value, std::string_view key, Sign sign,
                        const std::string& expected) const {
  double x = 0.0;
  if (value.is_integer()) {
    const std::int64_t i = value.as_integer();
    std::string text = source_text(value);
    std::erase(text, '_');
    const bool long_binary =
        text.starts_with("0b") &&
        text.size() - std::min(text.find_first_not_of('0', 2), text.size()) > 53;
    if (i > kMaxExactInteger || i < -kMaxExactInteger || long_binary) {
      fail_at(value, key,
              "expected " + expected + ", got the integer " + describe(value) +
                  " beyond ±2^53 (write large values as floats)");
    }
    x = static_cast<double>(i);
  } else if (value.is_floating()) {
    x = value.as_floating();
    if (!std::isfinite(x)) {
      fail_at(value, key,
              "expected " + expected + ", got " + source_text(value) +
                  " (infinite and NaN values are not allowed)");
    }
    // toml11 turns literals beyond the double range into ±DBL_MAX: treat that as overflow.
    if (std::abs(x) == std::numeric_limits<double>::max()) {
      fail_at(value, key,
              "expected " + expected + ", got " + source_text(value) +
                  " (beyond the range of a double)");
    }
  } else {
    fail_at(value, key, "expected " + expected + ", got " + describe(value));
  }
  const bool ok = sign == Sign::kAny || (sign == Sign::kPositive && x > 0.0) ||
                  (sign == Sign::kNonNegative && x >= 0.0);
  if (!ok) fail_at(value, key, "expected " + expected + ", got " + source_text(value));
  return x;
}

double Table::number(std::string_view key, Sign sign, const std::string& expected) const {
  const toml::value* v = find(key);
  if (v == nullptr) fail(key, "required key is missing; expected " + expected);
  return to_number(*v, key, sign, expected);
}

double Table::number_or(std::string_view key, double fallback, Sign sign,
                        const std::string& expected) const {
  const toml::value* v = find(key);
  return v == nullptr ? fallback : to_number(*v, key, sign, expected);
}

std::optional<std::string> Table::optional_string(std::string_view key,
                                                  const std::string& expected) const {
  const toml::value* v = find(key);
  if (v == nullptr) return std::nullopt;
  if (!v->is_string()) fail(key, "expected " + expected + ", got " + describe(*v));
  return v->as_string().str;
}

bool Table::boolean_or(std::string_view key, bool fallback, const std::string& expected) const {
  const toml::value* v = find(key);
  if (v == nullptr) return fallback;
  if (!v->is_boolean()) fail(key, "expected " + expected + ", got " + describe(*v));
  return v->as_boolean();
}

std::string Table::string(std::string_view key, const std::string& expected) const {
  std::optional<std::string> s = optional_string(key, expected);
  if (!s) fail(key, "required key is missing; expected " + expected);
  return *std::move(s);
}

std::string Table::name(std::string_view key, const std::string& expected) const {
  std::string s = string(key, expected);
  if (s.empty() || !std::all_of(s.begin(), s.end(), is_name_character)) {
    fail(key, "expected " + expected + " (letters, digits, '_' and '-' only), got " +
                  describe(*find(key)));
  }
  return s;
}

int Table::choice(std::string_view key, std::initializer_list<std::string_view> choices,
                  int fallback, std::initializer_list<std::string_view> planned) const {
  const std::string expected = "one of " + quoted_list(choices);
  const toml::value* v = find(key);
  if (v == nullptr) {
    if (fallback >= 0) return fallback;
    fail(key, "required key is missing; expected " + expected);
  }
  if (!v->is_string()) fail(key, "expected " + expected + ", got " + describe(*v));
  const std::string& s = v->as_string().str;
  const auto it = std::find(choices.begin(), choices.end(), s);
  if (it != choices.end()) return static_cast<int>(it - choices.begin());
  if (contains(planned, s)) {
    fail(key, "\"" + s + "\" is planned but not supported yet; expected " + expected);
  }
  fail(key, "expected " + expected + ", got " + describe(*v));
}

template <int N>
Eigen::Matrix<double, N, 1> Table::fixed_vector(std::string_view key,
                                                const std::string& expected) const {
  const toml::value& v = *find(key);
  if (!v.is_array() || v.as_array().size() != static_cast<std::size_t>(N)) {
    fail(key, "expected " + expected + ", got " + describe(v));
  }
  Eigen::Matrix<double, N, 1> out;
  for (int i = 0; i < N; ++i) {
    out(i) = to_number(v.as_array()[static_cast<std::size_t>(i)], key, Sign::kAny,
                       "finite components in " + expected);
  }
  return out;
}

Eigen::Vector3d Table::vector3(std::string_view key, const std::string& expected) const {
  if (!has(key)) fail(key, "required key is missing; expected " + expected);
  return fixed_vector<3>(key, expected);
}

Eigen::Vector3d Table::vector3_or(std::string_view key, const Eigen::Vector3d& fallback,
                                  const std::string& expected) const {
  return has(key) ? fixed_vector<3>(key, expected) : fallback;
}

Eigen::Vector4d Table::vector4_or(std::string_view key, const Eigen::Vector4d& fallback,
                                  const std::string& expected) const {
  return has(key) ? fixed_vector<4>(key, expected) : fallback;
}

std::vector<Table> Table::tables(std::string_view key, const std::string& expected) const {
  std::vector<Table> out;
  const toml::value* v = find(key);
  if (v == nullptr) return out;
  if (v->is_table()) {
    const std::string hint = path_.empty() ? "write [[" + std::string(key) + "]] for each element"
                                           : "write an array: " + std::string(key) + " = [{...}]";
    fail(key, "expected " + expected + ", got a single table (" + hint + ")");
  }
  if (!v->is_array()) fail(key, "expected " + expected + ", got " + describe(*v));
  const toml::array& elements = v->as_array();
  out.reserve(elements.size());
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (!elements[i].is_table()) {
      fail_at(elements[i], key,
              "expected " + expected + ", but element " + std::to_string(i + 1) + " is " +
                  describe(elements[i]));
    }
    out.emplace_back(elements[i], *file_, key_path(key) + "[" + std::to_string(i + 1) + "]");
  }
  return out;
}

std::optional<Table> Table::table(std::string_view key, const std::string& expected) const {
  const toml::value* v = find(key);
  if (v == nullptr) return std::nullopt;
  if (!v->is_table()) fail(key, "expected " + expected + ", got " + describe(*v));
  return Table(*v, *file_, key_path(key));
}

}  // namespace flexref::scene::scene_toml
