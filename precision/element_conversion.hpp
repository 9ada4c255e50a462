#pragma once
/// \file element_conversion.hpp
/// The double model's force elements in another scalar type S (Drake's scalar conversion): the
/// same class template instantiated in S, its data converted exactly and its unit vectors
/// normalized again in S (core/unit_vector_tpl.hpp). Internal to precision/: the class
/// templates' definitions (the *_impl.hpp headers) are instantiated for long double and
/// float128 in element_conversion.cpp only, so that the libraries of core/ and contact/ build
/// without float128.
#include <memory>

#include "core/constraint_equations.hpp"
#include "core/force_element.hpp"

namespace flexref::precision {

/// `element` in S: uniform gravity, applied forces and torques, point-charge potentials,
/// spherical and revolute bushings, gap supports and contacts; nullptr for another kind.
template <typename S>
std::unique_ptr<const core::ForceElementTpl<S>> element_in(const core::ForceElement& element);

/// The double model's constraint equations in S: its ideal joints (constraint::IdealJointsTpl,
/// the same joint specifications evaluated in S, on a model of `body_count` bodies); nullptr for
/// another kind.
template <typename S>
std::unique_ptr<const core::ConstraintEquationsTpl<S>> constraints_in(
    const core::ConstraintEquations& equations, int body_count);

}  // namespace flexref::precision
