#pragma once
/// \file study_refused.hpp
/// A study that refuses to report a result it cannot stand behind — a reference whose
/// estimated error is larger than the solution itself, an order fitted from too few valid
/// levels. The command line maps it to exit code 4 (docs/decisions.md, "Command line").
#include <stdexcept>

namespace flexref::trajectory {

class StudyRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace flexref::trajectory
