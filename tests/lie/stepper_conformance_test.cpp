/// The conformance suite (tests/support/stepper_conformance.hpp) for every built-in scheme, and
/// for a user's stepper registered from outside the library (examples/cpp/lie_euler_stepper.hpp,
/// the explicit Lie–Euler method, first order): one line each. Plus the registry itself.
#include "tests/support/stepper_conformance.hpp"

#include <catch2/catch.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "examples/cpp/lie_euler_stepper.hpp"
#include "lie/method_registry.hpp"
#include "lie/stepper.hpp"

namespace {

// Registered before main(), as a user's program would register at start-up.
const bool kLieEulerRegistered = (user::register_lie_euler(), true);

}  // namespace

FLEXREF_STEPPER_CONFORMANCE_TESTS("c1")
FLEXREF_STEPPER_CONFORMANCE_TESTS("c2")
FLEXREF_STEPPER_CONFORMANCE_TESTS("nmb")
FLEXREF_STEPPER_CONFORMANCE_TESTS("genalpha")
FLEXREF_STEPPER_CONFORMANCE_TESTS("lie_euler")

namespace flexref::lie {
namespace {

TEST_CASE("the registry lists the built-in schemes first and refuses bad entries",
          "[lie][conformance]") {
  REQUIRE(kLieEulerRegistered);
  const std::vector<std::string> names = scheme_names();
  const std::vector<std::string> builtin = builtin_scheme_names();
  CHECK(builtin == std::vector<std::string>{"c1", "c2", "nmb"});
  CHECK(std::vector<std::string>(names.begin(), names.begin() + 3) == builtin);
  CHECK(std::find(names.begin(), names.end(), "lie_euler") != names.end());
  for (const char* name : {"c1", "c2", "nmb"}) {
    CHECK(find_method(name)->claimed_order == 2);  // Simo–Wong and Krysl–Endres claim order 2
  }
  const core::Model model = testing::free_spin();
  CHECK_THROWS_WITH(make_stepper("rk4", model, {}),
                    Catch::Matchers::Contains("unknown scheme 'rk4'"));
  const StepperFactory factory = [](const core::Model& m, const MethodOptions& options) {
    return make_stepper("c2", m, options);
  };
  CHECK_THROWS_WITH(register_method({"c2", 2, "", factory}),
                    Catch::Matchers::Contains("already registered"));
  CHECK_THROWS_AS(register_method({"bad name", 2, "", factory}), std::invalid_argument);
  CHECK_THROWS_AS(register_method({"zero", 0, "", factory}), std::invalid_argument);
  CHECK_THROWS_AS(register_method({"none", 1, "", nullptr}), std::invalid_argument);
  CHECK(find_method("zero") == nullptr);
}

}  // namespace
}  // namespace flexref::lie
