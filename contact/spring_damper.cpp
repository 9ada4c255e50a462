/// \file spring_damper.cpp
/// SpringDamperTpl<double> (spring_damper.hpp).
#include "contact/spring_damper.hpp"

namespace flexref::contact {
template class SpringDamperTpl<double>;
}  // namespace flexref::contact
