/// \file penalty_load_tpl_test.cpp
/// The contact templates every precision runs (contact/contact_point_tpl.hpp,
/// contact/penalty_load_tpl.hpp) against their closed forms: the sphere–plane and sphere–sphere
/// gap, normal and contact point; the load's normal force along n, friction against the slip,
/// the dissipated power's sign and value; nothing while separated; and long double agreeing
/// with double to double's round-off (the templates do the same operations in both).
#include "contact/penalty_load_tpl.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "contact/contact_point_tpl.hpp"

namespace flexref::contact {
namespace {

using V3 = Eigen::Vector3d;
using V3l = Eigen::Matrix<long double, 3, 1>;

TEST_CASE("contact points: gap, normal and point in closed form", "[contact]") {
  // Sphere of radius 0.1 centred 0.05 above the plane z = 0.02 (tilted normal normalized).
  const V3 n = V3(0.0, 0.6, 0.8);
  const V3 q(0.0, 0.0, 0.02);
  const V3 c = q + 0.05 * n + V3(0.3, -0.8, 0.6);  // a tangential offset (⊥ n) moves nothing
  const ContactPointTpl<double> p = sphere_plane_point_tpl<double>(c, 0.1, q, n);
  CHECK(p.gap == Approx(-0.05).margin(1e-15));
  CHECK((p.n_W - n).norm() == 0.0);
  CHECK((p.p_WP - (c - 0.1 * n)).norm() < 1e-15);
  // Spheres of radii 0.2 and 0.3, centres 0.4 apart along (2, −1, 2)/3: g = −0.1, P at
  // C_a + (0.2 − 0.05) n, n from a to b.
  const V3 d = V3(2.0, -1.0, 2.0) / 3.0;
  const V3 ca(0.1, 0.2, 0.3);
  const ContactPointTpl<double> s = sphere_sphere_point_tpl<double>(ca, 0.2, ca + 0.4 * d, 0.3);
  CHECK(s.gap == Approx(-0.1).margin(1e-15));
  CHECK((s.n_W - d).norm() < 1e-15);
  CHECK((s.p_WP - (ca + 0.15 * d)).norm() < 1e-15);
  // Coincident centres have no direction: n = e_z, g = −r_a − r_b.
  const ContactPointTpl<double> z = sphere_sphere_point_tpl<double>(ca, 0.2, ca, 0.3);
  CHECK(z.n_W == V3::UnitZ());
  CHECK(z.gap == -0.5);
}

TEST_CASE("penalty load: normal force along n, friction against the slip, power >= 0",
          "[contact]") {
  const NormalLaw law = NormalLaw::linear(1e4, 30.0);
  const FrictionLaw friction{0.4, 1e-3};
  const V3 n = V3(1.0, 2.0, 2.0) / 3.0;
  const V3 t = V3(2.0, 1.0, -2.0) / 3.0;  // ⊥ n
  // Penetration 1e-3, approaching at 0.2 m/s (v_rel·n = −0.2), slipping at 0.5 m/s along t.
  const V3 v_rel = -0.2 * n + 0.5 * t;
  const PenaltyLoadTpl<double> e = penalty_load_tpl<double>(law, friction, -1e-3, n, v_rel);
  // Tolerance: δ̇ = −v_rel·n from three products and sums: a few roundings of O(1)-relative
  // operations, each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor ~10 over them.
  CHECK(e.delta_dot == Approx(0.2).epsilon(1e-14));
  CHECK((e.v_t_W - 0.5 * t).norm() < 1e-15);
  // F_n = k δ + c δ̇ = 10 + 6 = 16 N; F_t = −μ F_n tanh(|v_t|/v_reg) t (t the slip's direction).
  // Tolerance: k δ + c δ̇: two products and a sum: a few roundings of O(1)-relative operations,
  // each ≤ 2^-53 ≈ 1.1e-16: 1e-14 leaves a factor ~10 over them.
  CHECK(e.normal.total == Approx(16.0).epsilon(1e-14));
  const double th = std::tanh(0.5 / 1e-3);
  CHECK((e.f_friction_W + 0.4 * 16.0 * th * t).norm() < 1e-12);
  CHECK(e.f_friction_W.dot(e.v_t_W) < 0.0);
  // Dissipated: c δ̇ · δ̇ + μ F_n tanh(|v_t|/v_reg) |v_t| = 6 × 0.2 + 6.4 th × 0.5.
  // Tolerance: F_n δ̇ + |F_t| |v_t| with a tanh (its own rounding ~1 ulp) and the norms of v_t:
  // ~10 roundings of terms of one sign, ≤ ~1e-15; 1e-13 leaves a factor ~100.
  CHECK(e.dissipated_power() == Approx(6.0 * 0.2 + 6.4 * th * 0.5).epsilon(1e-13));
  // Separated (g ≥ 0): nothing.
  const PenaltyLoadTpl<double> off = penalty_load_tpl<double>(law, friction, 1e-6, n, v_rel);
  CHECK(off.normal.total == 0.0);
  CHECK(off.f_friction_W.norm() == 0.0);
  CHECK(off.dissipated_power() == 0.0);
  // Long double: the same operations, to double's round-off (a few ε of the largest term).
  const PenaltyLoadTpl<long double> el = penalty_load_tpl<long double>(
      law, friction, -1e-3L, n.cast<long double>(), v_rel.cast<long double>());
  CHECK(std::abs(static_cast<double>(el.normal.total) - e.normal.total) < 1e-13);
  CHECK((el.f_friction_W.cast<double>() - e.f_friction_W).norm() < 1e-13);
  const V3l cl = V3l(0.1L, 0.2L, 0.3L);
  const V3l dl = V3l(2.0L, -1.0L, 2.0L) / 3.0L;
  const auto sl = sphere_sphere_point_tpl<long double>(cl, 0.2L, cl + 0.4L * dl, 0.3L);
  CHECK(std::abs(static_cast<double>(sl.gap) + 0.1) < 1e-15);
}

}  // namespace
}  // namespace flexref::contact
