/// \file body_coupling.cpp
/// See body_coupling.hpp.
#include "core/body_coupling.hpp"

#include <algorithm>
#include <cstddef>

namespace flexref::core {

namespace {

void couple_all(const std::vector<int>& bodies, std::vector<std::vector<int>>& coupling) {
  for (const int a : bodies) {
    if (a < 0) continue;
    for (const int b : bodies) {
      if (b >= 0) coupling[static_cast<std::size_t>(a)].push_back(b);
    }
  }
}

void sort_unique(std::vector<std::vector<int>>& coupling) {
  for (std::vector<int>& c : coupling) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
  }
}

std::vector<std::vector<int>> coupling_by_elements(const Model& model) {
  const auto n = static_cast<std::size_t>(model.num_bodies());
  std::vector<std::vector<int>> coupling(n);
  for (std::size_t b = 0; b < n; ++b) coupling[b].push_back(static_cast<int>(b));
  for (const auto& element : model.elements()) couple_all(element->coupled_bodies(), coupling);
  return coupling;
}

}  // namespace

std::vector<std::vector<int>> element_coupling(const Model& model) {
  std::vector<std::vector<int>> coupling = coupling_by_elements(model);
  sort_unique(coupling);
  return coupling;
}

std::vector<std::vector<int>> body_coupling(const Model& model) {
  std::vector<std::vector<int>> coupling = coupling_by_elements(model);
  if (model.has_constraints()) {
    const ConstraintEquations& joints = *model.constraints();
    for (int row = 0; row < joints.row_count(); ++row) {
      const std::array<int, 2> ends = joints.row_bodies(row);
      couple_all({ends[0], ends[1]}, coupling);
    }
  }
  sort_unique(coupling);
  return coupling;
}

std::vector<int> colour_bodies(const std::vector<std::vector<int>>& coupling) {
  const std::size_t n = coupling.size();
  std::vector<int> colour(n, -1);
  // taken[c] == b: colour c is used within distance 2 of body b
  std::vector<std::size_t> taken;
  for (std::size_t b = 0; b < n; ++b) {
    for (const int k : coupling[b]) {
      for (const int j : coupling[static_cast<std::size_t>(k)]) {
        const int c = colour[static_cast<std::size_t>(j)];
        if (c < 0) continue;
        if (static_cast<std::size_t>(c) >= taken.size())
          taken.resize(static_cast<std::size_t>(c) + 1, n);
        taken[static_cast<std::size_t>(c)] = b;
      }
    }
    int c = 0;
    while (static_cast<std::size_t>(c) < taken.size() && taken[static_cast<std::size_t>(c)] == b)
      ++c;
    colour[b] = c;
  }
  return colour;
}

}  // namespace flexref::core
