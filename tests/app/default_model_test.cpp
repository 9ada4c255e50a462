#include <catch2/catch.hpp>
#include <string>

#include "app/commands.hpp"
#include "app/modal_truncation_command.hpp"
#include "app/work_precision_command.hpp"

namespace flexref::app {
namespace {

TEST_CASE("every command that takes --model has the same default (lte)", "[app][model]") {
  // Every command defaults to the same model, so `work-precision scenes/flexible_spinner.toml`
  // runs and a run and its reference solve the same equations. The
  // command line binds --model to these members (app/cli_options.cpp, add_model_option).
  CHECK(RunOptions{}.model == core::FlexibleFormulation::kLte);
  CHECK(ReferenceOptions{}.model == core::FlexibleFormulation::kLte);
  CHECK(ConvergeOptions{}.model == core::FlexibleFormulation::kLte);
  CHECK(WorkPrecisionOptions{}.model == core::FlexibleFormulation::kLte);
  CHECK(ModalTruncationCommandOptions{}.model == core::FlexibleFormulation::kLte);
  // Commands without --model (check, figure, stability, lte-map's scene) load the same one.
  CHECK(load_scene("scenes/flexible_spinner.toml").model->formulation() ==
        core::FlexibleFormulation::kLte);
}

}  // namespace
}  // namespace flexref::app
