#include "precision/precise_comparison.hpp"

#include <algorithm>
#include <boost/multiprecision/float128.hpp>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "core/error.hpp"
#include "io/input_file.hpp"
#include "precision/parse_text.hpp"
#include "trajectory/error_metrics_tpl.hpp"
#include "trajectory/reference_sidecar.hpp"
#include "trajectory/trajectory_contract.hpp"

namespace flexref::precision {
namespace {

using Quad = boost::multiprecision::float128;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

template <typename S>
trajectory::ComparisonReport compare_in(const PreciseTable& run, const PreciseTable& reference) {
  trajectory::TrajectoryTable shape;
  shape.columns = run.columns;
  for (double t : run.times) shape.rows.push_back({t});
  // Values parsed once, in S: cell(table, k, i) reads column i ≥ 1 of row k.
  const auto parse_all = [](const PreciseTable& table) {
    std::vector<std::vector<S>> values;
    values.reserve(table.text.size());
    for (const auto& row : table.text) {
      std::vector<S> v;
      v.reserve(row.size());
      for (const std::string& cell : row) v.push_back(detail::parse_in<S>(cell, table.precision));
      values.push_back(std::move(v));
    }
    return values;
  };
  const std::vector<std::vector<S>> a = parse_all(run);
  const std::vector<std::vector<S>> b = parse_all(reference);
  return trajectory::detail::compare_cells<S>(shape, [&](int table, std::size_t k, std::size_t i) {
    return table == 0 ? a[k][i - 1] : b[k][i - 1];
  });
}

Precision precision_of(const std::string& name) {
  return name == "quad" ? Precision::kQuad
                        : (name == "extended" ? Precision::kExtended : Precision::kDouble);
}

}  // namespace

PreciseTable read_precise_table(const std::string& path) {
  PreciseTable table;
  table.path = path;
  table.precision = precision_of(trajectory::read_reference_sidecar(path).precision);
  io::InputFile in(path, "a trajectory CSV file");
  if (!in.is_open()) throw core::InputError(path, 0, "", in.error());
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line_number == 1 && line.starts_with(trajectory::kUtf8ByteOrderMark)) {
      line.erase(0, trajectory::kUtf8ByteOrderMark.size());
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line.front() == '#') continue;
    std::vector<std::string> cells = split(line);
    if (table.columns.empty()) {
      table.columns = std::move(cells);
      continue;
    }
    if (cells.size() != table.columns.size()) {
      throw core::InputError(path, line_number, "",
                             std::to_string(cells.size()) + " cells for " +
                                 std::to_string(table.columns.size()) + " columns");
    }
    table.times.push_back(std::strtod(cells.front().c_str(), nullptr));
    table.text.emplace_back(cells.begin() + 1, cells.end());
  }
  return table;
}

bool precisely_comparable(const PreciseTable& run, const PreciseTable& reference) {
  return (run.precision != Precision::kDouble || reference.precision != Precision::kDouble) &&
         run.columns == reference.columns && run.times == reference.times;
}

trajectory::ComparisonReport compare_precisely(const PreciseTable& run,
                                               const PreciseTable& reference) {
  if (run.columns != reference.columns || run.times != reference.times) {
    throw std::invalid_argument("compare_precisely: " + run.path + " and " + reference.path +
                                " are not on the same columns and times");
  }
  switch (std::max(run.precision, reference.precision)) {
    case Precision::kDouble:
      return compare_in<double>(run, reference);
    case Precision::kExtended:
      return compare_in<long double>(run, reference);
    case Precision::kQuad:
      return compare_in<Quad>(run, reference);
  }
  return compare_in<double>(run, reference);
}

}  // namespace flexref::precision
