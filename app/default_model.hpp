#pragma once
/// \file default_model.hpp
/// The one default of the flexible-body model (docs/decisions.md, "One default model").
#include "core/flexible_formulation.hpp"

namespace flexref::app {

/// The model of flexible bodies' equations when no --model is given, for every command that
/// takes --model (check, run, reference, converge, work-precision, modes) and every command that
/// loads a scene without one: LTE, the model the hybrid schemes integrate, so that a run, the
/// reference it is compared with and the studies of both measure the same equations (the
/// modelling error of LTE against the coupled model is lte-map's). Rigid bodies are the same in
/// both. Its --model spelling is core::to_string(kDefaultFormulation).
inline constexpr core::FlexibleFormulation kDefaultFormulation = core::FlexibleFormulation::kLte;

}  // namespace flexref::app
