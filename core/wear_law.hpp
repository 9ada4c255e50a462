#pragma once
/// \file wear_law.hpp
/// The wear law of a named contact (docs/wear.md): how fast material is removed at a contact
/// point, and what one point's worn depth is made of.
///
///   Archard (Archard 1953):            V̇ = F k F_n |v_t| / H
///   work rate (Frick, Connors, Au-Yang): V̇ = F K_w |F_t · v_t|
///
/// with V̇ the worn volume rate (m³/s), k the dimensionless wear coefficient, F_n the normal
/// force (N), v_t the slip velocity (m/s), H the hardness of the softer surface (Pa), K_w the
/// work-rate coefficient (m³/(N·m) = 1/Pa), |F_t · v_t| the friction power (W, the rate of the
/// contact's `wear_work`) and F the acceleration factor (≥ 1 by convention, any positive value
/// accepted) that multiplies the coefficient so that the geometry changes within a simulated
/// window of seconds instead of years (recorded in every output's sidecar, never hidden).
///
/// Volume to depth (docs/wear.md, "Wear laws"): a point or sphere contact is a flat pin of area
/// A, ḣ = V̇ / A; a circular gap support's circumference is cut into S angular sectors of scar
/// area (2π r / S) w (r the hole's radius, w the support's thickness), each with its depth.
#include <string>
#include <vector>

namespace flexref::core {

struct WearLaw {
  enum class Kind { kArchard, kWorkRate };
  Kind kind = Kind::kArchard;
  double coefficient = 0.0;   ///< k (Archard, dimensionless) or K_w (work rate, 1/Pa)
  double hardness = 0.0;      ///< H, Pa (Archard only)
  double area = 0.0;          ///< A, m²: each point's pin (point and sphere contacts)
  double acceleration = 1.0;  ///< F, multiplies the coefficient (> 0)
  int sectors = 0;            ///< S ≥ 1 (gap support)
  double thickness = 0.0;     ///< w, m (gap support)
  double radius = 0.0;        ///< r, the hole's radius, m (gap support)
  /// The depths h(0) of the points or sectors, m (empty: all zero): the geometry the contact
  /// starts from (the multi-scale scheme's restarts on a worn geometry).
  std::vector<double> initial_depth;
  /// True while the multi-scale scheme integrates a window of dynamics on a frozen geometry
  /// (docs/wear.md, "Multi-scale scheme"): the contact sees initial_depth whatever the state's
  /// depths, which then only accumulate the window's wear.
  bool geometry_frozen = false;

  /// "archard" or "work-rate" (the scene's `law`).
  const char* name() const { return kind == Kind::kArchard ? "archard" : "work-rate"; }
  /// The factor of the law's force term: F k / H (Archard, on F_n |v_t|) or F K_w (work rate,
  /// on |F_t · v_t|), in m²/N.
  double rate_factor() const {
    return kind == Kind::kArchard ? acceleration * coefficient / hardness
                                  : acceleration * coefficient;
  }
  /// V̇ (m³/s) at one contact point, in any scalar type.
  template <typename S>
  S volume_rate(const S& normal_force, const S& slip_speed, const S& friction_power) const {
    return kind == Kind::kArchard ? S(rate_factor()) * normal_force * slip_speed
                                  : S(rate_factor()) * friction_power;
  }
  /// The scar area of one sector of a gap support, (2π r / S) w, m².
  double sector_area() const;
  /// One line: law, coefficient, hardness, area or sectors, acceleration.
  std::string describe() const;
};

/// Throws std::invalid_argument naming the value when the law cannot be used: a coefficient,
/// acceleration or (Archard) hardness that is not positive and finite; for `points` contact
/// points (gap_support false) an area ≤ 0; for a gap support (true) sectors < 1, a thickness or
/// radius ≤ 0; initial depths that are not finite and ≥ 0 or not one per point or sector.
/// `depth_count` is the number of depths the contact integrates.
void validate_wear_law(const WearLaw& law, bool gap_support, int depth_count);

}  // namespace flexref::core
