#pragma once
/// \file model_conversion.hpp
/// A double model in another scalar type S (Pinocchio's ModelTpl::cast, Drake's scalar
/// conversion): the same core::ModelTpl, its bodies formed in S from the scene's descriptions
/// (core::BodyTpl<S>: Br, the invariants, m_ff's factor and the data's unit vectors in S), its
/// force elements and ideal joints converted (element_conversion.hpp), the double model's
/// independent constraint rows kept. The initial state is then made consistent with the joints
/// by Newton projection in S (core::ModelTpl::project), to S's round-off.
/// ModelTpl<S> and BodyTpl<S> are instantiated for long double and float128 in
/// precision/model_instances_{extended,quad}.cpp.
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/model.hpp"
#include "precision/element_conversion.hpp"

namespace flexref::precision {

/// `model` in S. Throws std::invalid_argument (naming `what`, the scene) for a force element or
/// constraint kind the conversion does not know (none of scene::build_model's today).
template <typename S>
core::ModelTpl<S> model_in(const core::Model& model, const std::string& what) {
  std::vector<core::BodyTpl<S>> bodies;
  bodies.reserve(static_cast<std::size_t>(model.num_bodies()));
  for (const core::Body& b : model.bodies()) bodies.emplace_back(b.description());
  std::vector<std::unique_ptr<const core::ForceElementTpl<S>>> elements;
  for (const auto& element : model.elements()) {
    std::unique_ptr<const core::ForceElementTpl<S>> e = element_in<S>(*element);
    if (e == nullptr) {
      // An element of another kind would be left out of the model silently.
      throw std::invalid_argument(what +
                                  ": a force element the extended/quad model does not know; use "
                                  "--precision double");
    }
    elements.push_back(std::move(e));
  }
  std::unique_ptr<const core::ConstraintEquationsTpl<S>> joints;
  core::ConstraintOptions options;
  if (model.has_constraints()) {
    joints = constraints_in<S>(*model.constraints(), model.num_bodies());
    if (joints == nullptr) {
      throw std::invalid_argument(what +
                                  ": constraints the extended/quad model does not know; use "
                                  "--precision double");
    }
    // The double model accepted the scene's initial state (or was told to project it); in S the
    // same state is projected to S's round-off, on the double model's rows.
    options.project_initial_state = true;
    options.independent_rows = model.independent_rows();
  }
  return core::ModelTpl<S>(std::move(bodies), std::move(elements), model.formulation(),
                           std::move(joints), options);
}

}  // namespace flexref::precision
