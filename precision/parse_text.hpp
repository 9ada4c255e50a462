#pragma once
/// \file parse_text.hpp
/// A run's values as text and back: print() writes a value with the digits that round-trip
/// its precision; parse_in reads it back exactly: its text is parsed in the run's own precision
/// (the decimal of a 21-digit extended value is not the value, only its nearest 21-digit decimal)
/// and the result converted to the wider S, which represents it exactly. Internal to precision/ (it
/// sees float128).
#include <boost/multiprecision/float128.hpp>
#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "precision/precision.hpp"

namespace flexref::precision::detail {

template <typename S>
std::string print(const S& x, int digits) {
  std::ostringstream out;
  out << std::setprecision(digits) << x;
  return out.str();
}

template <typename S>
S parse_in(const std::string& text, Precision p) {
  switch (p) {
    case Precision::kDouble:
      return S(std::strtod(text.c_str(), nullptr));
    case Precision::kExtended:
      if constexpr (!std::is_same_v<S, double>) return S(std::strtold(text.c_str(), nullptr));
      break;
    case Precision::kQuad:
      if constexpr (std::is_same_v<S, boost::multiprecision::float128>) {
        return boost::multiprecision::float128(text);
      }
      break;
  }
  throw std::logic_error("parse_in: a value of a higher precision than the scalar");
}

}  // namespace flexref::precision::detail
