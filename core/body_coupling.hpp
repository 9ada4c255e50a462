#pragma once
/// \file body_coupling.hpp
/// Which bodies' equations read which bodies' states: the graph behind the sparsity of the
/// Jacobians of the implicit solvers (genalpha's iteration matrix, lie/genalpha_newton.hpp; IDA's
/// Newton matrix takes the elements' part, element_coupling, and lays the joints out finer:
/// reference/dae_coloured_jacobian.hpp). Body i's loads, its joints' reactions
/// on it and its rows depend on its own state, on the states of the bodies an element couples it
/// with (ForceElementTpl::coupled_bodies: a spring's two ends, a contact's pairs) and on the
/// states of the bodies it shares a joint row with (ConstraintEquationsTpl::row_bodies: the rows'
/// J, Φ and Φ_t read the poses of both ends). A chain's bodies each have at most three
/// neighbours (themselves included), whatever the chain's length.
#include <vector>

#include "core/model.hpp"

namespace flexref::core {

/// Per body, the bodies whose states its equations may depend on: sorted, unique, itself
/// included. Every row of the joints counts (the rows in force may be any of them).
std::vector<std::vector<int>> body_coupling(const Model& model);

/// As body_coupling, the force elements' coupling alone (each body itself, and the bodies an
/// element couples it with): for a form whose joint terms read the other end's pose only and
/// lays them out itself (IDA's GGL residual, reference/dae_coloured_jacobian.hpp).
std::vector<std::vector<int>> element_coupling(const Model& model);

/// A colouring of the bodies in which two bodies that share a neighbour (or are neighbours)
/// get different colours (a distance-2 colouring of body_coupling's graph, greedy in body
/// order): perturbing every body of one colour at once changes each body's equations through
/// one perturbed body at most, so one evaluation per colour and unknown separates them
/// (Curtis, Powell & Reid 1974). Returns each body's colour, from 0.
std::vector<int> colour_bodies(const std::vector<std::vector<int>>& coupling);

}  // namespace flexref::core
