#include "scene/calculix_matrices.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <utility>

#include "core/error.hpp"
#include "io/input_file.hpp"

namespace flexref::scene {
namespace {

/// The deck keyword that writes the matrix files, for messages.
constexpr const char* kHowToWrite =
    "add a step '*STEP / *BOUNDARY, OP=NEW / *FREQUENCY, SOLVER=MATRIXSTORAGE / *END STEP' "
    "after the frequency step (docs/calculix.md)";

/// Opens a matrix file (io::InputFile: regular files only); throws core::InputError.
void open(io::InputFile& in, const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    throw core::InputError(path, 0, "", "missing " + what + ": " + kHowToWrite);
  }
  if (!in.is_open()) throw core::InputError(path, 0, "", in.error());
}

/// Skips blanks; false at the end of the text.
bool skip_blanks(const char*& p, const char* end) {
  while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
  return p < end;
}

template <typename T>
bool number(const char*& p, const char* end, T& value) {
  if (!skip_blanks(p, end)) return false;
  const auto [next, ec] = std::from_chars(p, end, value);
  if (ec != std::errc()) return false;
  p = next;
  return true;
}

}  // namespace

void read_calculix_dofs(const std::string& path, std::vector<int>& node,
                        std::vector<int>& direction) {
  io::InputFile in(path, "the degree-of-freedom list (.dof)");
  open(in, path, "degree-of-freedom list (.dof)");
  node.clear();
  direction.clear();
  std::string line;
  int number_of_line = 0;
  while (std::getline(in, line)) {
    ++number_of_line;
    const char* p = line.data();
    const char* end = p + line.size();
    if (!skip_blanks(p, end)) continue;
    int id = 0;
    int dir = 0;
    const auto [dot, ec] = std::from_chars(p, end, id);
    bool ok = ec == std::errc() && dot < end && *dot == '.';
    if (ok) {
      p = dot + 1;
      ok = number(p, end, dir) && !skip_blanks(p, end);
    }
    if (!ok) {
      throw core::InputError(path, number_of_line, "",
                             "expected \"node.direction\" (e.g. 12.3), got \"" + line + "\"");
    }
    if (dir < 1 || dir > 3) {
      throw core::InputError(
          path, number_of_line, "",
          "direction " + std::to_string(dir) + " of node " + std::to_string(id) +
              ": only displacements 1-3 are read (ccx writes rotations of shells and beams as "
              "expanded solid nodes; no temperatures)");
    }
    node.push_back(id);
    direction.push_back(dir - 1);
  }
  if (node.empty()) throw core::InputError(path, number_of_line, "", "no degree of freedom");
}

Eigen::SparseMatrix<double> read_calculix_matrix(const std::string& path, int size) {
  const std::string what =
      path.ends_with(".mas") ? "mass matrix (.mas)" : "stiffness matrix (.sti)";
  io::InputFile in(path, "the " + what);
  open(in, path, what);
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<std::uint64_t> keys;
  std::string line;
  int number_of_line = 0;
  while (std::getline(in, line)) {
    ++number_of_line;
    const char* p = line.data();
    const char* end = p + line.size();
    if (!skip_blanks(p, end)) continue;
    int row = 0;
    int col = 0;
    double value = 0.0;
    if (!number(p, end, row) || !number(p, end, col) || !number(p, end, value) ||
        skip_blanks(p, end)) {
      throw core::InputError(path, number_of_line, "",
                             "expected \"row column value\", got \"" + line + "\"");
    }
    if (row < 1 || col < 1 || row > size || col > size) {
      throw core::InputError(path, number_of_line, "",
                             "entry (" + std::to_string(row) + ", " + std::to_string(col) +
                                 ") outside the " + std::to_string(size) +
                                 " degrees of freedom of the .dof file (files of different runs?)");
    }
    if (!std::isfinite(value)) {
      throw core::InputError(path, number_of_line, "", "the value is not finite");
    }
    const int i = std::min(row, col) - 1;
    const int j = std::max(row, col) - 1;
    keys.push_back((static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j));
    entries.emplace_back(i, j, value);
    if (i != j) entries.emplace_back(j, i, value);
  }
  if (entries.empty()) throw core::InputError(path, number_of_line, "", "no matrix entry");
  std::sort(keys.begin(), keys.end());
  const auto twice = std::adjacent_find(keys.begin(), keys.end());
  if (twice != keys.end()) {
    throw core::InputError(path, 0, "",
                           "entry (" + std::to_string((*twice >> 32) + 1) + ", " +
                               std::to_string((*twice & 0xffffffffu) + 1) +
                               ") is given twice (both triangles, or two runs in one file)");
  }
  Eigen::SparseMatrix<double> matrix(size, size);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

CalculixMatrices read_calculix_matrices(const std::string& base) {
  CalculixMatrices out;
  out.dof_file = base + ".dof";
  out.mass_file = base + ".mas";
  out.stiffness_file = base + ".sti";
  read_calculix_dofs(out.dof_file, out.dof_node, out.dof_direction);
  const auto size = static_cast<int>(out.dof_node.size());
  out.mass = read_calculix_matrix(out.mass_file, size);
  out.stiffness = read_calculix_matrix(out.stiffness_file, size);
  return out;
}

}  // namespace flexref::scene
