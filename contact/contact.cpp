#include "contact/contact.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "contact/contact_impl.hpp"
#include "core/body.hpp"

namespace flexref::contact {
namespace {

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(what);
}

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

ContactPair ContactPair::sphere_plane(int body, const Eigen::Vector3d& p_BoC_B, double radius,
                                      const Eigen::Vector3d& p_WQ, const Eigen::Vector3d& n_W) {
  require(body >= 0, "contact sphere body index must be >= 0");
  require(radius >= 0.0 && std::isfinite(radius), "contact sphere radius must be >= 0");
  require(finite(p_BoC_B) && finite(p_WQ) && finite(n_W), "contact geometry must be finite");
  const double norm = n_W.norm();
  require(norm > 0.0 && std::isfinite(norm), "contact plane normal must be nonzero");
  ContactPair p;
  p.kind = Kind::kSpherePlane;
  p.body_b = body;
  p.p_BoCb_B = p_BoC_B;
  p.radius_b = radius;
  p.p_WQ = p_WQ;
  p.n_W = n_W / norm;
  return p;
}

ContactPair ContactPair::point_plane(int body, const Eigen::Vector3d& p_BoP_B,
                                     const Eigen::Vector3d& p_WQ, const Eigen::Vector3d& n_W) {
  return sphere_plane(body, p_BoP_B, 0.0, p_WQ, n_W);
}

ContactPair ContactPair::sphere_sphere(int body_a, const Eigen::Vector3d& p_BoCa_B, double radius_a,
                                       int body_b, const Eigen::Vector3d& p_BoCb_B,
                                       double radius_b) {
  require(body_a >= 0 && body_b >= 0, "contact sphere body indices must be >= 0");
  require(body_a != body_b, "sphere-sphere contact needs two different bodies");
  require(radius_a >= 0.0 && radius_b >= 0.0 && std::isfinite(radius_a) && std::isfinite(radius_b),
          "contact sphere radii must be >= 0");
  require(finite(p_BoCa_B) && finite(p_BoCb_B), "contact geometry must be finite");
  ContactPair p;
  p.kind = Kind::kSphereSphere;
  p.body_a = body_a;
  p.p_BoCa_B = p_BoCa_B;
  p.radius_a = radius_a;
  p.body_b = body_b;
  p.p_BoCb_B = p_BoCb_B;
  p.radius_b = radius_b;
  return p;
}

ContactPoint contact_point(const ContactPair& pair, std::span<const core::BodyKinematics> bodies) {
  return detail::pair_point<double>(detail::pair_in<double>(pair), bodies);
}

namespace detail {

void validate_contact(const FrictionLaw& friction, double effective_mass) {
  require(friction.mu >= 0.0 && std::isfinite(friction.mu), "friction coefficient must be >= 0");
  require(friction.v_reg > 0.0 && std::isfinite(friction.v_reg),
          "friction regularization speed must be > 0");
  require(effective_mass >= 0.0 && std::isfinite(effective_mass),
          "contact effective mass must be >= 0");
}

double contact_effective_mass(std::span<const core::Body> bodies,
                              const std::vector<ContactPair>& pairs) {
  // body_b is the sphere body pushed along +n; body_a is −1 for the ground plane.
  const ContactPair& p = pairs.front();
  double m = bodies[static_cast<std::size_t>(p.body_b)].mass();
  if (p.body_a >= 0) {
    const double m_a = bodies[static_cast<std::size_t>(p.body_a)].mass();
    m = m * m_a / (m + m_a);
  }
  return m / static_cast<double>(pairs.size());
}

std::string contact_text(const std::vector<ContactPair>& pairs, const NormalLaw& normal,
                         const FrictionLaw& friction, double effective_mass,
                         const std::string& name, double k_eff, double omega, double step) {
  std::ostringstream out;
  int planes = 0;
  int nodes = 0;
  for (const ContactPair& p : pairs) nodes += p.node_a.deforms() + p.node_b.deforms();
  for (const ContactPair& p : pairs) planes += p.kind == ContactPair::Kind::kSpherePlane;
  out << "contact: " << planes << " sphere-plane and "
      << pairs.size() - static_cast<std::size_t>(planes) << " sphere-sphere pairs, "
      << normal.describe() << ", friction mu = " << friction.mu << ", v_reg = " << friction.v_reg
      << " m/s";
  if (nodes > 0) out << ", " << nodes << " sphere(s) at deforming nodes";
  if (!name.empty()) out << ", wear outputs '" << name << "'";
  if (effective_mass > 0.0) {
    out << "; m_eff = " << effective_mass << " kg: k_eff = " << k_eff << " N/m, omega = " << omega
        << " rad/s, explicit step limit 2/omega = " << step << " s";
    if (normal.kind() == NormalLaw::Kind::kLinear) {
      out << " (zeta = "
          << normal.damping() / (2.0 * std::sqrt(normal.stiffness() * effective_mass)) << ")";
    }
  }
  return out.str();
}

}  // namespace detail

template class ContactElementTpl<double>;

}  // namespace flexref::contact
