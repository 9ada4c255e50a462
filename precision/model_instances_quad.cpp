/// \file model_instances_quad.cpp
/// core::BodyTpl, core::ModelTpl and OdeSystemTpl in boost::multiprecision::float128 (the quad
/// references; libquadmath).
// Eigen's NumTraits for float128 before any Eigen type of it.
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/float128.hpp>

#include "core/body_impl.hpp"
#include "core/model_impl.hpp"
#include "precision/ode_system_impl.hpp"

namespace flexref::core {
template class BodyTpl<boost::multiprecision::float128>;
template class ModelTpl<boost::multiprecision::float128>;
}  // namespace flexref::core

namespace flexref::precision {
template class OdeSystemTpl<boost::multiprecision::float128>;
}  // namespace flexref::precision
