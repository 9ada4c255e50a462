#pragma once
/// \file plot.hpp
/// Runs a bundled matplotlib script. Plotting is optional: when no Python with matplotlib is
/// found the study still writes its CSV and table, and the outcome says why.
#include <string>
#include <vector>

namespace flexref::studies {

struct PlotOutcome {
  bool ok = false;
  std::string message;  ///< the file written, or why not
};

/// The first of $FLEXREF_PYTHON, /usr/bin/python3, python3 that imports matplotlib, or "".
std::string find_python_with_matplotlib();

/// Runs studies/<script> with the arguments; the PNG is written to a temporary name and
/// renamed to `png_path` only when the script succeeds.
PlotOutcome run_plot_script(const std::string& script, std::vector<std::string> arguments,
                            const std::string& png_path);

}  // namespace flexref::studies
