#include "studies/study_record.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <toml.hpp>
#include <vector>

namespace {

using flexref::studies::StudyRecord;
using flexref::studies::toml_float;

toml::value parse(const std::string& text) {
  std::istringstream in(text);
  return toml::parse(in, "record.toml");
}

TEST_CASE("a record reads back through a TOML parser with every value intact", "[study_record]") {
  StudyRecord record;
  // A title with quotes, a Windows path and a newline: string-built TOML broke on each.
  const std::string title = "Fig. 1 \"free\" spin";
  const std::string path = "C:\\Users\\me\\scene.toml";
  const std::string two_lines = "first\nsecond";
  record.table("study")
      .set("title", title)
      .set("file", path)
      .set("note", two_lines)
      .set("levels", 6)
      .set("steps", std::size_t{1000})
      .set("flag", true)
      .set("dt", 0.1)
      .set("third", 1.0 / 3.0)
      .set("tiny", 1e-300)
      .set("integral", 2.0)
      .set("schemes", std::vector<std::string>{"c1", "c\"2"})
      .set("values", std::vector<double>{1e-3, 0.1, 7.0});
  record.table("scene").set("name", "book_toss");
  flexref::studies::add_versions(record);

  const toml::value v = parse(record.to_toml());
  CHECK(toml::find<std::string>(v, "study", "title") == title);
  CHECK(toml::find<std::string>(v, "study", "file") == path);
  CHECK(toml::find<std::string>(v, "study", "note") == two_lines);
  CHECK(toml::find<long long>(v, "study", "levels") == 6);
  CHECK(toml::find<long long>(v, "study", "steps") == 1000);
  CHECK(toml::find<bool>(v, "study", "flag"));
  // Shortest round-trip formatting: the exact double comes back (== on purpose).
  CHECK(toml::find<double>(v, "study", "dt") == 0.1);
  CHECK(toml::find<double>(v, "study", "third") == 1.0 / 3.0);
  CHECK(toml::find<double>(v, "study", "tiny") == 1e-300);
  CHECK(toml::find(v, "study", "integral").is_floating());
  CHECK(toml::find<std::vector<std::string>>(v, "study", "schemes") ==
        std::vector<std::string>{"c1", "c\"2"});
  CHECK(toml::find<std::vector<double>>(v, "study", "values") ==
        std::vector<double>{1e-3, 0.1, 7.0});
  CHECK(toml::find<std::string>(v, "scene", "name") == "book_toss");
  CHECK(!toml::find<std::string>(v, "versions", "sundials").empty());
}

TEST_CASE("tables and keys keep their insertion order, a key set twice is replaced",
          "[study_record]") {
  StudyRecord record;
  record.table("scene").set("name", "a");
  record.table("study").set("kind", "converge").set("dt", 0.5);
  record.table("scene").set("model", "lte");
  record.table("study").set("dt", 0.25);
  const std::string text = record.to_toml();
  CHECK(text ==
        "[scene]\nname = \"a\"\nmodel = \"lte\"\n\n[study]\nkind = \"converge\"\ndt = 0.25\n");
}

TEST_CASE("arrays of tables nest under their table and read back in order", "[study_record]") {
  StudyRecord record;
  record.table("reference").set("solver", "cvode");
  record.append("reference.check").set("solver", "odeint").set("distance", 1e-9);
  record.append("reference.check").set("solver", "arkode").set("distance", 2e-9);
  record.table("versions").set("flexref", "0.1.0");
  const toml::value v = parse(record.to_toml());
  const auto& checks = toml::find(v, "reference", "check").as_array();
  REQUIRE(checks.size() == 2);
  CHECK(toml::find<std::string>(checks[1], "solver") == "arkode");
  CHECK(toml::find<double>(checks[0], "distance") == 1e-9);
  CHECK(toml::find<std::string>(v, "reference", "solver") == "cvode");
  CHECK_THROWS_AS(record.append("a..b"), std::invalid_argument);
}

TEST_CASE("long strings stay on one line", "[study_record]") {
  StudyRecord record;
  const std::string text(300, 'x');
  record.table("t").set("long", text + "\n" + text);
  const std::string toml = record.to_toml();
  CHECK(toml == "[t]\nlong = \"" + text + "\\n" + text + "\"\n");
}

TEST_CASE("non-finite numbers are written as TOML spells them", "[study_record]") {
  CHECK(toml_float(std::numeric_limits<double>::infinity()) == "inf");
  CHECK(toml_float(-std::numeric_limits<double>::infinity()) == "-inf");
  CHECK(toml_float(std::numeric_limits<double>::quiet_NaN()) == "nan");
  CHECK(toml_float(-3.0) == "-3.0");
  CHECK(toml_float(1e22) == "1e+22");
  const toml::value v = parse("x = " + toml_float(std::numeric_limits<double>::infinity()) + "\n");
  CHECK(std::isinf(toml::find<double>(v, "x")));
}

TEST_CASE("keys and table names that are not bare TOML keys are refused", "[study_record]") {
  StudyRecord record;
  CHECK_THROWS_AS(record.table("study").set("a key", 1), std::invalid_argument);
  CHECK_THROWS_AS(record.table("study").set("", 1), std::invalid_argument);
  CHECK_THROWS_AS(record.table("x.y"), std::invalid_argument);
}

}  // namespace
