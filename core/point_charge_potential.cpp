#include "core/point_charge_potential.hpp"

#include <algorithm>
#include <cstddef>
#include <sstream>
#include <utility>

namespace flexref::core {

PointChargePotential::PointChargePotential(double alpha, double beta, const Eigen::Vector3d& p_WM,
                                           std::vector<Charge> charges)
    : alpha_(alpha), beta_(beta), p_WM_(p_WM), charges_(std::move(charges)) {}

Eigen::Vector3d PointChargePotential::unit_force_W(const Eigen::Vector3d& p_WP) const {
  const double p[3] = {p_WP.x(), p_WP.y(), p_WP.z()};
  double f[3];
  double v = 0.0;
  unit_field(p, f, v);
  return {f[0], f[1], f[2]};
}

double PointChargePotential::unit_potential(const Eigen::Vector3d& p_WP) const {
  const double p[3] = {p_WP.x(), p_WP.y(), p_WP.z()};
  double f[3];
  double v = 0.0;
  unit_field(p, f, v);
  return v;
}

void PointChargePotential::add_wrenches(const LoadContext& /*context*/,
                                        std::span<const BodyKinematics> bodies,
                                        std::span<Wrench> wrenches) const {
  for (const Charge& c : charges_) {
    const auto i = static_cast<std::size_t>(c.body);
    const BodyKinematics& body = bodies[i];
    wrenches[i].add_force_at(c.weight * unit_force_W(body.p_WP(c.p_BoP_B)),
                             body.p_BrP_W(c.p_BoP_B));
  }
}

double PointChargePotential::potential_energy(const LoadContext& /*context*/,
                                              std::span<const BodyKinematics> bodies) const {
  double v = 0.0;
  for (const Charge& c : charges_) {
    v += c.weight * unit_potential(bodies[static_cast<std::size_t>(c.body)].p_WP(c.p_BoP_B));
  }
  return v;
}

int PointChargePotential::max_body_index() const {
  int m = -1;
  for (const Charge& c : charges_) m = std::max(m, c.body);
  return m;
}

std::string PointChargePotential::describe() const {
  std::ostringstream out;
  out << "point-charge potential: alpha " << alpha_ << ", beta " << beta_ << ", attractor ("
      << p_WM_.x() << ", " << p_WM_.y() << ", " << p_WM_.z() << "), wall z = 0, " << charges_.size()
      << " charges";
  return out.str();
}

}  // namespace flexref::core
