#pragma once
/// \file chain_scene.hpp
/// Issue 52's spatial chain (scripts/scenes/make_chain.py: rods of 0.2 m and 0.1 kg on ideal
/// spherical joints, released horizontal while turning about z at 2 rad/s), optionally with a
/// damped spring between two rods that are not neighbours: an element that couples bodies no
/// joint couples, and a dissipation that makes the forms track the work W_d.
#include <sstream>
#include <string>

namespace flexref::testing {

/// The chain of `rods` rods; with spring_a ≥ 0, a spring-damper from rod spring_a's far end to
/// rod spring_b's far end (k = 50 N/m, c = 0.2 N·s/m, rest length 0.1 m).
inline std::string chain_scene_text(int rods, double end_time = 0.5, int spring_a = -1,
                                    int spring_b = -1) {
  const double length = 0.2, mass = 0.1, spin = 2.0;
  std::ostringstream text;
  text.precision(17);
  text << "[scene]\nname = \"chain\"\nend_time = " << end_time
       << "\noutput_step = 0.01\ngravity = [0.0, 0.0, -9.81]\n";
  const double across = mass * length * length / 12.0;
  const double axial = mass * (length / 20.0) * (length / 20.0) / 6.0;
  for (int k = 0; k < rods; ++k) {
    text << "\n[[body]]\nname = \"rod" << k << "\"\nmass = " << mass << "\ninertia = [" << axial
         << ", " << across << ", " << across << "]\ncenter_of_mass = [" << length / 2
         << ", 0.0, 0.0]\nposition = [" << k * length << ", 0.0, 0.0]\nvelocity = [0.0, "
         << spin * k * length << ", 0.0]\nangular_velocity = [0.0, 0.0, " << spin << "]\n";
  }
  for (int k = 0; k < rods; ++k) {
    text << "\n[[joint]]\nname = \"j" << k << "\"\nmodel = \"ideal\"\nkind = \"spherical\"\n"
         << "body_a = \"rod" << k << "\"\npoint_a = [0.0, 0.0, 0.0]\nbody_b = \""
         << (k == 0 ? std::string("ground") : "rod" + std::to_string(k - 1)) << "\"\npoint_b = ["
         << (k == 0 ? 0.0 : length) << ", 0.0, 0.0]\n";
  }
  if (spring_a >= 0) {
    text << "\n[[spring]]\nbody_a = \"rod" << spring_a << "\"\npoint_a = [" << length
         << ", 0.0, 0.0]\nbody_b = \"rod" << spring_b << "\"\npoint_b = [" << length
         << ", 0.0, 0.0]\nstiffness = 50.0\ndamping = 0.2\nrest_length = 0.1\n";
  }
  return text.str();
}

}  // namespace flexref::testing
