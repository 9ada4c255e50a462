/// \file ideal_joints.cpp
/// IdealJointsTpl<double> and the joint types' names and row counts.
#include "constraint/ideal_joints_impl.hpp"

namespace flexref::constraint {

const char* to_string(JointType type) {
  switch (type) {
    case JointType::kSpherical:
      return "spherical";
    case JointType::kRevolute:
      return "revolute";
    case JointType::kPrismatic:
      return "prismatic";
    case JointType::kCylindrical:
      return "cylindrical";
    case JointType::kUniversal:
      return "universal";
    case JointType::kFixed:
      return "fixed";
    case JointType::kDistance:
      return "distance";
  }
  return "?";
}

int row_count(JointType type, bool driven) {
  int rows = 0;
  switch (type) {
    case JointType::kSpherical:
      rows = 3;
      break;
    case JointType::kRevolute:
      rows = 5;
      break;
    case JointType::kPrismatic:
      rows = 5;
      break;
    case JointType::kCylindrical:
      rows = 4;
      break;
    case JointType::kUniversal:
      rows = 4;
      break;
    case JointType::kFixed:
      rows = 6;
      break;
    case JointType::kDistance:
      rows = 1;
      break;
  }
  return rows + (driven ? 1 : 0);
}

template class IdealJointsTpl<double>;

}  // namespace flexref::constraint
