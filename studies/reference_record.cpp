#include "studies/reference_record.hpp"

#include <cmath>

namespace flexref::studies {

void add_estimate_checks(StudyRecord& record, const std::string& array,
                         const trajectory::ReferenceEstimate& estimate) {
  for (const trajectory::EstimateCheck& c : estimate.checks) {
    auto& check = record.append(array);
    check.set("role", c.role)
        .set("solver", c.solver)
        .set("method", c.method)
        .set("rtol", c.rtol)
        .set("steps", c.steps)
        .set("used", c.used)
        .set("note", c.note);
    // No distance where there is none (a failed check): the note says why.
    if (!std::isnan(c.distance)) check.set("distance", c.distance);
    if (!std::isnan(c.energy_distance)) check.set("energy_distance", c.energy_distance);
  }
}

void add_reference(StudyRecord& record, const trajectory::CertifiedReference& reference) {
  const trajectory::ReferenceEstimate& e = reference.estimate;
  record.table("reference")
      .set("solver", reference.run.solver)
      .set("method", reference.run.method)
      .set("method_reason", reference.run.method_reason)
      .set("jacobian", reference.run.jacobian)
      // 0 for the exact solution, as its checks record it: it has no tolerance.
      .set("rtol", reference.run.solver == "exact" ? 0.0 : reference.run.options.rtol)
      .set("estimated_error", e.value)
      .set("metric", e.metric)
      .set("estimate_method", e.method);
  if (!std::isnan(e.energy_balance)) {
    record.table("reference")
        .set("energy_balance", e.energy_balance)
        .set("energy_balance_time", e.energy_balance_time)
        .set("energy_estimate", e.energy_estimate);
  }
  add_estimate_checks(record, "reference.check", e);
}

}  // namespace flexref::studies
