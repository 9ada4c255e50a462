/// \file reference_policy_test.cpp
/// The reference policy (studies/reference_policy.hpp): which reference a study runs against
/// for each --reference-precision, when "auto" retries with a quad reference, what it says,
/// and the cost guard's refusal. The study and the references are stand-ins that record their
/// calls; the real quad retry on book_toss is tests/app/cli_test.sh's and
/// tests/python/test_reference_policy.py's.
#include "studies/reference_policy.hpp"

#include <catch2/catch.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace flexref::studies {
namespace {

/// References that record what was asked of them; quad_within_budget refuses over `budget`.
class RecordingReferences final : public HighPrecisionReferences {
 public:
  bool possible = true;
  double cost_seconds = 1.0;  ///< what the quad reference would take
  mutable std::vector<std::string> calls;

  std::shared_ptr<const trajectory::CertifiedReference> compute(
      ReferencePrecision precision) const override {
    calls.push_back(std::string("compute ") + to_string(precision));
    return std::make_shared<const trajectory::CertifiedReference>();
  }
  bool quad_possible() const override { return possible; }
  std::shared_ptr<const trajectory::CertifiedReference> quad_within_budget(
      double budget_seconds, std::string& refused) const override {
    calls.push_back("quad within budget");
    if (budget_seconds > 0.0 && cost_seconds > budget_seconds) {
      refused = "over its budget";
      return nullptr;
    }
    return std::make_shared<const trajectory::CertifiedReference>();
  }
};

/// A study whose result is the list of references it ran against; the double run leaves
/// `uncertified_on_double` levels uncertified, a given reference none.
struct Runs {
  std::vector<std::string> against;
  int uncertified = 0;
};

PolicyStudy<Runs> recording_study(int uncertified_on_double) {
  auto runs = std::make_shared<Runs>();
  PolicyStudy<Runs> study;
  study.run = [runs, uncertified_on_double](
                  std::shared_ptr<const trajectory::CertifiedReference> reference,
                  ReferencePrecision precision) {
    runs->against.push_back(reference ? to_string(precision) : "own double");
    runs->uncertified = reference ? 0 : uncertified_on_double;
    return *runs;
  };
  study.uncertified = [](const Runs& r) {
    return r.uncertified == 0 ? std::string()
                              : "could not certify " + std::to_string(r.uncertified) + " level(s)";
  };
  return study;
}

TEST_CASE("auto retries with a quad reference only when double leaves something uncertified",
          "[studies][reference_policy]") {
  RecordingReferences references;
  SECTION("uncertified levels: the quad reference, the study again, the note") {
    const auto out =
        run_with_reference_policy(ReferencePrecision::kAuto, 600.0, references, recording_study(2));
    CHECK(out.result.against == std::vector<std::string>{"own double", "quad"});
    CHECK(out.precision_used == ReferencePrecision::kQuad);
    CHECK(out.note ==
          "could not certify 2 level(s): the study was repeated with a quad-precision "
          "reference (docs/precision.md)");
    CHECK(out.refused.empty());
    CHECK(references.calls == std::vector<std::string>{"quad within budget"});
  }
  SECTION("everything certified: the double run alone, no note") {
    const auto out =
        run_with_reference_policy(ReferencePrecision::kAuto, 600.0, references, recording_study(0));
    CHECK(out.result.against == std::vector<std::string>{"own double"});
    CHECK(out.precision_used == ReferencePrecision::kDouble);
    CHECK(out.note.empty());
    CHECK(references.calls.empty());
  }
  SECTION("a scene the quad model cannot carry: the double result stands, no note") {
    references.possible = false;
    const auto out =
        run_with_reference_policy(ReferencePrecision::kAuto, 600.0, references, recording_study(2));
    CHECK(out.result.against == std::vector<std::string>{"own double"});
    CHECK(out.precision_used == ReferencePrecision::kDouble);
    CHECK(out.note.empty());
    CHECK(references.calls.empty());
  }
  SECTION("over the budget: the double result stands and the note says why") {
    references.cost_seconds = 10.0;
    const auto out =
        run_with_reference_policy(ReferencePrecision::kAuto, 1.0, references, recording_study(2));
    CHECK(out.result.against == std::vector<std::string>{"own double"});
    CHECK(out.precision_used == ReferencePrecision::kDouble);
    CHECK(out.refused == "over its budget");
    CHECK(out.note == "could not certify 2 level(s); over its budget");
  }
}

TEST_CASE("a given precision is computed before the one run, and double never asks for one",
          "[studies][reference_policy]") {
  RecordingReferences references;
  for (ReferencePrecision p : {ReferencePrecision::kExtended, ReferencePrecision::kQuad}) {
    references.calls.clear();
    const auto out = run_with_reference_policy(p, 600.0, references, recording_study(2));
    CHECK(out.result.against == std::vector<std::string>{to_string(p)});
    CHECK(out.precision_used == p);
    CHECK(out.note.empty());
    CHECK(references.calls == std::vector<std::string>{std::string("compute ") + to_string(p)});
  }
  references.calls.clear();
  const auto out =
      run_with_reference_policy(ReferencePrecision::kDouble, 600.0, references, recording_study(2));
  CHECK(out.result.against == std::vector<std::string>{"own double"});
  CHECK(out.precision_used == ReferencePrecision::kDouble);
  CHECK(out.note.empty());
  CHECK(references.calls.empty());
}

TEST_CASE("reference precision names parse and print, and others are refused with the list",
          "[studies][reference_policy]") {
  for (const char* name : {"auto", "double", "extended", "quad"}) {
    CHECK(std::string(to_string(parse_reference_precision(name))) == name);
  }
  CHECK_THROWS_WITH(
      parse_reference_precision("float"),
      Catch::Contains("'float'") && Catch::Contains("expected auto, double, extended or quad"));
}

}  // namespace
}  // namespace flexref::studies
