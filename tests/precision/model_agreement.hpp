#pragma once
/// \file model_agreement.hpp
/// The precision references' ODE (precision/ode_system.hpp over the double model converted by
/// precision/model_conversion.hpp, instantiated in double) against core::Model at random states
/// of a scene: the accelerations, the integrals' rates, the gaps and the output row. Both run
/// core::ModelTpl's equations; what this compares is what the conversion and the flat state add —
/// the bodies formed again from their descriptions, the elements' and joints' conversion, the
/// state's packing, the prescribed bodies' kinematics and the output rows — so an error there
/// shows up as an O(1) difference. The equations themselves are guarded by their own tests.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/model.hpp"
#include "precision/ode_system.hpp"
#include "rotation/euler_parameters.hpp"
#include "scene/build_model.hpp"
#include "trajectory/trajectory_table.hpp"

namespace flexref::precision {

/// How far the random states lie from the initial one: uniform in ±position (m) about a free
/// body's Br, ±attitude in each Euler parameter (then normalized), ±velocity (m/s) and ±rate
/// (rad/s) added to v_WBr and ω̄, and q_f, q̇_f uniform in ±q, ±qd.
struct Spread {
  double position = 1.0;
  double attitude = 0.5;
  double velocity = 1.0;
  double rate = 2.0;
  double q = 0.02;
  double qd = 0.3;
};

/// Checks the model against core::Model at four random states (drawn from `seed`, `spread`
/// about the initial state; a pivot's Br stays, with v = 0). Returns in how many states a wear
/// channel pushed (F_n > 0), and counts them per channel in `pushed_by_channel`.
inline int check_against_core_model(const scene::SceneSpec& spec,
                                    core::FlexibleFormulation formulation, double t,
                                    const Spread& spread, unsigned seed = 11,
                                    std::map<std::string, int>* pushed_by_channel = nullptr) {
  // Tolerance: both sides are a few thousand flops from the same doubles on O(1)–O(1e6) terms
  // (the stiff scenes' modal forces K q reach ~1e4 at q ~ 1e-2, a bushing's k d ~1e5 at d ~ 1 m),
  // whose cancellations leave accelerations of the size of the largest of them over the masses;
  // 1e-9 relative to each body's largest acceleration (a, α̅ or q̈_f; at least 1) is ~1e6 ε of it.
  const core::Model model = scene::build_model(spec, formulation);
  const OdeSystemTpl<double> tpl(spec, formulation);
  core::Workspace ws = model.make_workspace();
  core::Accelerations acc = model.make_accelerations();
  REQUIRE(tpl.num_bodies() == model.num_bodies());
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int pushed = 0;
  for (int trial = 0; trial < 4; ++trial) {
    CAPTURE(trial);
    std::vector<double> y = tpl.initial_state();
    core::State state = model.initial_state();
    for (int i = 0; i < model.num_bodies(); ++i) {
      const core::Body& body = model.body(i);
      core::BodyState& s = state[static_cast<std::size_t>(i)];
      const int n = body.mode_count();
      REQUIRE(tpl.mode_count(i) == n);
      const reference::BodyBlock& blk = tpl.blocks()[static_cast<std::size_t>(i)];
      REQUIRE((blk.theta >= 0) == !body.is_prescribed());
      REQUIRE((blk.p >= 0) == body.is_free());
      const auto at = [&y](int offset, int j) -> double& {
        return y[static_cast<std::size_t>(offset + j)];
      };
      if (blk.theta >= 0) {
        for (int k = 0; k < 4; ++k) at(blk.theta, k) += spread.attitude * unit(random);
        double norm = 0.0;
        for (int k = 0; k < 4; ++k) norm += at(blk.theta, k) * at(blk.theta, k);
        for (int k = 0; k < 4; ++k) at(blk.theta, k) /= std::sqrt(norm);
        if (blk.p >= 0) {
          for (int k = 0; k < 3; ++k) at(blk.p, k) += spread.position * unit(random);
          for (int k = 0; k < 3; ++k) at(blk.v, k) += spread.velocity * unit(random);
          s.p_WBr = Eigen::Vector3d(at(blk.p, 0), at(blk.p, 1), at(blk.p, 2));
          s.v_WBr = Eigen::Vector3d(at(blk.v, 0), at(blk.v, 1), at(blk.v, 2));
        }
        for (int k = 0; k < 3; ++k) at(blk.w, k) += spread.rate * unit(random);
        s.theta_WB =
            Eigen::Vector4d(at(blk.theta, 0), at(blk.theta, 1), at(blk.theta, 2), at(blk.theta, 3));
        s.w_WB_B = Eigen::Vector3d(at(blk.w, 0), at(blk.w, 1), at(blk.w, 2));
      }
      const auto o = static_cast<std::size_t>(blk.q);
      for (int k = 0; k < n; ++k) {
        y[o + static_cast<std::size_t>(k)] = spread.q * unit(random);
        y[o + static_cast<std::size_t>(n + k)] = spread.qd * unit(random);
        s.q_f(k) = y[o + static_cast<std::size_t>(k)];
        s.qd_f(k) = y[o + static_cast<std::size_t>(n + k)];
      }
    }
    model.apply_prescribed_motion(t, state);
    std::vector<double> dydt(y.size());
    model.compute_accelerations(core::LoadContext{t, t}, state, ws, acc);
    tpl.derivative(y, dydt, t, t);
    for (int i = 0; i < model.num_bodies(); ++i) {
      CAPTURE(i);
      const core::BodyAcceleration& a = acc[static_cast<std::size_t>(i)];
      const int n = model.body(i).mode_count();
      const double scale = std::max({1.0, a.a_WBr.norm(), a.alpha_WB_B.norm(), a.qdd_f.norm()});
      const reference::BodyBlock& blk = tpl.blocks()[static_cast<std::size_t>(i)];
      const auto rate = [&dydt](int offset, int j) {
        return dydt[static_cast<std::size_t>(offset + j)];
      };
      if (blk.theta >= 0) {
        // ṗ = v, θ̇ = ½ θ ⊗ (0, ω̄) (model.md eq. (2)); a pivot has no p, v blocks.
        const core::BodyState& s = state[static_cast<std::size_t>(i)];
        const Eigen::Vector4d theta_dot = rotation::euler_parameter_rate(s.theta_WB, s.w_WB_B);
        if (blk.p >= 0) {
          for (int k = 0; k < 3; ++k) {
            CHECK(rate(blk.p, k) == s.v_WBr(k));
            CHECK(std::abs(rate(blk.v, k) - a.a_WBr(k)) <= 1e-9 * scale);
          }
        }
        for (int k = 0; k < 4; ++k) {
          CHECK(std::abs(rate(blk.theta, k) - theta_dot(k)) <=
                1e-14 * std::max(1.0, s.w_WB_B.norm()));
        }
        for (int k = 0; k < 3; ++k) {
          CHECK(std::abs(rate(blk.w, k) - a.alpha_WB_B(k)) <= 1e-9 * scale);
        }
      }
      const auto o = static_cast<std::size_t>(blk.q);
      for (int k = 0; k < n; ++k) {
        CHECK(std::abs(dydt[o + static_cast<std::size_t>(n + k)] - a.qdd_f(k)) <= 1e-9 * scale);
        CHECK(dydt[o + static_cast<std::size_t>(k)] == y[o + static_cast<std::size_t>(n + k)]);
      }
    }
    if (model.dissipates()) {
      std::vector<double> rates(static_cast<std::size_t>(1 + model.extra_integral_count()));
      model.integral_rates(core::LoadContext{t, t}, state, ws, rates);
      const std::size_t first = y.size() - rates.size();
      for (std::size_t k = 0; k < rates.size(); ++k) {
        CAPTURE(k);
        CHECK(std::abs(dydt[first + k] - rates[k]) <= 1e-9 * std::max(1.0, std::abs(rates[k])));
      }
    }
    if (model.switching_function_count() > 0) {
      // The gaps at t (a prescribed body's node moves with its law): core has one switching
      // function per gap support or pair, the precision model two (the gap, then the clamp's).
      std::vector<double> g(static_cast<std::size_t>(model.switching_function_count()));
      model.switching_functions(core::LoadContext{t, t}, state, ws, g);
      std::vector<double> values;
      tpl.switching_functions(t, y, values);
      REQUIRE(values.size() == 2 * g.size());
      for (std::size_t k = 0; k < g.size(); ++k) {
        CHECK(std::abs(values[2 * k] - g[k]) <= 1e-12 * std::max(1.0, std::abs(g[k])));
      }
    }
    core::Trajectory trajectory;
    trajectory.times = {t};
    trajectory.states = {state};
    const trajectory::TrajectoryTable table = trajectory::tabulate(model, trajectory);
    const std::vector<double> row = tpl.output_row(t, y);
    // The integrals are NaN in the double tabulation (no integrator), and so is the balance.
    REQUIRE(row.size() + 1 == table.columns.size());
    for (std::size_t c = 0; c < row.size(); ++c) {
      const double expected = table.rows[0][c + 1];
      if (std::isnan(expected) || table.columns[c + 1] == "energy_balance") continue;
      CAPTURE(table.columns[c + 1]);
      CHECK(std::abs(row[c] - expected) <= 1e-9 * std::max(1.0, std::abs(expected)));
      const std::string& column = table.columns[c + 1];
      if (column.size() > 3 && column.ends_with(".fn") && expected > 0.0) {
        ++pushed;
        if (pushed_by_channel != nullptr) ++(*pushed_by_channel)[column];
      }
    }
  }
  return pushed;
}

}  // namespace flexref::precision
