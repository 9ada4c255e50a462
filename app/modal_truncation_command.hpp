#pragma once
/// \file modal_truncation_command.hpp
/// `flexref modes`: how the reference tip deflection and hub attitude of a scene's flexible
/// body change with the number of retained modes (studies/modal_truncation.hpp).
#include <string>
#include <vector>

#include "app/default_model.hpp"
#include "studies/reference_solver_name.hpp"

namespace flexref::app {

struct ModalTruncationCommandOptions {
  std::string scene;
  std::vector<int> modes = {4, 8, 16, 32, 64};
  std::string body;   ///< empty: the first flexible body
  std::string point;  ///< empty: the node point farthest from Br
  studies::ReferenceSolver solver = studies::ReferenceSolver::kOdeint;
  double rtol = 1e-10;
  double estimate_factor = 10.0;
  double end_time = 0.0;                                  ///< s (0: the scene's)
  core::FlexibleFormulation model = kDefaultFormulation;  ///< --model coupled|lte
  int jobs = 0;                                           ///< 0: all cores
  std::string out_dir = "out/modes";
};

int modal_truncation_command(const ModalTruncationCommandOptions& options);

}  // namespace flexref::app
