/// \file index_ranges.cpp
/// Selections such as "1-4,7,9" (scene/index_ranges.hpp).
#include "scene/index_ranges.hpp"

#include <algorithm>
#include <charconv>
#include <stdexcept>
#include <system_error>

namespace flexref::scene {

std::vector<std::pair<int, int>> parse_ranges(const std::string& text, const std::string& option) {
  std::vector<std::pair<int, int>> out;
  std::size_t begin = 0;
  const auto fail = [&](const std::string& part) {
    throw std::invalid_argument(
        option + ": expected positive integers and ranges such as 1-4,7, got \"" + part + "\"");
  };
  while (begin <= text.size()) {
    std::size_t end = text.find(',', begin);
    if (end == std::string::npos) end = text.size();
    const std::string part = text.substr(begin, end - begin);
    const std::size_t dash = part.find('-');
    const auto parse = [&](const std::string& s) {
      int v = 0;
      const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
      if (s.empty() || ec != std::errc() || p != s.data() + s.size() || v < 1) fail(part);
      return v;
    };
    if (dash == std::string::npos) {
      const int v = parse(part);
      out.emplace_back(v, v);
    } else {
      const int lo = parse(part.substr(0, dash));
      const int hi = parse(part.substr(dash + 1));
      if (hi < lo) fail(part);
      out.emplace_back(lo, hi);
    }
    begin = end + 1;
  }
  return out;
}

std::vector<int> parse_index_list(const std::string& text, const std::string& option) {
  std::vector<int> out;
  for (const auto& [lo, hi] : parse_ranges(text, option)) {
    if (hi - lo > 10000000) {
      throw std::invalid_argument(option + ": the range " + std::to_string(lo) + "-" +
                                  std::to_string(hi) + " is too long");
    }
    for (int v = lo; v <= hi; ++v) out.push_back(v);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace flexref::scene
