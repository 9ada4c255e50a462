#include <memory>
#include <stdexcept>
#include <string>

#include "lie/c1.hpp"
#include "lie/c2.hpp"
#include "lie/nmb.hpp"
#include "lie/stepper.hpp"

namespace flexref::lie {

std::unique_ptr<Stepper> make_stepper(std::string_view name, const core::Model& model) {
  if (name == "c1") return std::make_unique<C1Stepper>(model);
  if (name == "c2") return std::make_unique<C2Stepper>(model);
  if (name == "nmb") return std::make_unique<NmbStepper>(model);
  throw std::invalid_argument("unknown scheme '" + std::string(name) +
                              "' (expected one of c1, c2, nmb)");
}

std::vector<std::string> scheme_names() { return {"c1", "c2", "nmb"}; }

}  // namespace flexref::lie
