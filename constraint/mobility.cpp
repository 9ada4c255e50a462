/// \file mobility.cpp
/// Degrees of freedom by counting and in fact, and the redundant rows by joint.
#include "constraint/mobility.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "constraint/ideal_joints.hpp"

namespace flexref::constraint {

std::string row_label(JointType type, bool driven, int k) {
  // The rows in IdealJointsTpl::evaluate's order (constraint/ideal_joints_impl.hpp); a, b the
  // ends, X, Y, Z their joint frames' axes, d = p_a − p_b.
  static const std::array<const char*, 3> point{"point x", "point y", "point z"};
  static const std::array<const char*, 2> parallel{"axis Z_b.X_a = 0", "axis Z_b.Y_a = 0"};
  static const std::array<const char*, 2> slide{"slide X_b.d = 0", "slide Y_b.d = 0"};
  std::vector<std::string> rows;
  switch (type) {
    case JointType::kSpherical:
      rows.assign(point.begin(), point.end());
      break;
    case JointType::kRevolute:
      rows.assign(point.begin(), point.end());
      rows.insert(rows.end(), parallel.begin(), parallel.end());
      if (driven) rows.emplace_back("drive (angle about Z_b)");
      break;
    case JointType::kPrismatic:
      rows.assign(slide.begin(), slide.end());
      rows.insert(rows.end(), parallel.begin(), parallel.end());
      rows.emplace_back("no twist X_b.Y_a = 0");
      if (driven) rows.emplace_back("drive (slide along Z_b)");
      break;
    case JointType::kCylindrical:
      rows.assign(slide.begin(), slide.end());
      rows.insert(rows.end(), parallel.begin(), parallel.end());
      break;
    case JointType::kUniversal:
      rows.assign(point.begin(), point.end());
      rows.emplace_back("axes Z_b.Z_a = 0");
      break;
    case JointType::kFixed:
      rows.assign(point.begin(), point.end());
      rows.insert(rows.end(), parallel.begin(), parallel.end());
      rows.emplace_back("no twist X_b.Y_a = 0");
      break;
    case JointType::kDistance:
      rows.emplace_back("distance |d| = L");
      break;
  }
  if (k < 0 || k >= static_cast<int>(rows.size())) {
    throw std::out_of_range("row_label: row " + std::to_string(k) + " of a " + to_string(type) +
                            " joint with " + std::to_string(rows.size()) + " rows");
  }
  return rows[static_cast<std::size_t>(k)];
}

Mobility mobility(const core::Model& model) {
  Mobility m;
  for (const core::Body& b : model.bodies()) {
    m.coordinates += (b.is_free() ? 6 : b.is_prescribed() ? 0 : 3) + b.mode_count();
  }
  const core::ConstraintEquations* equations = model.constraints();
  if (equations == nullptr) return m;
  m.rows = equations->row_count();
  const std::vector<int>& active = model.independent_rows();
  m.rank = static_cast<int>(active.size());
  // Row labels need the joints' types: the scene's joints are IdealJoints; another
  // implementation of the interface gets numbered rows.
  const auto* ideal = dynamic_cast<const IdealJoints*>(equations);
  for (int r = 0; r < m.rows; ++r) {
    if (std::binary_search(active.begin(), active.end(), r)) continue;
    RedundantRow row;
    row.row = r;
    const int joint = equations->joint_of_row(r);
    row.joint = equations->joint_name(joint);
    row.joint_row = r - equations->joint_rows(joint)[0];
    if (ideal != nullptr) {
      const IdealJointSpec& spec = ideal->joints()[static_cast<std::size_t>(joint)];
      row.label = row_label(spec.type, spec.drive.active, row.joint_row);
    } else {
      row.label = "row " + std::to_string(row.joint_row);
    }
    m.redundant.push_back(std::move(row));
  }
  return m;
}

}  // namespace flexref::constraint
