#include "core/element_text.hpp"

namespace flexref::core {

std::string profile_text(const TimeProfile& p) {
  std::ostringstream out;
  switch (p.shape()) {
    case TimeProfile::Shape::kConstant:
      return "constant";
    case TimeProfile::Shape::kSin2Pulse:
      out << "sin2 pulse on [" << p.start() << ", " << p.start() + p.duration() << ")";
      return out.str();
    case TimeProfile::Shape::kRectangularPulse:
      out << "rectangular pulse on [" << p.start() << ", " << p.start() + p.duration() << ")";
      return out.str();
    case TimeProfile::Shape::kHarmonic:
      out << "harmonic sin(2 pi " << p.frequency() << " Hz t + " << p.phase() << ")";
      return out.str();
  }
  return {};
}

std::string body_text(int body, std::span<const Body> bodies) {
  if (body < 0) return "ground";
  const auto b = static_cast<std::size_t>(body);
  if (b < bodies.size()) return "body '" + bodies[b].name() + "'";
  return "body[" + std::to_string(body + 1) + "]";
}

namespace {

/// "1st", "2nd", "3rd", "4th", …, "11th", "12th", "13th", "21st".
std::string ordinal(int n) {
  const int tens = n % 100;
  const char* suffix = "th";
  if (tens < 11 || tens > 13) {
    if (n % 10 == 1) suffix = "st";
    if (n % 10 == 2) suffix = "nd";
    if (n % 10 == 3) suffix = "rd";
  }
  return std::to_string(n) + suffix;
}

}  // namespace

std::string node_text(int body, int node, std::span<const Body> bodies) {
  const auto b = static_cast<std::size_t>(body);
  if (body >= 0 && b < bodies.size() && bodies[b].is_flexible()) {
    const std::vector<std::string>& names = bodies[b].description().flexible->modal.node_names;
    const auto k = static_cast<std::size_t>(node);
    if (node >= 0 && k < names.size()) return "node '" + names[k] + "'";
  }
  return "node #" + std::to_string(node + 1) + " (unnamed; the " + ordinal(node + 1) +
         " node of the modal data)";
}

}  // namespace flexref::core
