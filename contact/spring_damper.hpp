#pragma once
/// \file spring_damper.hpp
/// A linear spring–damper between two points (a point of body A and a point of body B or of
/// the ground) with a rest length: an axial force along the line between them, as in Andrews'
/// squeezing mechanism and the IFToMM benchmarks (docs/joints.md, "Spring–dampers"). With
/// d = p_Q − p_P, ℓ = |d|, e = d/ℓ and ℓ̇ = e·(v_Q − v_P):
/// \f[ V = \tfrac12 k (\ell - \ell_0)^2,\qquad f = \big(k(\ell - \ell_0) + c\,\dot\ell\big)\,e
///     \ \text{on } P,\qquad -f \text{ on } Q, \f]
/// dissipated power c ℓ̇² ≥ 0. The points are points of the bodies' rigid parts (hubs). At ℓ = 0
/// the line, and so the force, is undefined: the element applies no force there (a spring with
/// ℓ₀ > 0 never reaches it in a physical motion; the references would see the kink).
/// Generic in the scalar type S (core/force_element.hpp): double is instantiated in
/// spring_damper.cpp, long double and float128 in precision/.
#include <cmath>
#include <limits>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact/bushing.hpp"
#include "core/element_text.hpp"
#include "core/force_element.hpp"

namespace flexref::contact {

/// Stiffness k (N/m), damping c (N·s/m) and rest length ℓ₀ (m) of a spring–damper.
struct SpringDamperParameters {
  double stiffness = 0.0;
  double damping = 0.0;
  double rest_length = 0.0;
};

template <typename S>
class SpringDamperTpl final : public core::ForceElementTpl<S> {
 public:
  using typename core::ForceElementTpl<S>::Context;
  using typename core::ForceElementTpl<S>::Kinematics;
  using Vector3 = Eigen::Matrix<S, 3, 1>;

  /// \throws std::invalid_argument when the first end is the ground, both ends are one body,
  /// a parameter is negative or not finite.
  SpringDamperTpl(int body_a, const Eigen::Vector3d& p_BoP_B, int body_b,
                  const Eigen::Vector3d& p_BoQ_B, const SpringDamperParameters& parameters)
      : body_a_(body_a), body_b_(body_b), parameters_(parameters) {
    if (body_a < 0) throw std::invalid_argument("spring-damper: the first end must be a body");
    if (body_b == body_a) throw std::invalid_argument("spring-damper: both ends on one body");
    if (body_b < kGround) throw std::invalid_argument("spring-damper: unknown second end");
    for (const double x : {parameters.stiffness, parameters.damping, parameters.rest_length}) {
      if (!(x >= 0.0 && std::isfinite(x))) {
        throw std::invalid_argument(
            "spring-damper: stiffness, damping and rest length must be finite and >= 0");
      }
    }
    if (!p_BoP_B.allFinite() || !p_BoQ_B.allFinite()) {
      throw std::invalid_argument("spring-damper: the points must be finite");
    }
    p_ = p_BoP_B.cast<S>();
    q_ = p_BoQ_B.cast<S>();
  }
  /// The same element in another scalar type.
  template <typename U>
  explicit SpringDamperTpl(const SpringDamperTpl<U>& other)
      : SpringDamperTpl(other.body_a(), other.point_a(), other.body_b(), other.point_b(),
                        other.parameters()) {}

  void add_wrenches(const Context& context, std::span<const Kinematics> bodies,
                    std::span<core::WrenchTpl<S>> wrenches) const override {
    (void)context;
    const Line line = line_of(bodies);
    if (!(line.length > S(0))) return;
    const Vector3 f = (S(parameters_.stiffness) * (line.length - S(parameters_.rest_length)) +
                       S(parameters_.damping) * line.rate) *
                      line.e;
    wrenches[static_cast<std::size_t>(body_a_)].add_force_at(f, line.r_a);
    if (body_b_ != kGround) wrenches[static_cast<std::size_t>(body_b_)].add_force_at(-f, line.r_b);
  }
  S potential_energy(const Context& context, std::span<const Kinematics> bodies) const override {
    (void)context;
    const S stretch = line_of(bodies).length - S(parameters_.rest_length);
    return S(0.5) * S(parameters_.stiffness) * stretch * stretch;
  }
  /// A spring and a damper: E + W_d is conserved from the start (core/invariants.hpp).
  double energy_balanced_from() const override { return -std::numeric_limits<double>::infinity(); }
  S dissipated_power(const Context& context, std::span<const Kinematics> bodies) const override {
    (void)context;
    if (parameters_.damping == 0.0) return S(0);
    const S rate = line_of(bodies).rate;
    return S(parameters_.damping) * rate * rate;
  }
  bool depends_on_velocity() const override { return parameters_.damping > 0.0; }
  int max_body_index() const override { return std::max(body_a_, body_b_); }
  std::vector<int> coupled_bodies() const override {
    if (body_b_ == kGround) return {body_a_};
    return {body_a_, body_b_};
  }
  std::string describe() const override {
    return describe_with_names(std::span<const core::Body>{});
  }
  std::string describe_with_names(std::span<const core::Body> bodies) const override {
    std::ostringstream out;
    out << "spring-damper: " << core::body_text(body_a_, bodies) << " point "
        << core::vector_text(point_a()) << " to " << core::body_text(body_b_, bodies) << " point "
        << core::vector_text(point_b()) << ", k = " << parameters_.stiffness
        << " N/m, c = " << parameters_.damping << " N*s/m, rest length " << parameters_.rest_length
        << " m";
    return out.str();
  }
  /// Kind "spring": its stiffness over the smallest effective mass of the two ends (the same added
  /// compliance as a bushing's translational mode, contact/compliance.hpp).
  void append_penalty_modes(std::span<const core::Body> bodies,
                            std::vector<core::PenaltyMode>& modes) const override {
    if (parameters_.stiffness <= 0.0) return;
    const BushingEnd a{body_a_, point_a(), Eigen::Vector3d::UnitZ()};
    const BushingEnd b{body_b_, point_b(), Eigen::Vector3d::UnitZ()};
    BushingParameters p;
    p.stiffness = parameters_.stiffness;
    p.damping = parameters_.damping;
    std::vector<core::PenaltyMode> bushing_modes;
    detail::append_bushing_modes(bodies, a, b, p, false, bushing_modes);
    for (core::PenaltyMode& m : bushing_modes) {
      m.label = "";
      m.kind = "spring";
      modes.push_back(m);
    }
  }

  int body_a() const { return body_a_; }
  int body_b() const { return body_b_; }
  Eigen::Vector3d point_a() const { return p_.template cast<double>(); }
  Eigen::Vector3d point_b() const { return q_.template cast<double>(); }
  const SpringDamperParameters& parameters() const { return parameters_; }

 private:
  /// The line from P to Q: its length, direction e, rate ℓ̇ and the arms from each body's Br.
  struct Line {
    S length = S(0);
    S rate = S(0);
    Vector3 e = Vector3::Zero();
    Vector3 r_a = Vector3::Zero();
    Vector3 r_b = Vector3::Zero();
  };
  Line line_of(std::span<const Kinematics> bodies) const {
    using std::sqrt;
    Line line;
    const Kinematics& ka = bodies[static_cast<std::size_t>(body_a_)];
    line.r_a = ka.p_BrP_W(p_);
    const Vector3 p_P = ka.state->p_WBr + line.r_a;
    const Vector3 v_P = ka.state->v_WBr + (ka.R_WB * ka.state->w_WB_B).cross(line.r_a);
    Vector3 p_Q = q_;
    Vector3 v_Q = Vector3::Zero();
    if (body_b_ != kGround) {
      const Kinematics& kb = bodies[static_cast<std::size_t>(body_b_)];
      line.r_b = kb.p_BrP_W(q_);
      p_Q = kb.state->p_WBr + line.r_b;
      v_Q = kb.state->v_WBr + (kb.R_WB * kb.state->w_WB_B).cross(line.r_b);
    }
    const Vector3 d = p_Q - p_P;
    line.length = sqrt(d.squaredNorm());
    if (line.length > S(0)) {
      line.e = d / line.length;
      line.rate = line.e.dot(v_Q - v_P);
    }
    return line;
  }

  int body_a_;
  int body_b_;
  Vector3 p_;  ///< P from Bo of body A, body frame
  Vector3 q_;  ///< Q from Bo of body B, body frame (ground: world point)
  SpringDamperParameters parameters_;
};

using SpringDamper = SpringDamperTpl<double>;
extern template class SpringDamperTpl<double>;

}  // namespace flexref::contact
