#include "studies/wear_cycle_jump.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>

#include "reference/solve_reference.hpp"
#include "scene/build_model.hpp"
#include "studies/parallel.hpp"

namespace flexref::studies {
namespace {

/// The bodies' state at a window's end, as the next window's scene takes it.
struct CarriedState {
  std::vector<core::BodyInitialState> initial;
  std::vector<Eigen::VectorXd> q_f, qd_f;
};

CarriedState carried_from(const core::Model& model, const core::State& state) {
  CarriedState c;
  for (int i = 0; i < model.num_bodies(); ++i) {
    const core::BodyState& s = state[static_cast<std::size_t>(i)];
    core::BodyInitialState b;
    b.p_WBo = model.p_WBo(i, s);
    b.theta_WB = s.theta_WB;
    b.v_WBo = model.v_WBo(i, s);
    b.w_WB_B = s.w_WB_B;
    c.initial.push_back(b);
    c.q_f.push_back(s.q_f);
    c.qd_f.push_back(s.qd_f);
  }
  return c;
}

void apply_carried(const CarriedState& c, scene::SceneSpec& spec) {
  for (std::size_t i = 0; i < spec.bodies.size(); ++i) {
    core::RigidBodyDescription& d = spec.bodies[i].description;
    d.initial = c.initial[i];
    if (d.flexible) {
      d.flexible->q0 = c.q_f[i];
      d.flexible->qd0 = c.qd_f[i];
    }
  }
}

/// What a window found.
struct WindowOutcome {
  WearWindow window;
  CarriedState end;
};

WindowOutcome run_window(const scene::SceneSpec& spec, const Eigen::VectorXd& depth,
                         const CarriedState* start, double transient,
                         const CycleJumpOptions& options) {
  const double cpu_start = thread_cpu_seconds();
  scene::SceneSpec s = with_wear_geometry(spec, depth, true);
  if (start != nullptr) apply_carried(*start, s);
  const core::Model model = scene::build_model(s, options.formulation);
  // Outputs on the grid, with T_tr and T_tr + T_w exact.
  const double end = transient + options.window;
  std::vector<double> times{0.0};
  const auto add_grid = [&](double to) {
    const double from = times.back();
    const int n =
        std::max(1, static_cast<int>(std::ceil((to - from) / options.output_step - 1e-9)));
    for (int k = 1; k <= n; ++k) times.push_back(k == n ? to : from + (to - from) * k / n);
  };
  if (transient > 0.0) add_grid(transient);
  const std::size_t averaged_from = times.size() - 1;
  add_grid(end);
  reference::SolverOptions solver;
  solver.rtol = options.rtol;
  const reference::ReferenceRun run =
      reference::solve_reference(options.solver, model, times, solver);
  WindowOutcome out;
  WearWindow& w = out.window;
  w.depth = depth;
  const core::State& first = run.trajectory.states[averaged_from];
  const core::State& last = run.trajectory.states.back();
  // r = (h(T_tr + T_w) − h(T_tr)) / T_w: the states' depths accumulate the window's wear on the
  // frozen geometry.
  w.rate = (last.wear_depth - first.wear_depth) / options.window;
  const auto channels = static_cast<std::size_t>(model.wear_channel_count());
  const std::vector<double>& impacts = run.trajectory.impacts;
  if (channels > 0 && impacts.size() == channels * times.size()) {
    double count = 0.0;
    for (std::size_t c = 0; c < channels; ++c) {
      count += impacts[(times.size() - 1) * channels + c] - impacts[averaged_from * channels + c];
    }
    w.impacts_per_second = count / options.window;
  }
  w.steps = run.stats.steps;
  out.end = carried_from(model, last);
  w.cpu_seconds = thread_cpu_seconds() - cpu_start;
  return out;
}

/// How the regime of window b differs from window a's (empty: the same regime): the impacts in
/// the window differ by more than 20 % of the larger count and by more than 2 (an impact more or
/// less at a window's edge is not a change), wear starts or stops, or a point or sector changes
/// between worn (above 20 % of the largest rate) and unworn (below 5 %: the margin keeps a
/// sector near one threshold from flickering).
std::string regime_difference(const WearWindow& a, const WearWindow& b, double window) {
  std::ostringstream out;
  out.precision(3);
  const double n_a = a.impacts_per_second * window;
  const double n_b = b.impacts_per_second * window;
  if (std::abs(n_a - n_b) > std::max(2.0, 0.2 * std::max(n_a, n_b))) {
    out << "impacts " << a.impacts_per_second << " -> " << b.impacts_per_second << " per s";
  }
  const double top_a = a.rate.size() > 0 ? a.rate.maxCoeff() : 0.0;
  const double top_b = b.rate.size() > 0 ? b.rate.maxCoeff() : 0.0;
  if ((top_a > 0.0) != (top_b > 0.0)) {
    out << (out.tellp() > 0 ? "; " : "") << (top_a > 0.0 ? "wear stops" : "wear starts");
  } else if (top_a > 0.0) {
    int gained = 0, lost = 0;
    for (Eigen::Index j = 0; j < a.rate.size(); ++j) {
      gained += a.rate(j) < 0.05 * top_a && b.rate(j) > 0.2 * top_b;
      lost += a.rate(j) > 0.2 * top_a && b.rate(j) < 0.05 * top_b;
    }
    if (gained + lost > 0) {
      out << (out.tellp() > 0 ? "; " : "") << "worn points or sectors +" << gained << " -" << lost;
    }
  }
  return out.str();
}

/// The windows' rate noise below which an oscillation is not reported, relative to the largest
/// rate: at rtol 1e-8 a window's averaged rate is repeatable to ~1e-5 (docs/wear.md).
double oscillation_floor(double rtol) { return std::max(1e-3, 100.0 * rtol); }

void check_options(const CycleJumpOptions& o) {
  const auto positive = [](double x) { return x > 0.0 && std::isfinite(x); };
  if (!positive(o.window)) throw std::invalid_argument("wear: the window must be positive");
  if (!(o.transient >= 0.0) || !std::isfinite(o.transient)) {
    throw std::invalid_argument("wear: the transient must be >= 0");
  }
  if (!positive(o.jump)) throw std::invalid_argument("wear: the jump must be positive");
  if (!positive(o.until)) throw std::invalid_argument("wear: the slow time must be positive");
  if (!positive(o.output_step))
    throw std::invalid_argument("wear: the output step must be positive");
  if (o.until / o.jump > 1e6) {
    throw std::invalid_argument("wear: more than 1e6 jumps (--until / --jump); use a larger jump");
  }
}

}  // namespace

const char* to_string(SlowIntegrator slow) {
  switch (slow) {
    case SlowIntegrator::kEuler:
      return "euler";
    case SlowIntegrator::kHeun:
      return "heun";
    case SlowIntegrator::kAb2:
      return "ab2";
  }
  return "euler";
}

SlowIntegrator parse_slow_integrator(const std::string& name) {
  if (name == "euler") return SlowIntegrator::kEuler;
  if (name == "heun") return SlowIntegrator::kHeun;
  if (name == "ab2") return SlowIntegrator::kAb2;
  throw std::invalid_argument("unknown slow-time integrator \"" + name +
                              "\"; expected euler, heun or ab2");
}

int claimed_order(SlowIntegrator slow) { return slow == SlowIntegrator::kEuler ? 1 : 2; }

std::string slow_instability(const std::vector<Eigen::VectorXd>& rates,
                             const std::vector<double>& slow_times, double rtol) {
  double top = 0.0;
  for (const Eigen::VectorXd& r : rates) top = std::max(top, r.cwiseAbs().maxCoeff());
  const double floor = oscillation_floor(rtol) * top;
  // Δr_k = r_k − r_{k−1}; reversals at k and k−1, and |Δr_k| ≥ |Δr_{k−2}| > floor.
  for (std::size_t k = 3; k < rates.size(); ++k) {
    const Eigen::VectorXd d0 = rates[k] - rates[k - 1];
    const Eigen::VectorXd d1 = rates[k - 1] - rates[k - 2];
    const Eigen::VectorXd d2 = rates[k - 2] - rates[k - 3];
    if (d0.dot(d1) < 0.0 && d1.dot(d2) < 0.0 && d0.norm() >= d2.norm() && d0.norm() > floor) {
      std::ostringstream out;
      out.precision(3);
      out << "jumps " << k - 3 << "-" << k << " (t = " << slow_times[k - 3] << " -> "
          << slow_times[k] << " s): the averaged rates oscillate without decaying (their change "
          << d2.norm() << " -> " << d0.norm()
          << " m/s): the jump is beyond the slow-time integrator's stability limit";
      return out.str();
    }
  }
  return {};
}

scene::SceneSpec with_wear_geometry(const scene::SceneSpec& spec, const Eigen::VectorXd& depth,
                                    bool frozen) {
  scene::SceneSpec out = spec;
  Eigen::Index offset = 0;
  for (scene::ContactSpec& c : out.contacts) {
    if (!c.wear) continue;
    const Eigen::Index count = c.gap ? c.wear->sectors : static_cast<Eigen::Index>(c.pairs.size());
    if (offset + count > depth.size()) {
      throw std::invalid_argument(
          "with_wear_geometry: fewer depths than the scene's contacts wear");
    }
    c.wear->initial_depth.assign(depth.data() + offset, depth.data() + offset + count);
    c.wear->geometry_frozen = frozen;
    offset += count;
  }
  if (offset != depth.size()) {
    throw std::invalid_argument("with_wear_geometry: more depths than the scene's contacts wear");
  }
  return out;
}

scene::SceneSpec with_initial_state(const scene::SceneSpec& spec, const core::Model& model,
                                    const core::State& state) {
  scene::SceneSpec out = spec;
  apply_carried(carried_from(model, state), out);
  return out;
}

CycleJumpResult run_cycle_jump(const scene::SceneSpec& spec, const CycleJumpOptions& options) {
  check_options(options);
  CycleJumpResult result;
  result.options = options;
  {
    const core::Model model = scene::build_model(spec, options.formulation);
    if (model.wear_depth_count() == 0) {
      throw std::invalid_argument("wear: the scene has no contact with a wear law (docs/wear.md)");
    }
    for (int c = 0; c < model.wear_channel_count(); ++c) {
      if (model.channel_depth_count(c) == 0) continue;
      result.channels.push_back(model.wear_channel_names()[static_cast<std::size_t>(c)]);
      result.channel_first.push_back(model.channel_depth_first(c));
      result.channel_count.push_back(model.channel_depth_count(c));
      result.channel_sectors.push_back(model.channel_wear_law(c)->sectors);
    }
    result.depth_areas = model.wear_depth_areas();
    result.path.push_back({0.0, model.initial_state().wear_depth});
  }
  const double first_transient =
      options.first_transient >= 0.0 ? options.first_transient : options.transient;
  Eigen::VectorXd h = result.path.front().depth;
  CarriedState carried;
  bool have_carried = false;
  double tau = 0.0;
  Eigen::VectorXd previous_rate;
  double previous_jump = 0.0;
  const auto window = [&](const Eigen::VectorXd& depth, int jump, const char* role) {
    const double transient = have_carried ? options.transient : first_transient;
    WindowOutcome w =
        run_window(spec, depth, have_carried ? &carried : nullptr, transient, options);
    carried = std::move(w.end);
    have_carried = true;
    w.window.jump = jump;
    w.window.role = role;
    w.window.slow_time = tau;
    result.fast_time += transient + options.window;
    result.cpu_seconds += w.window.cpu_seconds;
    result.windows.push_back(w.window);
    if (options.on_window) options.on_window(tau);
    return result.windows.back();
  };
  const auto note_regime = [&](int jump, double from, double to, const WearWindow& a,
                               const WearWindow& b) {
    const std::string change = regime_difference(a, b, options.window);
    if (change.empty()) return;
    std::ostringstream out;
    out << "jump " << jump << " (t = " << from << " -> " << to << " s): " << change;
    result.regime_changes.push_back(out.str());
    result.regime_change_jumps.push_back(jump);
  };
  // The slow time's end within round-off: the last jump lands on it.
  const double slack = 1e-9 * options.until;
  int k = 0;
  std::size_t previous_start = 0;
  for (; tau < options.until - slack; ++k) {
    const double d = std::min(options.jump, options.until - tau);
    const WearWindow start = window(h, k, "start");
    const std::size_t start_index = result.windows.size() - 1;
    if ((k > 0 && options.slow == SlowIntegrator::kEuler) ||
        (k > 1 && options.slow == SlowIntegrator::kAb2)) {
      // The previous jump ended on this window's geometry (AB2's first jump, by Heun, compared
      // its own ends).
      const WearWindow& before = result.windows[previous_start];
      note_regime(k - 1, before.slow_time, tau, before, start);
    }
    const bool heun =
        options.slow == SlowIntegrator::kHeun || (options.slow == SlowIntegrator::kAb2 && k == 0);
    if (options.slow == SlowIntegrator::kEuler) {
      // h_{k+1} = h_k + D r(h_k)
      h += d * start.rate;
    } else if (heun) {
      // h̃ = h_k + D r(h_k),  h_{k+1} = h_k + ½ D (r(h_k) + r(h̃))
      const Eigen::VectorXd predicted = h + d * start.rate;
      const WearWindow end = window(predicted, k, "predictor");
      note_regime(k, tau, tau + d, result.windows[start_index], end);
      h += (0.5 * d) * (result.windows[start_index].rate + end.rate);
    } else {
      // h_{k+1} = h_k + D ((1 + ω/2) r_k − (ω/2) r_{k−1}),  ω = D_k / D_{k−1}
      const double omega = d / previous_jump;
      h += d * ((1.0 + 0.5 * omega) * start.rate - (0.5 * omega) * previous_rate);
    }
    previous_rate = result.windows[start_index].rate;
    previous_jump = d;
    previous_start = start_index;
    tau = tau + d >= options.until - slack ? options.until : tau + d;
    result.path.push_back({tau, h});
  }
  result.jumps = k;
  std::vector<Eigen::VectorXd> rates;
  std::vector<double> times;
  for (const WearWindow& w : result.windows) {
    if (w.role != "start") continue;
    rates.push_back(w.rate);
    times.push_back(w.slow_time);
  }
  result.slow_instability = slow_instability(rates, times, options.rtol);
  return result;
}

}  // namespace flexref::studies
