#include <iomanip>
#include <iostream>
#include <stdexcept>

#include "app/commands.hpp"
#include "core/error.hpp"
#include "studies/error_metrics.hpp"
#include "studies/trajectory_table.hpp"

namespace flexref::app {

int compare_command(const CompareOptions& options) {
  const studies::TrajectoryTable run = studies::read_csv(options.run);
  const studies::TrajectoryTable ref = studies::read_csv(options.reference);
  studies::ComparisonReport report;
  try {
    report = studies::compare_trajectories(run, ref);
  } catch (const std::invalid_argument& e) {
    throw core::InputError(
        options.run, 0, "",
        std::string("cannot compare with ") + options.reference + ": " + e.what());
  }
  std::cout << std::left << std::setw(28) << "quantity" << std::setw(7) << "unit" << std::right
            << std::setw(13) << "L-inf" << std::setw(13) << "RMS" << std::setw(13) << "final"
            << "\n";
  for (const auto& q : report.quantities) {
    std::cout << std::left << std::setw(28) << q.name << std::setw(7) << q.unit << std::right
              << std::scientific << std::setprecision(4) << std::setw(13) << q.norms.linf
              << std::setw(13) << q.norms.rms << std::setw(13) << q.norms.final << "\n";
  }
  std::cout << "metric " << options.metric << ": " << std::scientific << std::setprecision(6)
            << studies::metric_value(report, options.metric) << "\n";
  return kExitOk;
}

}  // namespace flexref::app
