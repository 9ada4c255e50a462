/// \file precision_order_study_test.cpp
/// Label study: double, extended and quad references of every scene the extended/quad model
/// carries, over the whole scene (rigid scenes about a minute on one core; the ten flexible
/// scenes some minutes each in quad).
#include "tests/precision/precision_order.hpp"

namespace flexref::precision {
namespace {

TEST_CASE("double, extended and quad agree in that order over whole scenes", "[precision]") {
  for (const char* file : kSupportedScenes) check_precision_order(file, 1e9);
}

TEST_CASE("double, extended and quad agree in that order over whole flexible scenes",
          "[precision]") {
  for (const char* file : kFlexibleScenes) check_precision_order(file, 1e9);
}

}  // namespace
}  // namespace flexref::precision
