#include "app/cli_validators.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <optional>
#include <sstream>

namespace flexref::app {
namespace {

std::string text(double x) {
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

CLI::Validator number_check(const std::string& description,
                            std::function<std::string(double)> check) {
  return CLI::Validator(
      [check = std::move(check)](std::string& s) -> std::string {
        std::string why;
        const std::optional<double> x = parse(s, why);
        return x ? check(*x) : why;
      },
      description);
}

}  // namespace

CLI::Validator positive_number() {
  return number_check("POSITIVE", [](double x) {
    return x > 0.0 ? std::string() : "must be a positive number, got " + text(x);
  });
}

CLI::Validator non_negative_number() {
  return number_check("NONNEGATIVE", [](double x) {
    return x >= 0.0 ? std::string() : "must be zero or positive, got " + text(x);
  });
}

CLI::Validator number_in(double lo, double hi) {
  return number_check("in [" + text(lo) + ", " + text(hi) + "]", [lo, hi](double x) {
    return x >= lo && x <= hi ? std::string()
                              : "must lie in [" + text(lo) + ", " + text(hi) + "], got " + text(x);
  });
}

CLI::Validator integer_in(long lo, long hi) {
  return number_check("integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
                      [lo, hi](double x) {
                        if (x != std::floor(x)) return "must be an integer, got " + text(x);
                        if (x < static_cast<double>(lo) || x > static_cast<double>(hi)) {
                          return "must be an integer in [" + std::to_string(lo) + ", " +
                                 std::to_string(hi) + "], got " + text(x);
                        }
                        return std::string();
                      });
}

}  // namespace flexref::app
