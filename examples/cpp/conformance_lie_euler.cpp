/// The user's stepper joins flexref's stepper conformance suite in one line (installed as
/// <flexref/testing/stepper_conformance.hpp>; Catch2 v2): registry entry, two-sided order at
/// its claimed order on an exact flow, failure semantics, independent bodies, unit Euler
/// parameters.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
#include <flexref/testing/stepper_conformance.hpp>

#include "lie_euler_stepper.hpp"

namespace {
const bool kRegistered = (user::register_lie_euler(), true);
}  // namespace

FLEXREF_STEPPER_CONFORMANCE_TESTS("lie_euler")
