#include "core/model.hpp"

#include "core/model_impl.hpp"

namespace flexref::core {

const char* to_string(FlexibleFormulation formulation) {
  return formulation == FlexibleFormulation::kLte ? "lte" : "coupled";
}

template class ModelTpl<double>;

}  // namespace flexref::core
