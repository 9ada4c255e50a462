#pragma once
/// \file mechanism_scene_texts.hpp
/// Scene texts of small mechanisms on ideal joints that the bundled scenes do not cover: a
/// parallelogram four-bar driven into its change point (IFToMM A02, N = 1), a slider-crank whose
/// slider is driven (from dead centre, or towards it), and a ball held by two distance joints.
/// Each states its geometry and what is known of it.
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

namespace flexref::testing {

/// One [[joint]] table of an ideal joint (`extra`: more keys, each line ending in \n).
inline std::string ideal_joint_text(const std::string& name, const std::string& kind,
                                    const std::string& a, const std::string& point_a,
                                    const std::string& b, const std::string& point_b,
                                    const std::string& extra = "") {
  return "[[joint]]\nname = \"" + name + "\"\nmodel = \"ideal\"\nkind = \"" + kind +
         "\"\nbody_a = \"" + a + "\"\npoint_a = " + point_a + "\nbody_b = \"" + b +
         "\"\npoint_b = " + point_b + "\n" + extra;
}

/// IFToMM A02 with N = 1: cranks A-B and D-C of 1 m (1 kg rods), vertical at t = 0, the coupler
/// B-C horizontal; the crank at A driven clockwise at 1 rad/s, so all links are collinear (the
/// mechanism's change point, where J M⁻¹ Jᵀ loses rank) at t = π/2.
inline std::string parallelogram_scene_text(double end_time = 2.0) {
  std::ostringstream text;
  text << "[scene]\nname = \"parallelogram\"\nend_time = " << end_time << "\noutput_step = 0.01\n";
  const auto rod = [](const std::string& name, const std::string& at, bool upright) {
    // Upright: turned by π/2 about +z, θ = (cos π/4, 0, 0, sin π/4) to 17 digits.
    return "[[body]]\nname = \"" + name + "\"\nmass = 1.0\ninertia = [1e-4, 0.0833333333333, " +
           "0.0833333333333]\ncenter_of_mass = [0.5, 0.0, 0.0]\nposition = " + at +
           (upright ? "\norientation = [0.70710678118654757, 0.0, 0.0, 0.70710678118654757]\n"
                    : "\n");
  };
  text << rod("left", "[0.0, 0.0, 0.0]", true) << "angular_velocity = [0.0, 0.0, -1.0]\n";
  text << rod("coupler", "[0.0, 1.0, 0.0]", false) << "velocity = [1.0, 0.0, 0.0]\n";
  text << rod("right", "[1.0, 0.0, 0.0]", true) << "angular_velocity = [0.0, 0.0, -1.0]\n";
  const std::string axes = "axis_a = [0.0, 0.0, 1.0]\naxis_b = [0.0, 0.0, 1.0]\n";
  text << ideal_joint_text("A", "revolute", "left", "[0.0, 0.0, 0.0]", "ground", "[0.0, 0.0, 0.0]",
                           axes + "drive = { law = \"constant-rate\", rate = -1.0 }\n");
  text << ideal_joint_text("B", "revolute", "coupler", "[0.0, 0.0, 0.0]", "left", "[1.0, 0.0, 0.0]",
                           axes);
  text << ideal_joint_text("C", "revolute", "coupler", "[1.0, 0.0, 0.0]", "right",
                           "[1.0, 0.0, 0.0]", axes);
  text << ideal_joint_text("D", "revolute", "right", "[0.0, 0.0, 0.0]", "ground", "[1.0, 0.0, 0.0]",
                           axes);
  return text.str();
}

/// Simeon's rigid slider-crank (scenes/slider_crank.toml's bodies: crank L1 = 0.15 m about O,
/// rod L2 = 0.30 m, slider on the x axis), at rest with the crank at angle `crank_angle`, its
/// slider driven along the guide at `slider_rate` m/s instead of the crank: at crank angle 0 the
/// start is the top dead centre, where the slider's row depends on the others (a singular start);
/// from π/2 at −0.5 m/s the slider pushes the crank into the bottom dead centre (x = L2 − L1) at
/// t = (√(L2² − L1²) − (L2 − L1)) / 0.5 = 0.2196 s, beyond which the drive cannot be followed.
/// The initial velocities are projected (project_initial_state).
inline std::string driven_slider_scene_text(double crank_angle, double slider_rate,
                                            double end_time) {
  const double L1 = 0.15, L2 = 0.30;
  const double s = L1 * std::sin(crank_angle);
  const double phi2 = -std::asin(s / L2);
  const double x3 = L1 * std::cos(crank_angle) + std::sqrt(L2 * L2 - s * s);
  std::ostringstream text;
  text.precision(17);
  const auto turned = [&text](double angle) {
    text << "orientation = [" << std::cos(0.5 * angle) << ", 0.0, 0.0, " << std::sin(0.5 * angle)
         << "]\n";
  };
  text << "[scene]\nname = \"driven_slider\"\nend_time = " << end_time
       << "\noutput_step = 1e-3\nproject_initial_state = true\n";
  text << "[[body]]\nname = \"crank\"\nmass = 0.36\ninertia = [0.000702, 0.000702, 0.000702]\n"
          "center_of_mass = [0.075, 0.0, 0.0]\nposition = [0.0, 0.0, 0.0]\n";
  turned(crank_angle);
  text << "[[body]]\nname = \"rod\"\nmass = 0.151104\ninertia = [0.0011340859, 0.0011340859, "
          "0.0011340859]\ncenter_of_mass = [0.15, 0.0, 0.0]\nposition = ["
       << L1 * std::cos(crank_angle) << ", " << s << ", 0.0]\n";
  turned(phi2);
  text << "[[body]]\nname = \"slider\"\nmass = 0.075552\ninertia = [1e-5, 1e-5, 1e-5]\n"
          "position = ["
       << x3 << ", 0.0, 0.0]\n";
  const std::string z = "axis_a = [0.0, 0.0, 1.0]\naxis_b = [0.0, 0.0, 1.0]\n";
  text << ideal_joint_text("O", "revolute", "crank", "[0.0, 0.0, 0.0]", "ground", "[0.0, 0.0, 0.0]",
                           z);
  text << ideal_joint_text("P", "revolute", "rod", "[0.0, 0.0, 0.0]", "crank", "[0.15, 0.0, 0.0]",
                           z);
  text << ideal_joint_text("Q", "revolute", "slider", "[0.0, 0.0, 0.0]", "rod", "[0.3, 0.0, 0.0]",
                           z);
  std::ostringstream drive;
  drive.precision(17);
  drive << "axis_a = [1.0, 0.0, 0.0]\naxis_b = [1.0, 0.0, 0.0]\ndrive = { law = "
           "\"constant-rate\", rate = "
        << slider_rate << " }\n";
  text << ideal_joint_text("guide", "prismatic", "slider", "[0.0, 0.0, 0.0]", "ground",
                           "[0.0, 0.0, 0.0]", drive.str());
  return text.str();
}

/// A 1 kg ball at the origin on two distance joints to the ground points (∓1, 0, 0), both of
/// length 1: the two spheres touch at the ball only, so the rows are parallel there (a tangency:
/// the second row depends on the first at this pose only); gravity −z.
inline std::string tangent_distances_scene_text() {
  return "[scene]\nname = \"tangent\"\nend_time = 0.5\noutput_step = 0.01\n"
         "gravity = [0.0, 0.0, -9.81]\n"
         "[[body]]\nname = \"ball\"\nmass = 1.0\ninertia = [0.01, 0.01, 0.01]\n"
         "position = [0.0, 0.0, 0.0]\n" +
         ideal_joint_text("D1", "distance", "ball", "[0.0, 0.0, 0.0]", "ground",
                          "[-1.0, 0.0, 0.0]") +
         ideal_joint_text("D2", "distance", "ball", "[0.0, 0.0, 0.0]", "ground", "[1.0, 0.0, 0.0]");
}

}  // namespace flexref::testing
