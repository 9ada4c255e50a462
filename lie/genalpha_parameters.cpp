#include "lie/genalpha_parameters.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace flexref::lie {
namespace {

void require_rho_inf(double rho_inf) {
  if (std::isfinite(rho_inf) && rho_inf >= 0.0 && rho_inf <= 1.0) return;
  std::ostringstream out;
  out << "genalpha: the spectral radius at infinity rho_inf = " << rho_inf << " must lie in [0, 1]";
  throw std::invalid_argument(out.str());
}

}  // namespace

GenAlphaParameters GenAlphaParameters::from_rho_inf(double rho_inf) {
  require_rho_inf(rho_inf);
  GenAlphaParameters p;
  p.rho_inf = rho_inf;
  p.alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
  p.alpha_f = rho_inf / (rho_inf + 1.0);
  p.gamma = 0.5 + p.alpha_f - p.alpha_m;
  p.beta = 0.25 * (p.gamma + 0.5) * (p.gamma + 0.5);
  return p;
}

}  // namespace flexref::lie
