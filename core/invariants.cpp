#include "core/invariants.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>

namespace flexref::core {
namespace {

constexpr double kNever = std::numeric_limits<double>::infinity();

std::string element_label(const ForceElement& element, std::size_t index) {
  return "element " + std::to_string(index + 1) + " (" + element.describe() + ")";
}

std::string short_number(double x) {
  std::ostringstream out;
  out.precision(3);
  out << x;
  return out.str();
}

}  // namespace

ModelInvariants model_invariants(const Model& model) {
  ModelInvariants out;
  out.energy_from = -kNever;
  out.momentum_from = -kNever;
  const auto never = [](double& from, std::string& reason, const std::string& why) {
    if (from == kNever) return;
    from = kNever;
    reason = why;
  };
  for (const Body& body : model.bodies()) {
    const bool lte = body.is_flexible() && model.formulation() == FlexibleFormulation::kLte;
    if (body.is_prescribed()) {
      if (body.description().prescribed.law.rate != 0.0) {
        never(out.energy_from, out.energy_reason,
              "body '" + body.name() +
                  "' is driven along its prescribed law (the driving torque's "
                  "work is not tracked)");
      }
    } else if (lte) {
      never(out.energy_from, out.energy_reason,
            "flexible body '" + body.name() +
                "' is integrated under LTE, which cuts the elastic feedback on its rigid motion");
    }
    if (lte) {
      never(out.momentum_from, out.momentum_reason,
            "flexible body '" + body.name() +
                "' is integrated under LTE, which cuts the elastic feedback on its rigid motion");
    } else if (!body.is_free()) {
      never(out.momentum_from, out.momentum_reason,
            "body '" + body.name() + "' is held by a " +
                (body.is_prescribed() ? "prescribed frame" : "pivot") + " (a load from outside)");
    }
  }
  if (const ConstraintEquations* joints = model.constraints()) {
    // An ideal joint to the ground (or to a body held from outside, already counted above) is a
    // load from outside; a joint between two free bodies exerts equal and opposite reactions
    // whose rows are invariant under a rigid motion of the whole: momentum is kept. A drive does
    // work, which the integrals track as W_drive (Model::tracks_drive_work).
    for (int j = 0; j < joints->joint_count(); ++j) {
      const std::array<int, 2> ends = joints->row_bodies(joints->joint_rows(j)[0]);
      if (ends[0] < 0 || ends[1] < 0) {
        const int body = ends[0] >= 0 ? ends[0] : ends[1];
        never(out.momentum_from, out.momentum_reason,
              "ideal joint '" + joints->joint_name(j) + "' holds body '" + model.body(body).name() +
                  "' to the ground (a load from outside)");
      }
    }
  }
  const auto elements = model.elements();
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const ForceElement& element = *elements[i];
    // A load whose work the element would track is integrated only by a dissipating model
    // (Model::extra_integral_count); otherwise its work is in the balance only after its end.
    const bool untracked = element.tracks_applied_work() && !model.tracks_applied_work();
    const double energy = untracked ? element.loads_end() : element.energy_balanced_from();
    if (energy == kNever) {
      never(out.energy_from, out.energy_reason,
            element_label(element, i) + " keeps doing work that is not tracked");
    } else if (out.energy_from != kNever) {
      out.energy_from = std::max(out.energy_from, energy);
    }
    const double momentum = element.loads_end();
    if (momentum == kNever) {
      never(out.momentum_from, out.momentum_reason,
            element_label(element, i) + " loads the bodies from outside");
    } else if (out.momentum_from != kNever) {
      out.momentum_from = std::max(out.momentum_from, momentum);
    }
  }
  return out;
}

std::string InvariantBreach::describe() const {
  std::ostringstream out;
  out << quantity << (quantity == "energy balance" ? " E + W_d - W_a - W_drive" : "")
      << " changed by " << short_number(change) << " " << unit << " since t = " << short_number(t0)
      << " s, " << short_number(100.0 * relative()) << " % of its scale " << short_number(scale)
      << " " << unit << ", at t = " << short_number(t) << " s (tolerance "
      << short_number(100.0 * tolerance) << " %)";
  return out.str();
}

InvariantMonitor::InvariantMonitor(const Model& model, double tolerance, bool work_untracked)
    : model_(model),
      tolerance_(tolerance),
      invariants_(model_invariants(model)),
      ws_(model.make_workspace()) {
  if (work_untracked && model.tracks_work() && invariants_.energy()) {
    invariants_.energy_from = kNever;
    invariants_.energy_reason =
        "the run does not integrate the work the model dissipates or its drives do";
  }
}

void InvariantMonitor::check(const char* quantity, const char* unit, double t, Tracked& tracked,
                             const Eigen::Vector3d& value, double scale) {
  if (!tracked.started) {
    tracked.started = true;
    tracked.t0 = t;
    tracked.value0 = value;
  }
  tracked.scale = std::max(tracked.scale, scale);
  const double change = (value - tracked.value0).norm();
  if (tracked.scale > 0.0 && change / tracked.scale > worst_relative_) {
    worst_relative_ = change / tracked.scale;
    worst_quantity_ = quantity;
  }
  // A change of exactly 0 with a zero scale (a body at rest) conserves the quantity.
  if (breach_ || !(change > tolerance_ * tracked.scale)) return;
  breach_ = InvariantBreach{quantity, unit, t, tracked.t0, change, tracked.scale, tolerance_};
}

const std::optional<InvariantBreach>& InvariantMonitor::observe(double t, const State& state,
                                                                double dissipated, double applied) {
  if (breach_) return breach_;
  if (invariants_.energy() && t >= invariants_.energy_from) {
    const double kinetic = model_.kinetic_energy(state);
    const double potential = model_.potential_energy(LoadContext{t, t}, state, ws_);
    if (!energy_.started) {
      dissipated0_ = dissipated;
      applied0_ = applied;
    }
    kinetic_max_ = std::max(kinetic_max_, kinetic);
    potential_min_ = std::min(potential_min_, potential);
    potential_max_ = std::max(potential_max_, potential);
    // Offset-free scale: a potential's constant does not hide a change (nor inflate one).
    const double scale = kinetic_max_ + (potential_max_ - potential_min_) +
                         std::abs(dissipated - dissipated0_) + std::abs(applied - applied0_);
    check("energy balance", "J", t, energy_,
          Eigen::Vector3d(kinetic + potential + dissipated - applied, 0.0, 0.0), scale);
  }
  if (invariants_.momentum() && t >= invariants_.momentum_from) {
    double linear_scale = 0.0;
    double angular_scale = 0.0;
    for (int i = 0; i < model_.num_bodies(); ++i) {
      const Body& body = model_.body(i);
      const BodyState& s = state[static_cast<std::size_t>(i)];
      const Eigen::Vector3d p_W = body.mass() * s.v_WBr;
      linear_scale += p_W.norm();
      angular_scale += s.p_WBr.cross(p_W).norm() + (body.I_Br_B() * s.w_WB_B).norm();
    }
    check("linear momentum", "N*s", t, linear_, model_.linear_momentum_W(state), linear_scale);
    check("angular momentum", "N*m*s", t, angular_, model_.angular_momentum_W(state),
          angular_scale);
  }
  return breach_;
}

InvariantCheck check_invariants(const Model& model, const Trajectory& trajectory,
                                double tolerance) {
  InvariantMonitor monitor(model, tolerance);
  const bool dissipated = !trajectory.dissipated_work.empty();
  const std::size_t extra =
      trajectory.extra_work.empty() ? 0 : static_cast<std::size_t>(model.extra_integral_count());
  const IntegralLayout& integrals = model.integral_layout();
  // Integral i ≥ 1 of the layout at output k (extra_work omits W_d).
  const auto integral = [&](std::size_t k, int i) {
    return extra > 0 && i > 0 ? trajectory.extra_work[k * extra + static_cast<std::size_t>(i - 1)]
                              : 0.0;
  };
  for (std::size_t k = 0; k < trajectory.states.size(); ++k) {
    const double w_d = dissipated ? trajectory.dissipated_work[k] : 0.0;
    // The work fed in from outside: the applied loads' and the drives'.
    const double w_in = integral(k, integrals.applied) + integral(k, integrals.drive);
    if (monitor.observe(trajectory.times[k], trajectory.states[k], w_d, w_in)) break;
  }
  return {monitor.invariants(), monitor.breach(), monitor.worst_relative(),
          monitor.worst_quantity()};
}

}  // namespace flexref::core
