#pragma once
/// \file body_impl.hpp
/// BodyTpl<S>'s definitions, included by the translation units that instantiate it
/// (core/body.cpp for double; precision/model_instances_*.cpp for long double and float128).
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "core/body.hpp"
#include "core/unit_vector_tpl.hpp"
#include "flexible/modal_invariants_tpl.hpp"

namespace flexref::core {

namespace detail {

/// The scene's unit quaternion in S: as given in double (validated unit to 1e-12), normalized
/// in another S, whose round-off resolves that gap (the data's unit vectors, as unit_vector_as).
template <typename S>
Eigen::Matrix<S, 4, 1> unit_quaternion_as(const Eigen::Vector4d& theta) {
  if constexpr (std::is_same_v<S, double>) {
    return theta;
  } else {
    using std::sqrt;
    Eigen::Matrix<S, 4, 1> q = theta.cast<S>();
    q /= sqrt(q.squaredNorm());
    return q;
  }
}

}  // namespace detail

template <typename S>
BodyTpl<S>::BodyTpl(RigidBodyDescription description) : description_(std::move(description)) {
  const auto& d = description_;
  validate_body_description(d);
  axis_W_ = unit_vector_as<S>(d.prescribed.axis_W);
  theta_WB0_ = detail::unit_quaternion_as<S>(d.initial.theta_WB);
  const Eigen::Matrix3d I_sym_d = 0.5 * (d.I_Bcm_B + d.I_Bcm_B.transpose());
  const Matrix3 I_sym = I_sym_d.template cast<S>();

  if (!d.flexible) {
    mass_ = S(d.mass);
    if (d.motion == MotionKind::kFree) {
      p_BoBr_B_ = d.p_BoBcm_B.template cast<S>();
      p_BrBcm_B_.setZero();
      I_Br_B_ = I_sym;
    } else {
      p_BoBr_B_ = d.motion == MotionKind::kPivot ? Vector3(d.p_BoPivot_B.template cast<S>())
                                                 : Vector3::Zero();
      p_BrBcm_B_ = d.p_BoBcm_B.template cast<S>() - p_BoBr_B_;
      I_Br_B_ = shift_inertia_from_com<S>(I_sym, mass_, p_BrBcm_B_);
    }
  } else {
    const flexible::ModalData& modal = d.flexible->modal;
    const Vector3 hub_c = d.p_BoBcm_B.template cast<S>();
    // Invariants about Bo first (nodes, then the hub), to find the undeformed centre of mass;
    // then about Br, the nodes shifted by −p_BoBr (mode shapes are unchanged by the shift).
    flexible::ModalInvariantsTpl<S> about_Bo;
    if constexpr (std::is_same_v<S, double>) {
      about_Bo = flexible::make_modal_invariants(modal);
    } else {
      about_Bo =
          flexible::modal_invariants_tpl<S>(modal.mass, modal.p_BoNode_B, modal.phi, nullptr);
    }
    flexible::add_rigid_part_tpl<S>(about_Bo, S(d.mass), hub_c, I_sym);
    mass_ = about_Bo.mass;
    const Vector3 p_BoBcm_B = about_Bo.s0 / mass_;
    switch (d.motion) {
      case MotionKind::kFree:
        p_BoBr_B_ = p_BoBcm_B;
        break;
      case MotionKind::kPivot:
        p_BoBr_B_ = d.p_BoPivot_B.template cast<S>();
        break;
      case MotionKind::kPrescribed:
        p_BoBr_B_.setZero();
        break;
    }
    p_BrBcm_B_ = p_BoBcm_B - p_BoBr_B_;
    mode_count_ = modal.mode_count();
    stiffness_ = modal.stiffness.template cast<S>();
    if constexpr (std::is_same_v<S, double>) {
      // The nodes and the geometric stiffness shifted in double, d_i from the data's m_ff.
      flexible::ModalData shifted = modal;
      shifted.p_BoNode_B.colwise() -= p_BoBr_B_;
      if (shifted.geometric) shifted.geometric = shifted.geometric->shifted(p_BoBr_B_);
      invariants_ = flexible::make_modal_invariants(shifted);
      damping_ = flexible::modal_damping(modal);
    } else {
      // Every sum and shift in S; d_i = 2 ζ_i √(K_i μ_i), μ_i = (m_ff)_ii
      // (flexible::modal_damping).
      invariants_ = flexible::modal_invariants_tpl<S>(modal.mass, modal.p_BoNode_B, modal.phi,
                                                      modal.geometric ? &*modal.geometric : nullptr,
                                                      p_BoBr_B_);
      damping_ = Vector::Zero(mode_count_);
      for (int i = 0; i < mode_count_; ++i) {
        using std::sqrt;
        damping_(i) =
            S(2) * S(modal.damping_ratio(i)) * sqrt(stiffness_(i) * invariants_.m_ff(i, i));
      }
    }
    flexible::add_rigid_part_tpl<S>(invariants_, S(d.mass), Vector3(hub_c - p_BoBr_B_), I_sym);
    I_Br_B_ = invariants_.I0;
    frequencies_ = flexible::natural_frequencies(modal);
    modal_mass_ = flexible::ModalMassFactorTpl<S>(invariants_);
    if (d.motion != MotionKind::kPrescribed) {
      if (const std::string problem = inertia_problem(I_Br_B_.template cast<double>());
          !problem.empty()) {
        throw std::invalid_argument("body '" + d.name + "': the undeformed inertia about the " +
                                    (d.motion == MotionKind::kFree ? "centre of mass" : "pivot") +
                                    " " + problem +
                                    " (nodes on a line have no inertia about it: add a hub)");
      }
    }
  }
  if (d.motion == MotionKind::kPrescribed) {
    I_Br_B_inverse_ = Matrix3::Zero();
  } else {
    I_Br_B_inverse_ = I_Br_B_.inverse();
  }
  using std::isfinite;
  if (!I_Br_B_.allFinite() || !I_Br_B_inverse_.allFinite() || !isfinite(S(1) / mass_)) {
    throw InertiaRangeError("body '" + d.name +
                            "': mass or inertia out of the representable range");
  }
}

template <typename S>
typename BodyTpl<S>::Vector3 BodyTpl<S>::p_BrP_B(const TrackedPoint& point,
                                                 const Vector& q_f) const {
  Vector3 p = point.p_BoP_B.template cast<S>() - p_BoBr_B_;
  if (point.node >= 0) {
    p.noalias() += description_.flexible->modal.mode_rows(point.node).template cast<S>() * q_f;
  }
  return p;
}

}  // namespace flexref::core
