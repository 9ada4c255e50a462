#pragma once
/// \file calculix_import_report.hpp
/// What `flexref import-modes` prints of a CalculiX import (scene/calculix_import.hpp) and
/// records, as comments, in the modal-data file.
#include <string>

#include "scene/calculix_import.hpp"

namespace flexref::scene {

/// The report printed by `flexref import-modes` and recorded (as comments) in the modal-data
/// file: sources, mass properties (solid vs nodes), removed rigid modes, the frequency table.
std::string format_calculix_import_report(const CalculixImport& result);

}  // namespace flexref::scene
