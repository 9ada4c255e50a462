#pragma once
/// \file velocity_layout.hpp
/// The stacked generalized coordinates of a model, written once for everything that stacks them
/// (the model's joints, genalpha's Newton unknowns, the DAE form's multiplier rows): body b's
/// generalized velocity v_b = (v_WBr, ω̄, q̇_f) — and likewise its accelerations (a_WBr, α̅, q̈_f)
/// and position increments (δp_Br, δφ_B, δq_f) — occupies [offset(b), offset(b) + 6 + n_b) of
/// one vector of size() entries, and of those rows the body integrates the ones its motion does
/// not fix (a pivot's translation and a prescribed body's rigid six are fixed). The one layout
/// rule: no other code computes these offsets or this mask (docs/decisions.md).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "core/state.hpp"

namespace flexref::core {

struct VelocityLayout {
  /// Per body its first entry, then the total size N (bodies + 1 entries).
  std::vector<int> offsets;
  /// Per body, how many of its rigid rows its motion fixes, first: free 0, pivot 3 (the
  /// translation), prescribed 6; empty: none fixed.
  std::vector<int> fixed_rows;

  /// The layout of bodies (anything with mode_count() and motion(): core::BodyTpl<S>).
  template <typename Bodies>
  static VelocityLayout of(const Bodies& bodies) {
    VelocityLayout layout;
    layout.offsets.push_back(0);
    for (const auto& b : bodies) {
      layout.offsets.push_back(layout.size() + 6 + b.mode_count());
      layout.fixed_rows.push_back(b.is_free() ? 0 : b.is_prescribed() ? 6 : 3);
    }
    return layout;
  }

  int size() const { return offsets.empty() ? 0 : offsets.back(); }
  int body_count() const { return offsets.empty() ? 0 : static_cast<int>(offsets.size()) - 1; }
  int offset(int body) const { return offsets[static_cast<std::size_t>(body)]; }
  int width(int body) const {
    return offsets[static_cast<std::size_t>(body) + 1] - offsets[static_cast<std::size_t>(body)];
  }
  /// n_b: the body's modal coordinates.
  int mode_count(int body) const { return width(body) - 6; }
  /// Whether body b integrates its row k (0–2 translation, 3–5 rotation, 6… modes).
  bool integrated(int body, int k) const {
    return fixed_rows.empty() || k >= fixed_rows[static_cast<std::size_t>(body)];
  }

  /// v ← the stacked (v_WBr, ω̄, q̇_f) of the bodies' states (v sized size()).
  template <typename S, typename Vector>
  void stack_velocities(const StateTpl<S>& state, Vector& v) const {
    for (int b = 0; b < body_count(); ++b) {
      const BodyStateTpl<S>& s = state[static_cast<std::size_t>(b)];
      const int o = offset(b);
      v.template segment<3>(o) = s.v_WBr;
      v.template segment<3>(o + 3) = s.w_WB_B;
      v.segment(o + 6, mode_count(b)) = s.qd_f;
    }
  }
  /// x ← the stacked (a_WBr, α̅, q̈_f).
  template <typename S, typename Vector>
  void stack_accelerations(const AccelerationsTpl<S>& accelerations, Vector& x) const {
    for (int b = 0; b < body_count(); ++b) {
      const BodyAccelerationTpl<S>& a = accelerations[static_cast<std::size_t>(b)];
      const int o = offset(b);
      x.template segment<3>(o) = a.a_WBr;
      x.template segment<3>(o + 3) = a.alpha_WB_B;
      x.segment(o + 6, mode_count(b)) = a.qdd_f;
    }
  }
  /// The accelerations from their stack x.
  template <typename S, typename Vector>
  void unstack_accelerations(const Vector& x, AccelerationsTpl<S>& accelerations) const {
    for (int b = 0; b < body_count(); ++b) {
      BodyAccelerationTpl<S>& a = accelerations[static_cast<std::size_t>(b)];
      const int o = offset(b);
      a.a_WBr = x.template segment<3>(o);
      a.alpha_WB_B = x.template segment<3>(o + 3);
      a.qdd_f = x.segment(o + 6, mode_count(b));
    }
  }
  /// The velocities of the rows each body integrates moved by the stacked δ (the others, which
  /// its motion fixes, left as they are).
  template <typename S, typename Vector>
  void add_to_velocities(const Vector& delta, StateTpl<S>& state) const {
    for (int b = 0; b < body_count(); ++b) {
      BodyStateTpl<S>& s = state[static_cast<std::size_t>(b)];
      const int o = offset(b);
      if (integrated(b, 5)) {
        if (integrated(b, 0)) s.v_WBr += delta.template segment<3>(o);
        s.w_WB_B += delta.template segment<3>(o + 3);
      }
      s.qd_f += delta.segment(o + 6, mode_count(b));
    }
  }
};

}  // namespace flexref::core
