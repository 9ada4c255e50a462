/// Model-level checks of flexible bodies (docs/design/model.md, "Bodies and inertia invariants",
/// "Equations of motion", "The LTE model", "Energy and momentum"): every invariant-based quantity
/// the Model evaluates (gravity's generalized forces, kinetic energy, momenta) equals the direct
/// sum over the material points plus the hub at random states; the accelerations satisfy the
/// model's own residual; the coupled equations conserve energy up to the applied and damping
/// powers; the evaluations allocate nothing. The global operator new of this program counts
/// allocations (tests/support/allocation_counting.hpp).
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "core/gravity.hpp"
#include "reference/dae_form.hpp"
#include "reference/ode_form.hpp"
#include "rotation/so3.hpp"
#include "tests/support/allocation_counting.hpp"
#include "tests/support/flexible_models.hpp"

namespace flexref::core {
namespace {

using testing::flexible_spinner_model;
using testing::rotating_cantilever_model;
constexpr FlexibleFormulation kCoupled = FlexibleFormulation::kCoupled;
constexpr FlexibleFormulation kLte = FlexibleFormulation::kLte;

Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

/// A random state of body 0 (any attitude, velocities O(1), modal coordinates O(0.1)).
BodyState random_state(const Body& b, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto vec = [&](Eigen::Index n, double scale) {
    Eigen::VectorXd v(n);
    for (Eigen::Index i = 0; i < n; ++i) v[i] = scale * u(rng);
    return v;
  };
  BodyState s;
  s.p_WBr = vec(3, 2.0);
  s.theta_WB = Eigen::Vector4d(vec(4, 1.0)).normalized();
  s.v_WBr = vec(3, 1.0);
  s.w_WB_B = vec(3, 1.5);
  s.q_f = vec(b.mode_count(), 0.1);
  s.qd_f = vec(b.mode_count(), 0.5);
  return s;
}

/// The body as material points about Br: the nodes (deformed by q_f) and the hub as a point mass
/// at its centre with its own inertia, with world positions and velocities (eq. 10, 14).
struct NodalBody {
  std::vector<double> m;
  std::vector<Eigen::Vector3d> u_B;   ///< ū_k from Br, body frame
  std::vector<Eigen::Matrix3Xd> phi;  ///< Φ_k (zero for the hub)
  std::vector<Eigen::Vector3d> r_W, v_W;
  Eigen::Matrix3d I_hub = Eigen::Matrix3d::Zero();
};

NodalBody nodal_body(const Body& b, const BodyState& s) {
  const flexible::ModalData& md = b.description().flexible->modal;
  const Eigen::Matrix3d A = rotation::rotation_matrix(s.theta_WB);
  const Eigen::Index n = b.mode_count();
  NodalBody nb;
  auto add = [&](double m, const Eigen::Vector3d& u, const Eigen::Matrix3Xd& phi) {
    nb.m.push_back(m);
    nb.u_B.push_back(u);
    nb.phi.push_back(phi);
    nb.r_W.push_back(s.p_WBr + A * u);
    nb.v_W.push_back(s.v_WBr + A * (s.w_WB_B.cross(u) + phi * s.qd_f));
  };
  for (int k = 0; k < md.node_count(); ++k) {
    const Eigen::Matrix3Xd phi = md.mode_rows(k);
    add(md.mass[k], md.p_BoNode_B.col(k) - b.p_BoBr_B() + phi * s.q_f, phi);
  }
  const RigidBodyDescription& d = b.description();
  if (d.mass > 0.0) {
    add(d.mass, d.p_BoBcm_B - b.p_BoBr_B(), Eigen::Matrix3Xd::Zero(3, n));
    nb.I_hub = d.I_Bcm_B;
  }
  return nb;
}

/// The spinner's body in a model with uniform gravity (and no other load).
Model spinner_with_gravity(FlexibleFormulation formulation, const Eigen::Vector3d& g) {
  const Model base = flexible_spinner_model(formulation, 4, 10, 0.0);
  const Body& b = base.body(0);
  std::vector<Body> bodies{Body(b.description())};
  std::vector<std::unique_ptr<const ForceElement>> elements;
  elements.push_back(std::make_unique<UniformGravity>(
      g, std::vector<UniformGravity::BodyMass>{{0, b.mass(), b.description().p_BoBcm_B}}));
  return Model(std::move(bodies), std::move(elements), formulation);
}

TEST_CASE("gravity's generalized forces on a flexible body equal the nodal sums",
          "[core][flexible]") {
  // Σ_k L_kᵀ m_k g with L_k = [I, −A ũ_k, A Φ_k]: the rows are Σ m_k g (force), Σ m_k ũ_k Aᵀ g
  // (torque about Br, body frame) and Σ m_k Φ_kᵀ Aᵀ g (modal). The hub is a point with Φ = 0.
  // The invariant forms (s_t = s0 + S q_f, S) are the same sums reassociated, so they agree to
  // round-off: ~1e-16 × Σ m_k |ū_k| |g| ≈ 1e-16 × 20 × 10; 1e-11 leaves margin while any wrong
  // sign, arm or missing hub is O(1–100).
  const Eigen::Vector3d g(0.3, -1.2, -9.81);
  std::mt19937 rng(7);
  for (FlexibleFormulation formulation : {kCoupled, kLte}) {
    const Model model = spinner_with_gravity(formulation, g);
    const Body& b = model.body(0);
    Workspace ws = model.make_workspace();
    for (int trial = 0; trial < 5; ++trial) {
      State state{random_state(b, rng)};
      REQUIRE(state[0].q_f.norm() > 0.01);
      model.compute_wrenches({0.1, 0.1}, state, ws);
      const Wrench& w = ws.wrenches[0];
      // LTE: the loads act on the undeformed body (q_f seen as 0 for the arms).
      BodyState seen = state[0];
      if (formulation == kLte) seen.q_f.setZero();
      const NodalBody nb = nodal_body(b, seen);
      const Eigen::Matrix3d A = rotation::rotation_matrix(seen.theta_WB);
      Eigen::Vector3d f = Eigen::Vector3d::Zero(), tau_B = Eigen::Vector3d::Zero();
      Eigen::VectorXd Q = Eigen::VectorXd::Zero(b.mode_count());
      for (std::size_t k = 0; k < nb.m.size(); ++k) {
        const Eigen::Vector3d mg = nb.m[k] * g;
        f += mg;
        tau_B += (-A * skew(nb.u_B[k])).transpose() * mg;
        Q += (A * nb.phi[k]).transpose() * mg;
      }
      INFO(to_string(formulation) << " trial " << trial);
      CHECK((w.f_W - f).norm() < 1e-11);
      CHECK((A.transpose() * w.tau_Br_W - tau_B).norm() < 1e-11);
      CHECK((w.Q_f - Q).norm() < 1e-11);
      // Q_f depends on q_f in neither model (S is constant); the torque's arm does in the coupled
      // one: the deformed moment differs from the undeformed one by Σ m_k (Φ_k q_f) × Aᵀg.
      if (formulation == kCoupled) {
        const NodalBody undeformed = nodal_body(b, [&] {
          BodyState z = state[0];
          z.q_f.setZero();
          return z;
        }());
        Eigen::Vector3d tau0 = Eigen::Vector3d::Zero();
        for (std::size_t k = 0; k < undeformed.m.size(); ++k)
          tau0 += undeformed.m[k] * undeformed.u_B[k].cross(A.transpose() * g);
        CHECK((tau0 - tau_B).norm() > 1e-3);
      }
    }
  }
}

/// Rows [start, 6 + n) of dynamics_residual at the accelerations of compute_accelerations.
double residual_norm(const Model& model, const State& state, double t, Eigen::Index start,
                     Eigen::VectorXd* rhs_scale = nullptr) {
  Workspace ws = model.make_workspace();
  Accelerations acc = model.make_accelerations();
  const Loads loads = model.compute_accelerations({t, t}, state, ws, acc);
  Eigen::VectorXd r(6 + model.body(0).mode_count());
  model.dynamics_residual(0, loads, acc[0], ws, r);
  if (rhs_scale != nullptr) *rhs_scale = ws.flexible[0].rhs;
  return r.tail(r.size() - start).norm();
}

TEST_CASE("the accelerations satisfy the dynamics residual", "[core][flexible]") {
  // compute_accelerations solves M v = Q by Cholesky (coupled) or block forward substitution
  // (LTE); dynamics_residual forms M v − Q independently of that solve. The residual is then
  // round-off: cond(M) ≈ 1e3 here (hub 10 kg, beam 1 kg, inertia 0.2–1 kg·m²) times
  // ε_mach |Q| with |Q| ≲ 1e2 gives ~1e-11; 1e-9 is the bound. A wrong block in either solve
  // leaves an O(|Q|) residual; perturbing the modal accelerations shows the check can fail.
  std::mt19937 rng(11);
  for (FlexibleFormulation formulation : {kCoupled, kLte}) {
    INFO(to_string(formulation));
    const Model spinner = flexible_spinner_model(formulation);
    const Model cantilever = rotating_cantilever_model(formulation, 3.0);
    for (int trial = 0; trial < 4; ++trial) {
      State s{random_state(spinner.body(0), rng)};
      // t = 0.25: the hub torque pulse at its peak.
      Eigen::VectorXd rhs;
      CHECK(residual_norm(spinner, s, 0.25, 0, &rhs) < 1e-9);
      CHECK(rhs.norm() > 1.0);
      // Prescribed: only the modal rows are equations; the rigid rows are the drive's reactions.
      State c = cantilever.initial_state();
      const BodyState r = random_state(cantilever.body(0), rng);
      c[0].q_f = r.q_f;
      c[0].qd_f = r.qd_f;
      cantilever.apply_prescribed_motion(0.7, c);
      CHECK(residual_norm(cantilever, c, 0.7, 6) < 1e-9);
    }
    // Able to fail: the residual sees a change of the modal accelerations.
    State s = spinner.initial_state();
    Workspace ws = spinner.make_workspace();
    Accelerations acc = spinner.make_accelerations();
    const Loads loads = spinner.compute_accelerations({0.25, 0.25}, s, ws, acc);
    acc[0].qdd_f[0] += 1e-3;
    Eigen::VectorXd res(6 + spinner.body(0).mode_count());
    spinner.dynamics_residual(0, loads, acc[0], ws, res);
    CHECK(res.norm() > 1e-4);
  }
}

TEST_CASE("LTE rigid accelerations ignore the elastic state, coupled ones do not",
          "[core][flexible]") {
  // LTE: the rigid motion is the undeformed body's (M_Rf = M_θf = 0, inertia at q_f = 0,
  // loads on the undeformed body), so changing q_f, q̇_f must leave a_WBr and α̅ bit-identical
  // up to the order of floating-point operations (nothing of q_f enters them): 1e-13 relative.
  // Coupled: the elastic state changes them by O(|q_f|·m_beam/m) ≈ 1e-2 here.
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  std::mt19937 rng(3);
  for (FlexibleFormulation formulation : {kCoupled, kLte}) {
    const Model model = spinner_with_gravity(formulation, g);
    Workspace ws = model.make_workspace();
    Accelerations a1 = model.make_accelerations(), a2 = model.make_accelerations();
    State s{random_state(model.body(0), rng)};
    model.compute_accelerations({0.2, 0.2}, s, ws, a1);
    State s2 = s;
    s2[0].q_f = random_state(model.body(0), rng).q_f;
    s2[0].qd_f *= -2.0;
    model.compute_accelerations({0.2, 0.2}, s2, ws, a2);
    const double change =
        (a1[0].a_WBr - a2[0].a_WBr).norm() + (a1[0].alpha_WB_B - a2[0].alpha_WB_B).norm();
    const double scale = a1[0].a_WBr.norm() + a1[0].alpha_WB_B.norm();
    INFO(to_string(formulation) << " change " << change << " scale " << scale);
    if (formulation == kLte) {
      CHECK(change <= 1e-13 * scale);
    } else {
      CHECK(change > 1e-3);
    }
    // The modal accelerations depend on q_f in both (stiffness).
    CHECK((a1[0].qdd_f - a2[0].qdd_f).norm() > 1e-2);
  }
}

TEST_CASE("kinetic energy and momenta of a flexible body equal the nodal sums",
          "[core][flexible]") {
  // T = ½ Σ m_k |ṙ_k|² + ½ ω̄ᵀ I_hub ω̄,  p = Σ m_k ṙ_k,  H_O = Σ m_k r_k × ṙ_k + A I_hub ω̄, with
  // ṙ_k from eq. 14. The model evaluates them from the invariants (the rows of M v), the same
  // sums reassociated: round-off ≈ 1e-16 × (Σ m |r| |ṙ| ≈ 1e2); bound 1e-11. Any missing term
  // (hub, S q̇_f, Ī_θf q̇_f, the deformation in s_t or Ī_θθ) is ≥ 1e-5 at these states.
  std::mt19937 rng(5);
  const Model spinner = flexible_spinner_model(kCoupled);
  const Model lte = flexible_spinner_model(kLte);
  const Model cantilever = rotating_cantilever_model(kCoupled, 2.0);
  for (const Model* model : {&spinner, &lte, &cantilever}) {
    const Body& b = model->body(0);
    for (int trial = 0; trial < 5; ++trial) {
      State state{random_state(b, rng)};
      if (b.is_prescribed()) {
        const BodyState r = state[0];
        state = model->initial_state();
        state[0].q_f = r.q_f;
        state[0].qd_f = r.qd_f;
        model->apply_prescribed_motion(0.4, state);
      }
      const NodalBody nb = nodal_body(b, state[0]);
      const Eigen::Matrix3d A = rotation::rotation_matrix(state[0].theta_WB);
      const Eigen::Vector3d& w = state[0].w_WB_B;
      double T = 0.5 * w.dot(nb.I_hub * w);
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      Eigen::Vector3d H = A * (nb.I_hub * w);
      for (std::size_t k = 0; k < nb.m.size(); ++k) {
        T += 0.5 * nb.m[k] * nb.v_W[k].squaredNorm();
        p += nb.m[k] * nb.v_W[k];
        H += nb.m[k] * nb.r_W[k].cross(nb.v_W[k]);
      }
      INFO("body " << b.name() << " " << to_string(model->formulation()) << " trial " << trial);
      CHECK(model->kinetic_energy(state) == Approx(T).epsilon(0).margin(1e-11));
      CHECK((model->linear_momentum_W(state) - p).norm() < 1e-11);
      CHECK((model->angular_momentum_W(state) - H).norm() < 1e-11);
      // Able to fail: without the elastic rates the sums differ.
      State rigid = state;
      rigid[0].qd_f.setZero();
      CHECK(std::abs(model->kinetic_energy(rigid) - T) > 1e-5);
    }
  }
}

/// d/dt (T + V) along the ODE right-hand side at the state `state` and time t, by central
/// differences: E(y ± ε f) at t ± ε (prescribed bodies follow their law at t ± ε).
double energy_rate(const Model& model, const State& state, double t) {
  const reference::OdeForm ode(model);
  reference::OdeForm::Scratch scratch = ode.make_scratch();
  std::vector<double> y(static_cast<std::size_t>(ode.size())), f(y.size());
  ode.pack(state, y.data());
  ode.rhs({t, t}, y.data(), f.data(), scratch);
  const double eps = 1e-5;
  auto energy_at = [&](double s) {
    std::vector<double> z(y.size());
    for (std::size_t i = 0; i < y.size(); ++i) z[i] = y[i] + s * f[i];
    State st = model.initial_state();
    ode.unpack(t + s, z.data(), st);
    Workspace ws = model.make_workspace();
    return model.kinetic_energy(st) + model.potential_energy({t + s, t + s}, st, ws);
  };
  return (energy_at(eps) - energy_at(-eps)) / (2.0 * eps);
}

/// The spinner with every mode's damping ratio set to zeta.
Model damped_spinner(double zeta, double torque_z) {
  const Model base = flexible_spinner_model(kCoupled, 4, 10, torque_z);
  RigidBodyDescription d = base.body(0).description();
  d.flexible->modal.damping_ratio.setConstant(zeta);
  std::vector<Body> bodies{Body(d)};
  std::vector<std::unique_ptr<const ForceElement>> elements;
  elements.push_back(std::make_unique<AppliedTorque>(0, Eigen::Vector3d(0.0, 0.0, torque_z),
                                                     LoadFrame::kWorld,
                                                     TimeProfile::sin2_pulse(0.0, 0.5)));
  return Model(std::move(bodies), std::move(elements), kCoupled);
}

TEST_CASE("the coupled equations balance energy with the applied and damping powers",
          "[core][flexible]") {
  // dE/dt = Γ·ω (hub torque, world) − q̇_fᵀ D q̇_f. Central difference with ε = 1e-5:
  // truncation O(ε² |E'''|) ≈ 1e-10 × O(1e3) (the highest mode, ω ≈ 40 rad/s, gives E''' ~
  // ω³ × elastic amplitude terms), round-off ε_mach |E|/ε ≈ 1e-16 × 50 / 1e-5 ≈ 1e-9; bound
  // 1e-6. The powers are O(1–5) W (torque) and O(0.1) W (damping), and the elastic Coriolis
  // and centrifugal terms each exchange O(1) W between rigid and elastic energy, so a wrong
  // sign in any of them is far above the bound.
  std::mt19937 rng(13);
  for (int trial = 0; trial < 3; ++trial) {
    for (double zeta : {0.0, 0.05}) {
      for (double torque : {0.0, 5.0}) {
        const Model model = damped_spinner(zeta, torque);
        const Body& b = model.body(0);
        State s{random_state(b, rng)};
        const double t = 0.25;  // sin²(π t / 0.5) = 1: the full torque
        const Eigen::Matrix3d A = rotation::rotation_matrix(s[0].theta_WB);
        const double torque_power = Eigen::Vector3d(0, 0, torque).dot(A * s[0].w_WB_B);
        const double damping_power = s[0].qd_f.dot(b.modal_damping().cwiseProduct(s[0].qd_f));
        INFO("zeta " << zeta << " torque " << torque << " damping power " << damping_power);
        if (zeta > 0.0) REQUIRE(damping_power > 0.01);
        CHECK(energy_rate(model, s, t) == Approx(torque_power - damping_power).margin(1e-6));
      }
    }
  }
  // Prescribed body: the drive supplies the power τ_d φ̇ (driving_torque about the axis).
  const Model cantilever = rotating_cantilever_model(kCoupled, 3.0);
  State c = cantilever.initial_state();
  const BodyState r = random_state(cantilever.body(0), rng);
  c[0].q_f = r.q_f;
  c[0].qd_f = r.qd_f;
  const double t = 0.3;
  cantilever.apply_prescribed_motion(t, c);
  Workspace ws = cantilever.make_workspace();
  Accelerations acc = cantilever.make_accelerations();
  const Loads loads = cantilever.compute_accelerations({t, t}, c, ws, acc);
  const double drive_power = cantilever.driving_torque(0, loads, acc[0], ws) * 3.0;
  INFO("drive power " << drive_power);
  CHECK(std::abs(drive_power) > 0.01);
  CHECK(energy_rate(cantilever, c, t) == Approx(drive_power).margin(1e-6));
}

TEST_CASE("flexible evaluations allocate nothing", "[core][flexible][allocation]") {
  const Model coupled = flexible_spinner_model(kCoupled);
  const Model lte = flexible_spinner_model(kLte);
  const Model cantilever = rotating_cantilever_model(kCoupled, 3.0);
  const Model cantilever_lte = rotating_cantilever_model(kLte, 3.0);
  for (const Model* model : {&coupled, &lte, &cantilever, &cantilever_lte}) {
    const reference::OdeForm ode(*model);
    reference::OdeForm::Scratch ode_scratch = ode.make_scratch();
    const reference::DaeForm dae(*model);
    reference::DaeForm::Scratch dae_scratch = dae.make_scratch();
    std::vector<double> y(static_cast<std::size_t>(ode.size())), f(y.size());
    std::vector<double> z(static_cast<std::size_t>(dae.size())), zp(z.size()), r(z.size());
    State s = model->initial_state();
    s[0].q_f.setConstant(0.02);
    s[0].qd_f.setConstant(-0.1);
    ode.pack(s, y.data());
    const LoadContext ctx{0.25, 0.25};
    dae.initial_values(ctx, s, z.data(), zp.data());
    Workspace ws = model->make_workspace();
    Accelerations acc = model->make_accelerations();
    Eigen::VectorXd res(6 + model->body(0).mode_count());
    double energy = 0.0;
    auto evaluate = [&] {
      ode.rhs(ctx, y.data(), f.data(), ode_scratch);
      dae.residual(ctx, z.data(), zp.data(), r.data(), dae_scratch);
      const Loads loads = model->compute_accelerations(ctx, s, ws, acc);
      model->dynamics_residual(0, loads, acc[0], ws, res);
      energy = model->kinetic_energy(s) + model->potential_energy(ctx, s, ws) +
               model->driving_torque(0, loads, acc[0], ws);
    };
    evaluate();  // warm-up
    const long n = testing::count_allocations(evaluate);
    INFO("model " << model->body(0).name() << " " << to_string(model->formulation()));
    CHECK(std::isfinite(energy));
    CHECK(n == 0);
  }
  // The counter sees Eigen's heap matrices (see evaluation_allocation_test.cpp).
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
  double sum = 0.0;
  const long m = testing::count_allocations([&] {
    const Eigen::VectorXd v = Eigen::VectorXd::Constant(7, 1.0);
    sum = v.sum();
  });
  CHECK(sum == 7.0);
  CHECK(m >= 1);
#endif
}

}  // namespace
}  // namespace flexref::core
