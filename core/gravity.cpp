#include "core/gravity.hpp"

#include <algorithm>
#include <cstddef>
#include <sstream>
#include <utility>

namespace flexref::core {

UniformGravity::UniformGravity(const Eigen::Vector3d& g_W, std::vector<BodyMass> bodies)
    : g_W_(g_W), bodies_(std::move(bodies)) {}

void UniformGravity::add_wrenches(const LoadContext& /*context*/,
                                  std::span<const BodyKinematics> bodies,
                                  std::span<Wrench> wrenches) const {
  for (const BodyMass& b : bodies_) {
    const auto i = static_cast<std::size_t>(b.body);
    wrenches[i].add_force_at(b.mass * g_W_, bodies[i].p_BrP_W(b.p_BoBcm_B));
  }
}

double UniformGravity::potential_energy(const LoadContext& /*context*/,
                                        std::span<const BodyKinematics> bodies) const {
  double v = 0.0;
  for (const BodyMass& b : bodies_) {
    v -= b.mass * g_W_.dot(bodies[static_cast<std::size_t>(b.body)].p_WP(b.p_BoBcm_B));
  }
  return v;
}

int UniformGravity::max_body_index() const {
  int m = -1;
  for (const BodyMass& b : bodies_) m = std::max(m, b.body);
  return m;
}

std::string UniformGravity::describe() const {
  std::ostringstream out;
  out << "gravity (" << g_W_.x() << ", " << g_W_.y() << ", " << g_W_.z() << ") m/s^2 on "
      << bodies_.size() << " bodies";
  return out.str();
}

}  // namespace flexref::core
