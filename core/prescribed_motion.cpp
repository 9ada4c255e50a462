#include "core/prescribed_motion.hpp"

#include <cmath>
#include <sstream>

namespace flexref::core {

double AngleLaw::angle(double t) const { return angle_in<double>(t); }

double AngleLaw::angular_rate(double t) const { return angular_rate_in<double>(t); }

double AngleLaw::angular_acceleration(double t) const { return angular_acceleration_in<double>(t); }

std::string AngleLaw::describe(std::string_view rate_unit) const {
  std::ostringstream out;
  if (kind == Kind::kConstantRate) {
    out << "constant rate " << rate << " " << rate_unit;
  } else {
    out << "spin-up to " << rate << " " << rate_unit << " over " << spin_up_time << " s";
  }
  return out.str();
}

PrescribedAttitude prescribed_attitude(const PrescribedRotation& rotation,
                                       const rotation::EulerParameters& theta_WB0, double t) {
  return prescribed_attitude_in<double>(rotation.law, rotation.axis_W, theta_WB0, t);
}

}  // namespace flexref::core
