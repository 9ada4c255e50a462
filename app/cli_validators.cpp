#include "app/cli_validators.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <optional>
#include <sstream>

namespace flexref::app {
namespace {

/// A bound of a range as the help and messages print it: a few digits.
std::string bound_text(double x) {
  std::ostringstream out;
  out.precision(6);
  out << x;
  return out.str();
}

/// The whole string as a finite double, or nullopt (with why) when it is not one.
std::optional<double> parse(const std::string& s, std::string& why) {
  const char* begin = s.c_str();
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(begin, &end);
  if (s.empty() || end == begin || *end != '\0') {
    why = "'" + s + "' is not a number";
    return std::nullopt;
  }
  if (!std::isfinite(x) || errno == ERANGE) {
    // ERANGE also flags underflow to 0 or a subnormal (1e-400): not the number the user typed.
    why = "'" + s + "' is not a finite number that double precision represents";
    return std::nullopt;
  }
  return x;
}

/// A validator of a number: `check(x, written)` returns "" or why x (the user wrote `written`,
/// which messages quote as it was typed) is refused.
CLI::Validator number_check(const std::string& description,
                            std::function<std::string(double, const std::string&)> check) {
  return CLI::Validator(
      [check = std::move(check)](std::string& s) -> std::string {
        std::string why;
        const std::optional<double> x = parse(s, why);
        return x ? check(*x, s) : why;
      },
      description);
}

}  // namespace

std::string number_text(double x) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

CLI::Validator positive_number() {
  return number_check("POSITIVE", [](double x, const std::string& s) {
    return x > 0.0 ? std::string() : "must be a positive number, got " + s;
  });
}

CLI::Validator non_negative_number() {
  return number_check("NONNEGATIVE", [](double x, const std::string& s) {
    return x >= 0.0 ? std::string() : "must be zero or positive, got " + s;
  });
}

CLI::Validator number_in(double lo, double hi) {
  return number_check("in [" + bound_text(lo) + ", " + bound_text(hi) + "]",
                      [lo, hi](double x, const std::string& s) {
                        return x >= lo && x <= hi ? std::string()
                                                  : "must lie in [" + bound_text(lo) + ", " +
                                                        bound_text(hi) + "], got " + s;
                      });
}

CLI::Validator integer_in(long lo, long hi) {
  return number_check("integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
                      [lo, hi](double x, const std::string& s) {
                        if (x != std::floor(x)) return "must be an integer, got " + s;
                        if (x < static_cast<double>(lo) || x > static_cast<double>(hi)) {
                          return "must be an integer in [" + std::to_string(lo) + ", " +
                                 std::to_string(hi) + "], got " + s;
                        }
                        return std::string();
                      });
}

CLI::Validator positive_integer() {
  return number_check("POSITIVE INTEGER", [](double x, const std::string& s) {
    if (x != std::floor(x)) return "must be a whole number, got " + s;
    return x >= 1.0 ? std::string() : "must be a positive whole number, got " + s;
  });
}

}  // namespace flexref::app
