/// \file method_options.cpp
#include "lie/method_options.hpp"

namespace flexref::lie {

double MethodOptions::value(std::string_view name, double fallback) const {
  const auto found = values.find(name);
  return found == values.end() ? fallback : found->second;
}

}  // namespace flexref::lie
