#pragma once
/// \file high_precision_references.hpp
/// The extended and quad references of a study (docs/precision.md), behind the interface the
/// reference policy uses (studies/reference_policy.hpp): Odeint's Bulirsch-Stoer in that
/// precision at its default tolerance, certified by its own error estimate in the study's
/// metric, with a progress line on standard error.
#include <memory>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "studies/reference_policy.hpp"
#include "studies/reference_solver_name.hpp"

namespace flexref::studies {

class StudyReferences final : public HighPrecisionReferences {
 public:
  /// The references of the study `study` ("converge": the progress line's name) of `scene` at
  /// `times`, certified in `metric`; `reference_solver` is the study's --reference-solver
  /// (kAuto unless one was named: a named solver rules out extended and quad). Keeps
  /// references to scene and times: they must outlive this object.
  StudyReferences(const scene::Scene& scene, const std::vector<double>& times, std::string metric,
                  ReferenceSolver reference_solver, std::string study);

  /// Throws std::invalid_argument when the scene (precision::check_supported), the metric
  /// (relative, rotation+points, rotation or points) or a named reference solver rules it out.
  std::shared_ptr<const trajectory::CertifiedReference> compute(
      ReferencePrecision wanted) const override;
  bool quad_possible() const override;
  std::shared_ptr<const trajectory::CertifiedReference> quad_within_budget(
      double budget_seconds, std::string& refused) const override;

 private:
  std::shared_ptr<const trajectory::CertifiedReference> solve(ReferencePrecision wanted,
                                                              double budget_seconds) const;

  const scene::Scene& scene_;
  const std::vector<double>& times_;
  std::string metric_;
  ReferenceSolver reference_solver_;
  std::string study_;
};

}  // namespace flexref::studies
