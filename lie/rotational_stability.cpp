#include "lie/rotational_stability.hpp"

#include <cstddef>

namespace flexref::lie {

double rotational_stability_limit(std::string_view scheme) {
  // Measured as the file comment says (tests/studies/stability_limits_test.cpp repeats it).
  if (scheme == "c1") return 8.96;
  if (scheme == "c2") return 0.582;
  if (scheme == "nmb") return 3.81;
  return 0.0;
}

SpinRate largest_spin(const core::Model& model, const core::State& state) {
  SpinRate out;
  for (int i = 0; i < model.num_bodies(); ++i) {
    if (model.body(i).is_prescribed()) continue;
    const double w = state[static_cast<std::size_t>(i)].w_WB_B.norm();
    if (out.body < 0 || w > out.w) out = {w, i};
  }
  return out;
}

}  // namespace flexref::lie
