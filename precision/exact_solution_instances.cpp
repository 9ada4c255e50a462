// The exact solutions of reference/ (exact_torque_free.hpp, exact_heavy_top.hpp,
// exact_pendulum.hpp, written once for any scalar type) instantiated in extended (long double) and
// quad (float128) precision. Only precision/ sees float128 (it links libquadmath); the double
// instantiations are in reference/. <boost/multiprecision/eigen.hpp> gives Eigen the NumTraits of
// float128 and must come before any Eigen use of it.
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/float128.hpp>

#include "reference/exact_heavy_top_impl.hpp"
#include "reference/exact_pendulum_impl.hpp"
#include "reference/exact_torque_free_impl.hpp"

namespace flexref::reference {

#define FLEXREF_INSTANTIATE_EXACT(S)                                                              \
  template Eigen::Matrix<S, 4, 1> zxz_euler_parameters<S>(S, S, S, S);                            \
  template Eigen::Matrix<S, 4, 1> detail::unit_euler_parameters<S>(const Eigen::Matrix<S, 4, 1>&, \
                                                                   const char*);                  \
  template elliptic::JacobiValuesTpl<S> elliptic::jacobi<S>(S, S, S);                             \
  template S elliptic::complete_k<S>(S);                                                          \
  template S elliptic::incomplete_f<S>(S, S, S);                                                  \
  template class elliptic::CircularPiTpl<S>;                                                      \
  template class elliptic::ShiftedHyperbolicPiTpl<S>;                                             \
  template class TorqueFreeExactTpl<S>;                                                           \
  template class HeavyTopExactTpl<S>;                                                             \
  template class PendulumExactTpl<S>;

FLEXREF_INSTANTIATE_EXACT(long double)
FLEXREF_INSTANTIATE_EXACT(boost::multiprecision::float128)

#undef FLEXREF_INSTANTIATE_EXACT

}  // namespace flexref::reference
