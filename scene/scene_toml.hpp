#pragma once
/// \file scene_toml.hpp
/// Checked access to a parsed TOML document for the scene reader: every accessor either
/// returns a validated value or throws core::InputError naming the file, the line (toml11
/// source locations) and the key path, and saying what was expected and what was found.
/// No toml11 exception, nor any other, leaves these functions.
#include <Eigen/Core>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <toml.hpp>
#include <vector>

namespace flexref::scene::scene_toml {

/// Parses TOML text. Syntax errors become core::InputError with toml11's line and message;
/// documents nested deeper than kMaxNesting (arrays, inline tables, dotted keys) are
/// rejected before parsing, because toml11's recursive-descent parser would overflow the
/// stack on them.
toml::value parse(const std::string& text, const std::string& file);

inline constexpr int kMaxNesting = 32;

/// Sign constraints for numbers.
enum class Sign { kAny, kPositive, kNonNegative };

/// One TOML table of the scene with its key path ("" for the document, "scene",
/// "body[2]", "body[2].points[1]"; array indices count from 1 like the tables in the file).
class Table {
 public:
  Table(const toml::value& table, const std::string& file, std::string path);

  const std::string& path() const { return path_; }
  const std::string& file() const { return *file_; }
  /// Line of the table: its [header], the `{` of an inline table, 1 for the document.
  int line() const;
  /// "path.key" (or "key" for the document).
  std::string key_path(std::string_view key) const;

  bool has(std::string_view key) const { return find(key) != nullptr; }
  const toml::value* find(std::string_view key) const;
  /// Line of the key's value, or of the table when the key is absent.
  int line_of(std::string_view key) const;

  /// Rejects every key not in `known`. A key in `planned` is reported as reserved for a
  /// later version instead of unknown. Reports the first offending key in file order.
  void check_keys(std::initializer_list<std::string_view> known,
                  std::initializer_list<std::string_view> planned = {}) const;

  /// Throws InputError at the key's line (the table's when absent) naming path.key.
  [[noreturn]] void fail(std::string_view key, const std::string& what) const;
  /// Throws InputError at the table's line naming the table's own path.
  [[noreturn]] void fail_table(const std::string& what) const;

  /// A required number (integers accepted); `expected` reads after "expected ...".
  double number(std::string_view key, Sign sign, const std::string& expected) const;
  double number_or(std::string_view key, double fallback, Sign sign,
                   const std::string& expected) const;

  /// true or false; `fallback` when the key is absent.
  bool boolean_or(std::string_view key, bool fallback, const std::string& expected) const;

  std::string string(std::string_view key, const std::string& expected) const;
  std::optional<std::string> optional_string(std::string_view key,
                                             const std::string& expected) const;

  /// A name: a non-empty string of ASCII letters, digits, '_' and '-'.
  std::string name(std::string_view key, const std::string& expected) const;

  /// Index in `choices` of the string value; `planned` values are reported as not yet
  /// supported. Returns `fallback` when the key is absent and fallback >= 0.
  int choice(std::string_view key, std::initializer_list<std::string_view> choices, int fallback,
             std::initializer_list<std::string_view> planned = {}) const;

  /// A required array of exactly 3 (or 4) finite numbers.
  Eigen::Vector3d vector3(std::string_view key, const std::string& expected) const;
  Eigen::Vector3d vector3_or(std::string_view key, const Eigen::Vector3d& fallback,
                             const std::string& expected) const;
  Eigen::Vector4d vector4_or(std::string_view key, const Eigen::Vector4d& fallback,
                             const std::string& expected) const;

  /// The elements of an array of tables ([[key]] or key = [{...}, ...]), empty when absent.
  std::vector<Table> tables(std::string_view key, const std::string& expected) const;
  /// A sub-table (inline or [path.key]), nullopt when absent.
  std::optional<Table> table(std::string_view key, const std::string& expected) const;

  /// Converts one TOML value to a finite number; `key` names it in messages.
  double to_number(const toml::value& value, std::string_view key, Sign sign,
                   const std::string& expected) const;
  /// Throws InputError at the value's own line (elements of multi-line arrays).
  [[noreturn]] void fail_at(const toml::value& value, std::string_view key,
                            const std::string& what) const;

 private:
  template <int N>
  Eigen::Matrix<double, N, 1> fixed_vector(std::string_view key, const std::string& expected) const;

  const toml::value* table_;
  const std::string* file_;
  std::string path_;
};

/// Line of a TOML value (1 when toml11 does not know it).
int line_of(const toml::value& value);
/// How a value reads in a message: its source text when short and on one line, with its
/// type ("\"abc\" (a string)", "[1, 0] (an array of 2 elements)", "a table").
std::string describe(const toml::value& value);
/// The source text of a value when it sits on one line, else empty.
std::string source_text(const toml::value& value);

}  // namespace flexref::scene::scene_toml
