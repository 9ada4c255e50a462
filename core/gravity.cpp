#include "core/gravity.hpp"

#include <algorithm>
#include <cstddef>
#include <sstream>
#include <utility>

#include "core/gravity_tpl.hpp"

namespace flexref::core {

UniformGravity::UniformGravity(const Eigen::Vector3d& g_W, std::vector<BodyMass> bodies)
    : g_W_(g_W), bodies_(std::move(bodies)) {}

void UniformGravity::add_wrenches(const LoadContext& /*context*/,
                                  std::span<const BodyKinematics> bodies,
                                  std::span<Wrench> wrenches) const {
  for (const BodyMass& b : bodies_) {
    const auto i = static_cast<std::size_t>(b.body);
    const BodyKinematics& k = bodies[i];
    if (k.invariants == nullptr) {
      wrenches[i].add_force_at(b.mass * g_W_, k.p_BrP_W(b.p_BoBcm_B));
      continue;
    }
    // Flexible: the loads of core/gravity_tpl.hpp on the invariants about Br.
    add_gravity_loads_tpl<double>(*k.invariants, k.R_WB, *k.q_f, g_W_, wrenches[i].f_W,
                                  wrenches[i].tau_Br_W, wrenches[i].Q_f);
  }
}

double UniformGravity::potential_energy(const LoadContext& /*context*/,
                                        std::span<const BodyKinematics> bodies) const {
  double v = 0.0;
  for (const BodyMass& b : bodies_) {
    const BodyKinematics& k = bodies[static_cast<std::size_t>(b.body)];
    if (k.invariants == nullptr) {
      v -= b.mass * g_W_.dot(k.p_WP(b.p_BoBcm_B));
    } else {
      v += gravity_potential_tpl<double>(*k.invariants, k.R_WB, k.state->p_WBr, *k.q_f, g_W_);
    }
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
