// The double instantiation of the exact torque-free solution and of the elliptic building
// blocks (exact_torque_free.hpp); long double and float128 are instantiated in precision/.
#include "reference/exact_torque_free_impl.hpp"

namespace flexref::reference {

template Eigen::Matrix<double, 4, 1> zxz_euler_parameters<double>(double, double, double, double);
template Eigen::Matrix<double, 4, 1> detail::unit_euler_parameters<double>(
    const Eigen::Matrix<double, 4, 1>&, const char*);
template elliptic::JacobiValuesTpl<double> elliptic::jacobi<double>(double, double, double);
template double elliptic::complete_k<double>(double);
template double elliptic::incomplete_f<double>(double, double, double);
template class elliptic::CircularPiTpl<double>;
template class elliptic::ShiftedHyperbolicPiTpl<double>;
template class TorqueFreeExactTpl<double>;

}  // namespace flexref::reference
