#include <catch2/catch.hpp>
#include <string>

#include "app/converge_command.hpp"
#include "app/input_checks.hpp"
#include "app/modal_truncation_command.hpp"
#include "app/reference_command.hpp"
#include "app/run_command.hpp"
#include "app/work_precision_command.hpp"

namespace flexref::app {
namespace {

TEST_CASE("every command that takes --model has the same default (lte)", "[app][model]") {
  // Every command defaults to the same model, so `work-precision scenes/flexible_spinner.toml`
  // runs and a run and its reference solve the same equations. The
  // command line binds --model to these members (app/cli_options.cpp, add_model_option).
  // Named objects, not temporaries: GCC 12 warns maybe-uninitialized (falsely) on a member
  // access of a temporary that holds a std::map (lie::MethodOptions::values).
  const RunOptions run;
  const ReferenceOptions reference;
  const ConvergeOptions converge;
  const WorkPrecisionOptions work_precision;
  const ModalTruncationCommandOptions modes;
  CHECK(run.model == core::FlexibleFormulation::kLte);
  CHECK(reference.model == core::FlexibleFormulation::kLte);
  CHECK(converge.model == core::FlexibleFormulation::kLte);
  CHECK(work_precision.model == core::FlexibleFormulation::kLte);
  CHECK(modes.model == core::FlexibleFormulation::kLte);
  // Commands without --model (check, figure, stability, lte-map's scene) load the same one.
  CHECK(load_scene("scenes/flexible_spinner.toml").model->formulation() ==
        core::FlexibleFormulation::kLte);
}

}  // namespace
}  // namespace flexref::app
