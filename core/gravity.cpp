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
    const BodyKinematics& k = bodies[i];
    if (k.invariants == nullptr) {
      wrenches[i].add_force_at(b.mass * g_W_, k.p_BrP_W(b.p_BoBcm_B));
      continue;
    }
    // Flexible (docs/design/model.md): Qe_R += m g, Qe_θ += s̃_t Aᵀ g, Qe_f += Sᵀ Aᵀ g, with
    // s_t = s0 + S q_f the first moment about Br (masses included). τ_Br_W = A(s_t × Aᵀg).
    const flexible::ModalInvariants& inv = *k.invariants;
    const Eigen::Vector3d g_B = k.R_WB.transpose() * g_W_;
    const Eigen::Vector3d s_t = flexible::first_moment(inv, *k.q_f);
    wrenches[i].f_W += inv.mass * g_W_;
    wrenches[i].tau_Br_W += k.R_WB * s_t.cross(g_B);
    wrenches[i].Q_f.noalias() += inv.S.transpose() * g_B;
    // Geometric stiffening: the foreshortening's work, ΔS(q_f)ᵀ Aᵀ g (so that a freely falling
    // body carries no axial load: docs/geometric_stiffening.md).
    if (inv.geometric) {
      flexible::add_foreshortening_first_moment_transpose(*inv.geometric, *k.q_f, g_B,
                                                          wrenches[i].Q_f);
    }
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
      // V = −g · Σ m_k r_k = −g · (m p_WBr + A s_t)
      v -= g_W_.dot(k.invariants->mass * k.state->p_WBr +
                    k.R_WB * flexible::first_moment(*k.invariants, *k.q_f));
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
