#pragma once
/// \file study_record.hpp
/// The record written next to every result (`study.toml` of a study, `FILE.meta.toml` of a run
/// or a reference): tables of settings, the scene, the reference, the files written and the
/// versions, in the order they were added. Serialized as TOML with toml11 (strings are escaped
/// by toml11, numbers in the shortest form that reads back as the same double), so any title,
/// path or name — quotes, backslashes, newlines — gives a valid file.
#include <cstddef>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace flexref::studies {

class StudyRecord {
 public:
  using Value = std::variant<double, long long, bool, std::string, std::vector<double>,
                             std::vector<std::string>>;

  /// One TOML table: keys in insertion order; setting a key twice replaces its value.
  class Table {
   public:
    explicit Table(std::string name, bool array = false) : name_(std::move(name)), array_(array) {}
    const std::string& name() const { return name_; }
    /// An element of an array of tables ([[name]]).
    bool is_array_element() const { return array_; }
    /// Keys are bare TOML keys (ASCII letters, digits, '_', '-'); throws std::invalid_argument
    /// otherwise.
    Table& set(const std::string& key, double value) { return put(key, value); }
    Table& set(const std::string& key, int value) {
      return put(key, static_cast<long long>(value));
    }
    Table& set(const std::string& key, long value) {
      return put(key, static_cast<long long>(value));
    }
    Table& set(const std::string& key, long long value) { return put(key, value); }
    Table& set(const std::string& key, std::size_t value) {
      return put(key, static_cast<long long>(value));
    }
    Table& set(const std::string& key, bool value) { return put(key, value); }
    Table& set(const std::string& key, const char* value) { return put(key, std::string(value)); }
    Table& set(const std::string& key, std::string value) { return put(key, std::move(value)); }
    Table& set(const std::string& key, std::vector<double> value) {
      return put(key, std::move(value));
    }
    Table& set(const std::string& key, std::vector<std::string> value) {
      return put(key, std::move(value));
    }
    const std::vector<std::pair<std::string, Value>>& entries() const { return entries_; }
    /// The value of a key, or nullptr.
    const Value* find(const std::string& key) const;

   private:
    Table& put(const std::string& key, Value value);
    std::string name_;
    bool array_ = false;
    std::vector<std::pair<std::string, Value>> entries_;
  };

  /// Table [name], created at its first use; tables keep the order of their first use.
  Table& table(const std::string& name);
  /// A new element of the array of tables [[name]]; `name` may be a dotted key of bare keys
  /// ("reference.check") to nest the array in a table.
  Table& append(const std::string& name);
  const Table* find(const std::string& name) const;
  const std::vector<Table>& tables() const { return tables_; }

  /// The record as TOML text.
  std::string to_toml() const;
  /// Writes to_toml() to path under the output rule (io/output_file.hpp); throws
  /// io::OutputError.
  void write(const std::string& path) const;

 private:
  std::vector<Table> tables_;
};

/// Adds the [versions] table: flexref, compiler, Eigen, Boost and SUNDIALS versions.
void add_versions(StudyRecord& record);

/// A double as TOML: the shortest decimal that reads back as the same double, with ".0"
/// appended to integral values so it stays a float; inf, -inf and nan as TOML spells them.
std::string toml_float(double x);

}  // namespace flexref::studies
