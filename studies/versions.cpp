#include "studies/versions.hpp"

#include <sundials/sundials_config.h>

#include <Eigen/Core>
#include <boost/version.hpp>
#include <sstream>

namespace flexref::studies {

std::string versions_toml() {
  std::ostringstream out;
  out << "[versions]\n"
      << "flexref = \"0.1.0\"\n"
      << "compiler = \"" << __VERSION__ << "\"\n"
      << "eigen = \"" << EIGEN_WORLD_VERSION << '.' << EIGEN_MAJOR_VERSION << '.'
      << EIGEN_MINOR_VERSION << "\"\n"
      << "boost = \"" << BOOST_VERSION / 100000 << '.' << BOOST_VERSION / 100 % 1000 << '.'
      << BOOST_VERSION % 100 << "\"\n"
      << "sundials = \"" << SUNDIALS_VERSION << "\"\n";
  return out.str();
}

}  // namespace flexref::studies
