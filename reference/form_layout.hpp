#pragma once
/// \file form_layout.hpp
/// Where each body's state sits in the flat y of the ODE and DAE forms (reference/ode_form.hpp,
/// reference/dae_form.hpp): one layout for both, so that a Jacobian of the ODE right-hand side
/// serves IDA too (reference/ode_jacobian.hpp). Per body, in model order:
///   free        [p_WBr(3) θ(4) v_WBr(3) ω̄(3) q_f(n) q̇_f(n)]
///   pivot       [θ(4) ω̄(3) q_f(n) q̇_f(n)]
///   prescribed  [q_f(n) q̇_f(n)]   (the angle law gives θ, ω̄ at the time of evaluation)
/// then the contacts' worn depths, and the forms' own components after them.
#include <vector>

#include "core/model.hpp"

namespace flexref::reference {

/// Offsets of a body's blocks in y (−1 when absent), its mode count and the end of its blocks.
struct BodyBlock {
  int p = -1, theta = -1, v = -1, w = -1, q = -1, qd = -1, n = 0, end = 0;
};

/// The bodies' blocks of a model, from y[0]; the last block's end is where the depths start.
std::vector<BodyBlock> body_blocks(const core::Model& model);

/// The bodies' state and the worn depths (at `depth_index`) into y.
void pack_bodies(const std::vector<BodyBlock>& blocks, int depth_index, const core::State& state,
                 double* y);

/// The state at time t from y, sized for the model: θ normalized (the loads always see an
/// orthogonal A), a pivot's position `fixed`'s, prescribed bodies their law's at t.
void unpack_bodies(const core::Model& model, const std::vector<BodyBlock>& blocks,
                   const core::State& fixed, int depth_index, double t, const double* y,
                   core::State& state);

}  // namespace flexref::reference
