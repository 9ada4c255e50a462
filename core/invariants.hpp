#pragma once
/// \file invariants.hpp
/// What a model conserves, read from its own elements and bodies, and a monitor that checks a
/// run against it (docs/decisions.md, "Invariant monitor").
///
/// **Energy balance.** B(t) = E(t) + W_d(t) − W_a(t) (E kinetic + potential, W_d the work the
/// dampers, friction and modal damping dissipated, W_a the tracked work of harmonic loads) is
/// constant from the time every element's work is in it (ForceElement::energy_balanced_from:
/// potentials, dissipation and tracked applied work from the start, a load pulse from its end,
/// any other applied load never), provided no body is driven (a prescribed body whose law
/// turns) and no flexible body is integrated under LTE with its rigid motion free (LTE cuts the
/// elastic feedback on the rigid motion, so energy flows into the modes from nowhere).
///
/// **Momentum.** Linear momentum and angular momentum about the world origin are constant from
/// the time no element applies a load any more (ForceElement::loads_end), when every body is
/// free (a pivot or a prescribed frame is a load from outside) and none is flexible under LTE.
/// Every element that acts counts as a load from outside: flexref does not claim that an
/// element between two bodies cancels its moments exactly (a damper's force is not along the
/// line of its ends).
///
/// **Tolerance** (kInvariantTolerance; docs/decisions.md, "Invariant monitor"): a run breaks an
/// invariant when the change of the conserved quantity since the first monitored output
/// exceeds 0.25 of its scale — for the energy balance the largest kinetic energy so far plus
/// the range of the potential energy plus the work dissipated and applied since (|ΔB| is at
/// most the scale; a potential's constant neither hides nor inflates a change), for momentum
/// the largest Σ over bodies of |m v| (linear) or |p × m v| + |I ω| (angular) so far (|ΔP| is
/// at most twice the scale). Measured (`run` on the bundled rigid and contact scenes, every
/// scheme, steps 0.1 … 2e-5 s below the explicit step limit and the rotational limit): a
/// correct run stays below 0.16, the worst being bouncing_ball at h = 2.5e-3 s, half its
/// contact's limit (the impacts' energy balance error, second order in h: 0.151, 0.048, 0.012
/// at h = 2.5e-3, 1.25e-3, 6.25e-4). A run-away of a torque-free body climbs to the largest
/// energy compatible with its momentum, a change of 1 − J_min/J_spin of the scale: 0.4 on
/// free_spin, 0.5 on book_toss (measured at C2's blow-ups: 0.33 and 0.46 when first seen).
/// 0.25 leaves a factor 1.6 above the former and catches the latter before they are done.
#include <limits>
#include <optional>
#include <string>

#include "core/model.hpp"
#include "core/state.hpp"

namespace flexref::core {

/// Relative change of a conserved quantity (of its scale) beyond which a run is unstable.
inline constexpr double kInvariantTolerance = 0.25;

/// When the model's invariants hold (−∞: from the start; +∞: never), and why not.
struct ModelInvariants {
  double energy_from = std::numeric_limits<double>::infinity();
  std::string energy_reason;  ///< why the energy balance is not an invariant (energy_from = +∞)
  double momentum_from = std::numeric_limits<double>::infinity();
  std::string momentum_reason;  ///< why momentum is not an invariant (momentum_from = +∞)
  bool energy() const { return energy_from < std::numeric_limits<double>::infinity(); }
  bool momentum() const { return momentum_from < std::numeric_limits<double>::infinity(); }
};

/// The invariants of the model (see the file comment).
ModelInvariants model_invariants(const Model& model);

/// A conserved quantity that changed by more than the tolerance.
struct InvariantBreach {
  std::string quantity;  ///< "energy balance", "linear momentum" or "angular momentum"
  std::string unit;      ///< "J", "N*s", "N*m*s"
  double t = 0.0;        ///< the first output time where it is broken, s
  double t0 = 0.0;       ///< the output time it is measured from, s
  double change = 0.0;   ///< |change| since t0, in unit
  double scale = 0.0;    ///< its scale at t, in unit
  double tolerance = kInvariantTolerance;
  double relative() const { return change / scale; }
  /// "energy balance E + W_d - W_a changed by 4.99e+06 J since t = 0 s, 32.8 % of its scale
  /// 1.52e+07 J, at t = 0.1 s (tolerance 25 %)".
  std::string describe() const;
};

/// Checks the states of a run, output time by output time, against model_invariants(model).
class InvariantMonitor {
 public:
  /// `work_untracked`: the caller does not integrate the dissipated and applied work, so a
  /// model that dissipates has no energy balance to monitor.
  explicit InvariantMonitor(const Model& model, double tolerance = kInvariantTolerance,
                            bool work_untracked = false);

  /// Feeds the state at output time t (times increasing), with the dissipated work W_d and the
  /// applied work W_a at t (0 when the run does not track them). Returns the first breach seen
  /// so far (the same one on every later call).
  const std::optional<InvariantBreach>& observe(double t, const State& state, double dissipated,
                                                double applied);
  const std::optional<InvariantBreach>& breach() const { return breach_; }
  const ModelInvariants& invariants() const { return invariants_; }
  /// The largest relative change (of its scale) of any monitored quantity so far, and which.
  double worst_relative() const { return worst_relative_; }
  const std::string& worst_quantity() const { return worst_quantity_; }

 private:
  struct Tracked {
    bool started = false;
    double t0 = 0.0;
    Eigen::Vector3d value0 = Eigen::Vector3d::Zero();  ///< energy: x only
    double scale = 0.0;
  };
  void check(const char* quantity, const char* unit, double t, Tracked& tracked,
             const Eigen::Vector3d& value, double scale);

  const Model& model_;
  double tolerance_;
  ModelInvariants invariants_;
  Workspace ws_;
  Tracked energy_, linear_, angular_;
  double kinetic_max_ = 0.0;
  double potential_min_ = std::numeric_limits<double>::infinity();
  double potential_max_ = -std::numeric_limits<double>::infinity();
  double dissipated0_ = 0.0;
  double applied0_ = 0.0;
  std::optional<InvariantBreach> breach_;
  double worst_relative_ = 0.0;
  std::string worst_quantity_;
};

/// What a run did to the model's invariants.
struct InvariantCheck {
  ModelInvariants invariants;
  std::optional<InvariantBreach> breach;  ///< the first breach, if any
  double worst_relative = 0.0;            ///< InvariantMonitor::worst_relative at the end
  std::string worst_quantity;
};

/// Monitors a whole trajectory (W_d and W_a from the trajectory when tracked), up to its first
/// breach.
InvariantCheck check_invariants(const Model& model, const Trajectory& trajectory,
                                double tolerance = kInvariantTolerance);

}  // namespace flexref::core
