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

}  // namespace flexref::core
