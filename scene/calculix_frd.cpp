#include "scene/calculix_frd.hpp"

#include <charconv>
#include <cmath>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "core/error.hpp"
#include "io/input_file.hpp"

namespace flexref::scene {
namespace {

/// The lines of a file with their numbers, and errors that name them.
class LineReader {
 public:
  LineReader(std::istream& in, std::string file) : in_(in), file_(std::move(file)) {}

  bool next() {
    if (!std::getline(in_, line_)) return false;
    if (!line_.empty() && line_.back() == '\r') line_.pop_back();
    ++number_;
    return true;
  }
  const std::string& line() const { return line_; }
  int number() const { return number_; }
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& what) const {
    throw core::InputError(file_, number_, "", what);
  }

 private:
  std::istream& in_;
  std::string file_;
  std::string line_;
  int number_ = 0;
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  return s;
}

bool starts_with(const std::string& line, std::string_view prefix) {
  return std::string_view(line).substr(0, prefix.size()) == prefix;
}

/// The fixed-width field [begin, begin + width) of the current line as a number; `what` names
/// it in the error.
template <typename T>
T field(const LineReader& r, std::size_t begin, std::size_t width, const std::string& what) {
  const std::string& line = r.line();
  if (line.size() < begin + width) {
    // The last field of a line may be shorter when ccx pads nothing after it.
    if (line.size() <= begin) {
      r.fail("the record ends before its " + what + " (columns " + std::to_string(begin + 1) + "-" +
             std::to_string(begin + width) + "): truncated or not a ccx .frd file");
    }
  }
  const std::string_view text = trim(std::string_view(line).substr(begin, width));
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) {
    r.fail("expected a number for the " + what + " in columns " + std::to_string(begin + 1) + "-" +
           std::to_string(begin + width) + ", got \"" + std::string(text) + "\"");
  }
  if constexpr (std::is_floating_point_v<T>) {
    if (!std::isfinite(value)) r.fail("the " + what + " is not finite");
  }
  return value;
}

/// The whitespace-separated tokens of `s`.
std::vector<std::string> tokens(std::string_view s) {
  std::vector<std::string> out;
  std::istringstream in{std::string(s)};
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

int integer_token(const LineReader& r, const std::string& token, const std::string& what) {
  int value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size()) {
    r.fail("expected an integer for the " + what + ", got \"" + token + "\"");
  }
  return value;
}

/// Width of the node number in `-1` records: format 0 (short) I5, 1 (long) I10; 2 is binary.
std::size_t node_width(const LineReader& r, int format) {
  if (format == 0) return 5;
  if (format == 1) return 10;
  r.fail("binary .frd blocks (format " + std::to_string(format) +
         ") are not read; run ccx without '-o bin' so that it writes the ASCII format");
}

/// Reads the `2C` node block after its header line.
void read_nodes(LineReader& r, CalculixModes& out) {
  const std::vector<std::string> t = tokens(std::string_view(r.line()).substr(6));
  if (t.size() < 2) r.fail("malformed node block header (2C): expected the node count and format");
  const int count = integer_token(r, t[t.size() - 2], "node count");
  const std::size_t width = node_width(r, integer_token(r, t.back(), "block format"));
  if (count <= 0) r.fail("the node block has no node");
  if (!out.node_ids.empty()) r.fail("a second node block (2C); expected one mesh per .frd file");
  out.node_ids.reserve(static_cast<std::size_t>(count));
  out.positions.resize(3, count);
  for (int k = 0; k < count; ++k) {
    if (!r.next()) {
      r.fail("the file ends inside the node block after " + std::to_string(k) + " of " +
             std::to_string(count) + " nodes (truncated)");
    }
    if (!starts_with(r.line(), " -1")) {
      r.fail("expected node record " + std::to_string(k + 1) + " of " + std::to_string(count) +
             " (\" -1\"), got \"" + r.line().substr(0, 20) + "\"");
    }
    out.node_ids.push_back(field<int>(r, 3, width, "node number"));
    for (int a = 0; a < 3; ++a) {
      out.positions(a, k) = field<double>(r, 3 + width + 12 * static_cast<std::size_t>(a), 12,
                                          std::string("coordinate ") + "xyz"[a]);
    }
  }
  if (!r.next() || !starts_with(r.line(), " -3")) {
    r.fail("the node block holds more records than its header's " + std::to_string(count) +
           " nodes, or lacks its end record \" -3\"");
  }
}

/// Skips a block up to and including its ` -3` end record.
void skip_block(LineReader& r, const std::string& what) {
  const int start = r.number();
  while (r.next()) {
    if (starts_with(r.line(), " -3")) return;
  }
  r.fail("the file ends inside the " + what + " that starts at line " + std::to_string(start) +
         " (truncated)");
}

/// State of the `1P` parameter lines that precede a result block.
struct Parameters {
  int step = 0;
  int mode = 0;
  double eigenvalue = 0.0;
  bool has_eigenvalue = false;
};

void read_parameter(const LineReader& r, Parameters& p) {
  const std::string& line = r.line();
  // The keyword ("    1PSTEP", "    1PMODE": 10 characters) is followed by the numbers.
  const std::vector<std::string> t =
      tokens(line.size() > 10 ? std::string_view(line).substr(10) : std::string_view());
  if (starts_with(line, "    1PSTEP")) {
    if (t.size() < 3) r.fail("malformed 1PSTEP record: expected three numbers");
    p.step = integer_token(r, t[2], "step number");
    p.has_eigenvalue = false;
    p.mode = 0;
  } else if (starts_with(line, "    1PGK")) {
    if (line.size() <= 8) r.fail("malformed 1PGK record: expected the eigenvalue");
    p.eigenvalue = field<double>(r, 8, line.size() - 8, "eigenvalue (1PGK)");
    p.has_eigenvalue = true;
  } else if (starts_with(line, "    1PMODE")) {
    if (t.empty()) r.fail("malformed 1PMODE record: expected the mode number");
    p.mode = integer_token(r, t[0], "mode number");
  }
}

/// Reads a `100C` result block. Keeps it as a mode when it is the displacement (DISP) of a
/// modal step; skips every other result.
void read_result_block(LineReader& r, const Parameters& p, CalculixModes& out) {
  const int header_line = r.number();
  const std::string header = r.line();
  const bool modal =
      header.size() >= 73 && trim(std::string_view(header).substr(63, 10)) == "MODAL";
  const double value = field<double>(r, 12, 12, "result value of the 100C record");
  const int count = field<int>(r, 24, 12, "node count of the 100C record");
  const std::size_t width =
      node_width(r, header.size() >= 75 ? field<int>(r, 73, 2, "block format") : 1);
  if (!r.next()) r.fail("the file ends after a 100C record (truncated)");
  if (!starts_with(r.line(), " -4")) r.fail("expected the \" -4\" record after the 100C record");
  const std::string name(trim(std::string_view(r.line()).substr(3, 10)));
  if (!modal || name != "DISP") {
    skip_block(r, "result block " + name);
    return;
  }
  if (out.node_ids.empty()) r.fail("a displacement block before the node block (2C)");
  // The mode number is 1PMODE's: the 100C record's step field counts the result sets of the
  // whole run (it is 8 for the first mode of a second frequency step after 7 results).
  if (!p.has_eigenvalue || p.mode < 1) {
    r.fail(
        "a modal displacement block without the eigenvalue (1PGK) and mode number (1PMODE) "
        "records of its 1PSTEP");
  }
  const int number = p.mode;
  if (count != static_cast<int>(out.node_ids.size())) {
    r.fail("mode " + std::to_string(number) + " has displacements at " + std::to_string(count) +
           " nodes; the mesh has " + std::to_string(out.node_ids.size()) +
           " (results on a node subset are not read: request *NODE FILE for all nodes)");
  }
  CalculixMode mode;
  mode.number = number;
  mode.eigenvalue = p.eigenvalue;
  mode.frequency_hz = value;
  mode.line = header_line;
  mode.shape.setConstant(3, count, std::numeric_limits<double>::quiet_NaN());
  std::unordered_map<int, int> index;
  index.reserve(out.node_ids.size());
  for (std::size_t k = 0; k < out.node_ids.size(); ++k) {
    index.emplace(out.node_ids[k], static_cast<int>(k));
  }
  std::vector<bool> seen(out.node_ids.size(), false);
  int records = 0;
  while (true) {
    if (!r.next()) {
      r.fail("the file ends inside the displacements of mode " + std::to_string(number) +
             " after " + std::to_string(records) + " of " + std::to_string(count) +
             " nodes (truncated)");
    }
    const std::string& line = r.line();
    if (starts_with(line, " -5")) continue;
    if (starts_with(line, " -3")) break;
    if (!starts_with(line, " -1")) {
      r.fail("expected a displacement record (\" -1\") of mode " + std::to_string(number) +
             ", got \"" + line.substr(0, 20) + "\"");
    }
    const int id = field<int>(r, 3, width, "node number");
    const auto it = index.find(id);
    if (it == index.end()) {
      r.fail("mode " + std::to_string(number) + " has a displacement at node " +
             std::to_string(id) + ", which is not in the node block");
    }
    const auto k = static_cast<std::size_t>(it->second);
    if (seen[k]) {
      r.fail("mode " + std::to_string(number) + " repeats node " + std::to_string(id));
    }
    seen[k] = true;
    for (int a = 0; a < 3; ++a) {
      mode.shape(a, it->second) = field<double>(r, 3 + width + 12 * static_cast<std::size_t>(a), 12,
                                                std::string("displacement u") + "xyz"[a]);
    }
    ++records;
  }
  if (records != count) {
    r.fail("mode " + std::to_string(number) + " has " + std::to_string(records) +
           " displacement records; its 100C record (line " + std::to_string(header_line) +
           ") announces " + std::to_string(count));
  }
  if (out.steps.empty() || out.steps.back().step != p.step) {
    out.steps.push_back({p.step, {}});
  }
  std::vector<CalculixMode>& modes = out.steps.back().modes;
  const int expected = static_cast<int>(modes.size()) + 1;
  if (number != expected) {
    throw core::InputError(
        r.file(), header_line, "",
        "mode " + std::to_string(number) + " of step " + std::to_string(p.step) + " where mode " +
            std::to_string(expected) +
            " was expected (a mode is missing or repeated: the file is not one ccx run)");
  }
  modes.push_back(std::move(mode));
}

/// Throws core::InputError naming the path when `in` (io::InputFile: regular files only) did
/// not open.
void check_open(const io::InputFile& in, const std::string& path) {
  if (!in.is_open()) throw core::InputError(path, 0, "", in.error());
}

}  // namespace

CalculixModes parse_calculix_frd(std::istream& in, const std::string& file_name) {
  LineReader r(in, file_name);
  CalculixModes out;
  out.file = file_name;
  Parameters parameters;
  bool ended = false;
  while (r.next()) {
    const std::string& line = r.line();
    if (starts_with(line, " 9999")) {
      ended = true;
      break;
    }
    if (starts_with(line, "    2C")) {
      read_nodes(r, out);
    } else if (starts_with(line, "    3C")) {
      skip_block(r, "element block (3C)");
    } else if (starts_with(line, "    1P")) {
      read_parameter(r, parameters);
    } else if (starts_with(line, "  100C")) {
      read_result_block(r, parameters, out);
    } else if (starts_with(line, "    1") || trim(line).empty()) {
      // 1C, 1U header lines and blank lines carry nothing the import needs.
    } else {
      r.fail("unexpected record \"" + line.substr(0, 20) +
             "\" (not a ccx ASCII .frd file, or a corrupted one)");
    }
  }
  if (!ended) {
    r.fail(
        "the file ends without the end record \" 9999\": it is truncated (ccx still "
        "running, or the disk full?)");
  }
  if (out.node_ids.empty()) r.fail("the file has no node block (2C)");
  if (out.steps.empty()) {
    r.fail(
        "the file has no mode shapes: expected the displacements (*NODE FILE with U) of a "
        "*FREQUENCY step");
  }
  return out;
}

CalculixModes read_calculix_frd(const std::string& path) {
  io::InputFile in(path, "a CalculiX result file (.frd)");
  check_open(in, path);
  return parse_calculix_frd(in, path);
}

std::vector<CalculixEigenvalueTable> parse_calculix_dat_eigenvalues(std::istream& in,
                                                                    const std::string& file_name) {
  LineReader r(in, file_name);
  std::vector<CalculixEigenvalueTable> tables;
  while (r.next()) {
    if (r.line().find("E I G E N V A L U E   O U T P U T") == std::string::npos) continue;
    CalculixEigenvalueTable table;
    table.line = r.number();
    // Title, blank, three header lines, blank; then "mode λ ω f imag" rows up to a blank line.
    bool rows = false;
    while (r.next()) {
      const std::vector<std::string> t = tokens(r.line());
      if (t.empty()) {
        if (rows) break;
        continue;
      }
      if (t.size() != 5 || t[0].find_first_not_of("0123456789") != std::string::npos) {
        if (rows) r.fail("malformed eigenvalue row: expected mode, eigenvalue and 3 frequencies");
        continue;  // a header line
      }
      rows = true;
      const int mode = integer_token(r, t[0], "mode number");
      if (mode != static_cast<int>(table.eigenvalues.size()) + 1) {
        r.fail("eigenvalue row of mode " + std::to_string(mode) + " where mode " +
               std::to_string(table.eigenvalues.size() + 1) + " was expected");
      }
      double lambda = 0.0;
      const auto [end, ec] = std::from_chars(t[1].data(), t[1].data() + t[1].size(), lambda);
      if (ec != std::errc() || end != t[1].data() + t[1].size() || !std::isfinite(lambda)) {
        r.fail("expected a number for the eigenvalue, got \"" + t[1] + "\"");
      }
      table.eigenvalues.push_back(lambda);
    }
    tables.push_back(std::move(table));
  }
  return tables;
}

std::vector<CalculixEigenvalueTable> read_calculix_dat_eigenvalues(const std::string& path) {
  io::InputFile in(path, "a CalculiX printed-output file (.dat)");
  check_open(in, path);
  return parse_calculix_dat_eigenvalues(in, path);
}

}  // namespace flexref::scene
