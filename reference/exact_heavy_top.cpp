// The double instantiation of the exact heavy top (exact_heavy_top.hpp); long double and
// float128 are instantiated in precision/.
#include "reference/exact_heavy_top_impl.hpp"

namespace flexref::reference {

template class HeavyTopExactTpl<double>;

}  // namespace flexref::reference
