#pragma once
/// \file input_error_checks.hpp
/// The one check that a reader refuses bad input the way the CLI reports it: a core::InputError
/// naming the file, the line and the key, with "file:line: " and "key '...'" in its message and
/// a fragment saying what was expected.
#include <catch2/catch.hpp>
#include <string>

#include "core/error.hpp"

namespace flexref::testing {

/// Calls parse(text, "bad.toml") and requires a core::InputError at `line` and `key` whose
/// message contains `fragment` (when not empty). `what` names the parser in the failure.
template <class Parse>
void require_input_error(Parse&& parse, const std::string& what, const std::string& text, int line,
                         const std::string& key, const std::string& fragment = "") {
  using Catch::Matchers::Contains;
  INFO("input text:\n" << text);
  try {
    (void)parse(text, "bad.toml");
  } catch (const core::InputError& e) {
    const std::string message = e.what();
    INFO("what(): " << message);
    CHECK(e.file() == "bad.toml");
    CHECK(e.line() == line);
    CHECK(e.key() == key);
    CHECK_THAT(message, Contains("bad.toml:" + std::to_string(line) + ": "));
    if (!key.empty()) CHECK_THAT(message, Contains("key '" + key + "'"));
    if (!fragment.empty()) CHECK_THAT(message, Contains(fragment));
    return;
  }
  FAIL(what << " accepted the input");
}

}  // namespace flexref::testing
