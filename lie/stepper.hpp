#pragma once
/// \file stepper.hpp
/// The common interface of the Lie-group Newmark-family schemes (docs/design/schemes.md), after
/// Drake's IntegratorBase and Boost.Odeint's stepper concept: initialize, step(h) returning a
/// status, order(), name(). A failed step leaves the state at the start of the step and says
/// why. Stepping allocates nothing.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/model.hpp"
#include "lie/method_options.hpp"

namespace flexref::lie {

struct StepStatus {
  bool ok = true;
  std::string message;  ///< why the step failed (time and residual), empty when ok
};

class Stepper {
 public:
  virtual ~Stepper() = default;
  Stepper(const Stepper&) = delete;
  Stepper& operator=(const Stepper&) = delete;

  /// "c1", "c2", "nmb", "genalpha", or a user method's registered name.
  virtual std::string_view name() const = 0;
  /// The order the scheme's authors claim (measured by the tests and `converge`).
  virtual int order() const = 0;
  /// Force evaluations per step (1 for the explicit schemes).
  virtual double force_evaluations_per_step() const = 0;

  /// Sets t0 and the state, and evaluates the initial accelerations.
  virtual void initialize(double t0, const core::State& state) = 0;
  /// Advances by h. Steps never straddle a known load discontinuity: the driver makes them
  /// land on it.
  virtual StepStatus step(double h) = 0;

  virtual double time() const = 0;
  virtual const core::State& state() const = 0;
  /// True when step() also advances the contacts' worn depths (core::StateTpl::wear_depth;
  /// docs/wear.md). A method that does not leaves them at their initial values, so the driver
  /// refuses it on a model with a wear law rather than run it on a frozen geometry.
  virtual bool integrates_wear_depth() const { return false; }

 protected:
  Stepper() = default;
};

/// A stepper of a registered method (lie/method_registry.hpp: "c1", "c2", "nmb", "genalpha" and
/// whatever the program registered), built by its factory with `options`; throws
/// std::invalid_argument for any other name, or when the factory refuses an option value
/// (genalpha: ρ∞ outside [0, 1]). The model must outlive the stepper.
std::unique_ptr<Stepper> make_stepper(std::string_view name, const core::Model& model,
                                      const MethodOptions& options);

/// The names make_stepper accepts, in registration order: {"c1", "c2", "nmb", "genalpha", ...}.
std::vector<std::string> scheme_names();
/// The schemes a study runs when none are named: every registered method but those registered
/// with in_default_studies = false (genalpha, the comparison method, runs when named).
std::vector<std::string> default_scheme_names();
/// The paper's hybrid schemes flexref registers at start-up, {"c1", "c2", "nmb"}: what a study
/// or test means by "the built-in schemes", whatever else a program registered. The comparison
/// method "genalpha" (lie/genalpha.hpp) is registered after them and is not among these.
std::vector<std::string> builtin_scheme_names();

}  // namespace flexref::lie
