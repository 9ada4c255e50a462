#pragma once
/// \file state.hpp
/// The state every integrator advances, body by body, in the quasi-velocity variables of
/// docs/design/model.md: position of the reference point Br (world), Euler parameters θ (B → W),
/// velocity of Br (world) and body-frame angular velocity ω̄ = w_WB_B, and for a flexible body
/// the modal coordinates q_f and their rates (empty for a rigid body); and the contacts' worn
/// depths (StateTpl::wear_depth). A pivot body keeps p_WBr
/// fixed and v_WBr = 0; a prescribed body's rigid part is the angle law's at the state's time.
/// Copying a state into one of the same shape allocates nothing (Eigen keeps the storage).
#include <Eigen/Core>
#include <vector>

#include "rotation/euler_parameters.hpp"

namespace flexref::core {

/// One body's state in scalar type S: core::Model advances it in double, the extended and quad
/// references advance core::ModelTpl<S>'s (precision/ode_system.hpp).
template <typename S>
struct BodyStateTpl {
  using Vector3 = Eigen::Matrix<S, 3, 1>;
  using Vector = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  Vector3 p_WBr = Vector3::Zero();
  Eigen::Matrix<S, 4, 1> theta_WB = Eigen::Matrix<S, 4, 1>(S(1), S(0), S(0), S(0));  ///< identity
  Vector3 v_WBr = Vector3::Zero();
  Vector3 w_WB_B = Vector3::Zero();
  Vector q_f;   ///< modal coordinates (n)
  Vector qd_f;  ///< their rates (n)
};

using BodyState = BodyStateTpl<double>;

/// The state of a model in scalar type S: its bodies' states, body after body (a std::vector, so
/// state[i] is body i's), and the worn depths h of its contacts' wear points and sectors (m;
/// docs/wear.md): states like the bodies', integrated with them by every integrator, and the
/// geometry the contacts see. Model::initial_state() sizes wear_depth (empty without a wear law).
template <typename S>
struct StateTpl : std::vector<BodyStateTpl<S>> {
  using std::vector<BodyStateTpl<S>>::vector;
  /// Model::wear_depth_count() depths, contact after contact in the model's element order.
  Eigen::Matrix<S, Eigen::Dynamic, 1> wear_depth;
};
using State = StateTpl<double>;

/// Accelerations of one body: of Br (world) and the body-frame angular acceleration α̅.
template <typename S>
struct BodyAccelerationTpl {
  Eigen::Matrix<S, 3, 1> a_WBr = Eigen::Matrix<S, 3, 1>::Zero();
  Eigen::Matrix<S, 3, 1> alpha_WB_B = Eigen::Matrix<S, 3, 1>::Zero();
  Eigen::Matrix<S, Eigen::Dynamic, 1> qdd_f;  ///< modal accelerations (n)
};
using BodyAcceleration = BodyAccelerationTpl<double>;

template <typename S>
using AccelerationsTpl = std::vector<BodyAccelerationTpl<S>>;
using Accelerations = AccelerationsTpl<double>;

/// States at output times, as every integrator returns them.
struct Trajectory {
  std::vector<double> times;
  std::vector<State> states;
  /// W_d(t): work dissipated since t0 by dampers, friction and modal damping (J), at the output
  /// times; empty when the integrator does not track it (a model that dissipates nothing).
  std::vector<double> dissipated_work;
  /// Model::extra_integral_count() values per output time, row after row (applied work, then
  /// each contact's wear work, J), tracked with W_d; empty when not tracked.
  std::vector<double> extra_work;
  /// Impacts so far per wear channel (core/impact_counter.hpp), row after row per output time;
  /// empty when not counted.
  std::vector<double> impacts;
};

}  // namespace flexref::core
