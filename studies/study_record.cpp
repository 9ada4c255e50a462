#include "studies/study_record.hpp"

#include <sundials/sundials_config.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <boost/version.hpp>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <toml.hpp>

#include "io/output_file.hpp"

namespace flexref::studies {
namespace {

bool is_bare_key(const std::string& key) {
  if (key.empty()) return false;
  return std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

// Unlimited width: toml11 writes a one-line basic string with quotes, backslashes and control
// characters escaped (a finite width folds long strings and those with newlines or quotes into
// multi-line strings).
std::string toml_string(const std::string& s) {
  return toml::format(toml::value(s), std::numeric_limits<std::size_t>::max());
}

struct ValueFormatter {
  std::string operator()(double x) const { return toml_float(x); }
  std::string operator()(long long x) const { return std::to_string(x); }
  std::string operator()(bool x) const { return x ? "true" : "false"; }
  std::string operator()(const std::string& s) const { return toml_string(s); }
  std::string operator()(const std::vector<double>& v) const {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + toml_float(v[i]);
    return out + "]";
  }
  std::string operator()(const std::vector<std::string>& v) const {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + toml_string(v[i]);
    return out + "]";
  }
};

}  // namespace

std::string toml_float(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::array<char, 64> buffer{};
  const auto [end, ec] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), x);
  std::string text(buffer.data(), ec == std::errc{} ? end : buffer.data());
  // TOML floats need a fraction or an exponent: "2" would read back as an integer.
  if (text.find_first_of(".eE") == std::string::npos) text += ".0";
  return text;
}

const StudyRecord::Value* StudyRecord::Table::find(const std::string& key) const {
  for (const auto& [k, v] : entries_) {
    if (k == key) return &v;
  }
  return nullptr;
}

StudyRecord::Table& StudyRecord::Table::put(const std::string& key, Value value) {
  if (!is_bare_key(key)) {
    throw std::invalid_argument("record key \"" + key +
                                "\" is not a bare TOML key (letters, digits, '_', '-')");
  }
  for (auto& [k, v] : entries_) {
    if (k == key) {
      v = std::move(value);
      return *this;
    }
  }
  entries_.emplace_back(key, std::move(value));
  return *this;
}

namespace {

bool is_dotted_key(const std::string& key) {
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    if (!is_bare_key(key.substr(start, dot == std::string::npos ? dot : dot - start))) return false;
    if (dot == std::string::npos) return true;
    start = dot + 1;
  }
}

}  // namespace

StudyRecord::Table& StudyRecord::append(const std::string& name) {
  if (!is_dotted_key(name)) {
    throw std::invalid_argument("record array \"" + name + "\" is not a dotted bare TOML key");
  }
  return tables_.emplace_back(name, true);
}

StudyRecord::Table& StudyRecord::table(const std::string& name) {
  for (Table& t : tables_) {
    if (t.name() == name && !t.is_array_element()) return t;
  }
  if (!is_bare_key(name)) {
    throw std::invalid_argument("record table \"" + name + "\" is not a bare TOML key");
  }
  return tables_.emplace_back(name);
}

const StudyRecord::Table* StudyRecord::find(const std::string& name) const {
  for (const Table& t : tables_) {
    if (t.name() == name) return &t;
  }
  return nullptr;
}

std::string StudyRecord::to_toml() const {
  std::string out;
  for (const Table& t : tables_) {
    if (!out.empty()) out += '\n';
    out += t.is_array_element() ? "[[" + t.name() + "]]\n" : '[' + t.name() + "]\n";
    for (const auto& [key, value] : t.entries()) {
      out += key + " = " + std::visit(ValueFormatter{}, value) + '\n';
    }
  }
  return out;
}

void StudyRecord::write(const std::string& path) const { io::write_output_file(path, to_toml()); }

void add_versions(StudyRecord& record) {
  std::ostringstream eigen;
  eigen << EIGEN_WORLD_VERSION << '.' << EIGEN_MAJOR_VERSION << '.' << EIGEN_MINOR_VERSION;
  std::ostringstream boost;
  boost << BOOST_VERSION / 100000 << '.' << BOOST_VERSION / 100 % 1000 << '.'
        << BOOST_VERSION % 100;
  record.table("versions")
      .set("flexref", "0.1.0")
      .set("compiler", __VERSION__)
      .set("eigen", eigen.str())
      .set("boost", boost.str())
      .set("sundials", SUNDIALS_VERSION);
}

}  // namespace flexref::studies
