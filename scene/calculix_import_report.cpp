/// \file calculix_import_report.cpp
/// The report of a CalculiX import (scene/calculix_import_report.hpp).
#include "scene/calculix_import_report.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cstdio>
#include <numbers>
#include <sstream>

namespace flexref::scene {
namespace {

constexpr double kRadiansPerCycle = 2.0 * std::numbers::pi;  // f = ω/(2π)

std::string report_number(double x, int precision) {
  std::ostringstream s;
  s.precision(precision);
  s << x;
  return s.str();
}

}  // namespace

std::string format_calculix_import_report(const CalculixImport& r) {
  std::ostringstream out;
  char line[256];
  const CalculixDofMap& map = r.dof_map;
  out << "frequency step " << r.frequency_step << ": " << r.modes.size() << " elastic mode(s), "
      << r.data.node_count() << " nodes kept of "
      << r.total_nodes + static_cast<int>(map.added.size()) << " (" << r.total_nodes
      << " of the .frd";
  if (!map.added.empty()) out << ", " << map.added.size() << " shell or beam nodes of the deck";
  out << ")\n";
  if (!map.all_nodes()) {
    const auto condensed = static_cast<std::size_t>(
        std::count(map.kind.begin(), map.kind.end(), CalculixRow::kCondensed));
    out << "matrices: " << map.kind.size() << " rows; condensed (each mode's own rows of "
        << "(K - lambda M) phi = 0): " << map.internal.size()
        << " bubble amplitudes of incompatible modes, " << condensed - map.internal.size()
        << " of shell or beam nodes tied by boundary conditions; " << map.held_rows
        << " held by boundary conditions; " << map.expanded_nodes
        << " expanded shell or beam nodes in the .frd; largest force of a rigid motion "
        << report_number(r.rigid_force, 2) << " of max|K| max|R|\n";
  }
  if (r.rigid_modes.empty()) {
    out << "rigid-body modes: none (the solid is held by its boundary conditions)\n";
  } else {
    out << "rigid-body modes removed:";
    for (const CalculixRigidMode& m : r.rigid_modes) {
      std::snprintf(line, sizeof line, " %d (lambda %.3g, distance %.1e)", m.ccx_mode, m.eigenvalue,
                    m.distance);
      out << line;
    }
    std::snprintf(line, sizeof line,
                  "\n  elastic modes made M-orthogonal to them (largest change %.1e)\n",
                  r.rigid_orthogonalization);
    out << line;
  }
  const Eigen::Vector3d c_solid = r.solid.centre();
  const Eigen::Vector3d c_body = r.body.centre();
  const Eigen::Matrix3d I_solid = r.solid.I0();
  const Eigen::Matrix3d I_body = r.body.I0();
  out << "mass properties about the frame origin (solid: mass matrix; body: nodal masses)\n";
  std::snprintf(line, sizeof line, "  %-18s %-48s %-48s\n", "", "solid", "body");
  out << line;
  std::snprintf(line, sizeof line, "  %-18s %-48.12g %-48.12g\n", "mass [kg]", r.solid.mass,
                r.body.mass);
  out << line;
  std::snprintf(line, sizeof line, "  %-18s %-15.9g %-15.9g %-15.9g  %-15.9g %-15.9g %-15.9g\n",
                "centre [m]", c_solid(0), c_solid(1), c_solid(2), c_body(0), c_body(1), c_body(2));
  out << line;
  const int pairs[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  const char* names[6] = {"I_xx [kg m^2]", "I_yy", "I_zz", "I_xy", "I_xz", "I_yz"};
  for (int p = 0; p < 6; ++p) {
    std::snprintf(line, sizeof line, "  %-18s %-48.12g %-48.12g\n", names[p],
                  I_solid(pairs[p][0], pairs[p][1]), I_body(pairs[p][0], pairs[p][1]));
    out << line;
  }
  std::snprintf(line, sizeof line,
                "  relative difference: mass %.1e, first moment %.1e, inertia %.1e (required "
                "<= %.0e)\n",
                r.mass_difference.mass, r.mass_difference.first_moment, r.mass_difference.inertia,
                kMassPropertyTolerance);
  out << line;
  const InvariantDifference& d = r.invariant_difference;
  std::snprintf(line, sizeof line,
                "modal invariants of the nodal masses vs the mass matrix (matched: %s): S %.1e, "
                "X %.1e, m_ff %.1e; P_ab (quadratic in q_f, lumped) %.1e\n",
                r.mass_model.c_str(), d.S, d.X, d.m_ff, d.P);
  out << line;
  out << "frequency self-check: the body's frequencies eig(K, m_ff) with the nodal masses vs "
         "CalculiX\n";
  std::snprintf(line, sizeof line, "  %-6s %-9s %-16s %-16s %-12s %-12s %-10s\n", "mode",
                "ccx mode", "ccx [Hz]", "body [Hz]", "difference", "Rayleigh", "phi'Mphi");
  out << line;
  for (std::size_t i = 0; i < r.modes.size(); ++i) {
    const CalculixModeCheck& m = r.modes[i];
    std::snprintf(line, sizeof line, "  %-6zu %-9d %-16.10g %-16.10g %-+12.3e %-+12.1e %-10.7f\n",
                  i + 1, m.ccx_mode, m.omega_ccx / kRadiansPerCycle,
                  m.omega_body / kRadiansPerCycle, m.difference, m.rayleigh_difference,
                  m.consistent_modal_mass);
    out << line;
  }
  std::snprintf(line, sizeof line, "  largest |difference| %.3e, tolerance %.3g: %s\n",
                r.max_difference, r.frequency_tolerance, r.self_check_passed ? "passed" : "FAILED");
  out << line;
  for (const std::string& note : r.notes) out << "note: " << note << "\n";
  return out.str();
}

}  // namespace flexref::scene
