#pragma once
/// \file index_ranges.hpp
/// Selections of modes and nodes as the command line writes them ("1-4,7,9": positive
/// integers and inclusive ranges; `import-modes --modes`, `--nodes`).
#include <string>
#include <utility>
#include <vector>

namespace flexref::scene {

/// Parses a selection "1-4,7,9" (positive integers and inclusive ranges) into its ranges
/// ([7, 7] for a single number), in the order given; throws std::invalid_argument naming
/// `option`.
std::vector<std::pair<int, int>> parse_ranges(const std::string& text, const std::string& option);
/// The numbers of parse_ranges, sorted, without repeats.
std::vector<int> parse_index_list(const std::string& text, const std::string& option);

}  // namespace flexref::scene
