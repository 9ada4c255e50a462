#include "lie/genalpha_parameters.hpp"

#include <atomic>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace flexref::lie {
namespace {

std::atomic<double>& rho_inf_setting() {
  static std::atomic<double> value{kDefaultRhoInfinity};
  return value;
}

std::atomic<bool>& perturbed_start_setting() {
  static std::atomic<bool> value{false};
  return value;
}

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

void set_genalpha_rho_inf(double rho_inf) {
  require_rho_inf(rho_inf);
  rho_inf_setting().store(rho_inf);
}

double genalpha_rho_inf() { return rho_inf_setting().load(); }

void set_genalpha_perturbed_start(bool perturbed) { perturbed_start_setting().store(perturbed); }

bool genalpha_perturbed_start() { return perturbed_start_setting().load(); }

}  // namespace flexref::lie
