#pragma once
/// \file versions.hpp
/// Versions recorded next to every result, so a study can be reproduced.
#include <string>

namespace flexref::studies {

/// TOML lines: flexref, compiler, Eigen, Boost, SUNDIALS versions.
std::string versions_toml();

}  // namespace flexref::studies
