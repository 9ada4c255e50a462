#pragma once
/// \file reference_record.hpp
/// A certified reference in a study's record (study.toml, FILE.meta.toml): the `[reference]`
/// table and the checks behind an error estimate (trajectory/certified_reference.hpp).
#include <string>

#include "studies/study_record.hpp"
#include "trajectory/certified_reference.hpp"

namespace flexref::studies {

/// The `[reference]` table a study records next to its results: solver, method and why, the
/// Newton systems (implicit solvers), tolerance (0 for the exact solution), the estimate and how it
/// was made, and one
/// `[[reference.check]]` per comparison solution.
void add_reference(StudyRecord& record, const trajectory::CertifiedReference& reference);

/// One `[[<array>]]` table per check of an estimate (role, solver, method, rtol, steps,
/// distance, used, note).
void add_estimate_checks(StudyRecord& record, const std::string& array,
                         const trajectory::ReferenceEstimate& estimate);

}  // namespace flexref::studies
