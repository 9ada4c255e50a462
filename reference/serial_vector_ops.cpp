/// \file serial_vector_ops.cpp
/// See serial_vector_ops.hpp. Each operation's arithmetic is SUNDIALS 6.4's nvector_serial
/// (its user guide, "The NVECTOR_SERIAL module", documents the operations; the case split of
/// the linear sum is what it computes), element by element in index order.
#include "reference/serial_vector_ops.hpp"

#include <nvector/nvector_serial.h>

#include <cmath>
#include <stdexcept>

namespace flexref::reference::sundials {

namespace {

double* values(N_Vector v) { return NV_DATA_S(v); }
sunindextype length(N_Vector v) { return NV_LENGTH_S(v); }

/// z = a x + b y, by SUNDIALS' cases: y += a x and x += b y in place (b = 1, z = y; a = 1,
/// z = x), x + y, x − y, a x + y, a x − y, a (x + y), a (x − y), else a x + b y. The in-place
/// updates keep their own three loops (y += x, y −= x, y += a x), which round as a x + y.
void linear_sum(sunrealtype a, N_Vector x, sunrealtype b, N_Vector y, N_Vector z) {
  const sunindextype n = length(x);
  // w += c u (u and w may be one vector: each element is read before it is written).
  const auto axpy = [n](sunrealtype c, const double* u, double* w) {
    if (c == 1.0) {
      for (sunindextype i = 0; i < n; ++i) w[i] += u[i];
    } else if (c == -1.0) {
      for (sunindextype i = 0; i < n; ++i) w[i] -= u[i];
    } else {
      for (sunindextype i = 0; i < n; ++i) w[i] += c * u[i];
    }
  };
  if (b == 1.0 && z == y) {
    axpy(a, values(x), values(y));
    return;
  }
  if (a == 1.0 && z == x) {
    axpy(b, values(y), values(x));
    return;
  }
  const double* xd = values(x);
  const double* yd = values(y);
  double* zd = values(z);
  if (a == 1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + yd[i];
    return;
  }
  if (a == 1.0 && b == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] - yd[i];
    return;
  }
  if (a == -1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = yd[i] - xd[i];
    return;
  }
  if (a == 1.0 || b == 1.0) {  // c v1 + v2 with v2 the vector whose coefficient is 1
    const bool first = a == 1.0;
    const sunrealtype c = first ? b : a;
    const double* v1 = first ? yd : xd;
    const double* v2 = first ? xd : yd;
    for (sunindextype i = 0; i < n; ++i) zd[i] = (c * v1[i]) + v2[i];
    return;
  }
  if (a == -1.0 || b == -1.0) {  // c v1 − v2 with v2 the vector whose coefficient is −1
    const bool first = a == -1.0;
    const sunrealtype c = first ? b : a;
    const double* v1 = first ? yd : xd;
    const double* v2 = first ? xd : yd;
    for (sunindextype i = 0; i < n; ++i) zd[i] = (c * v1[i]) - v2[i];
    return;
  }
  if (a == b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] + yd[i]);
    return;
  }
  if (a == -b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] - yd[i]);
    return;
  }
  for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) + (b * yd[i]);
}

void constant(sunrealtype c, N_Vector z) {
  double* zd = values(z);
  for (sunindextype i = 0, n = length(z); i < n; ++i) zd[i] = c;
}

void product(N_Vector x, N_Vector y, N_Vector z) {
  const double* xd = values(x);
  const double* yd = values(y);
  double* zd = values(z);
  for (sunindextype i = 0, n = length(x); i < n; ++i) zd[i] = xd[i] * yd[i];
}

void quotient(N_Vector x, N_Vector y, N_Vector z) {
  const double* xd = values(x);
  const double* yd = values(y);
  double* zd = values(z);
  for (sunindextype i = 0, n = length(x); i < n; ++i) zd[i] = xd[i] / yd[i];
}

/// z = c x: in place x *= c, a copy for c = 1, −x for c = −1, else c x.
void scale(sunrealtype c, N_Vector x, N_Vector z) {
  const sunindextype n = length(x);
  double* zd = values(z);
  if (z == x) {
    for (sunindextype i = 0; i < n; ++i) zd[i] *= c;
    return;
  }
  const double* xd = values(x);
  if (c == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i];
  } else if (c == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = -xd[i];
  } else {
    for (sunindextype i = 0; i < n; ++i) zd[i] = c * xd[i];
  }
}

void absolute(N_Vector x, N_Vector z) {
  const double* xd = values(x);
  double* zd = values(z);
  for (sunindextype i = 0, n = length(x); i < n; ++i) zd[i] = std::fabs(xd[i]);
}

void inverse(N_Vector x, N_Vector z) {
  const double* xd = values(x);
  double* zd = values(z);
  for (sunindextype i = 0, n = length(x); i < n; ++i) zd[i] = 1.0 / xd[i];
}

void add_constant(N_Vector x, sunrealtype b, N_Vector z) {
  const double* xd = values(x);
  double* zd = values(z);
  for (sunindextype i = 0, n = length(x); i < n; ++i) zd[i] = xd[i] + b;
}

// The reductions sum in index order from zero, as SUNDIALS does: no reassociation, so the
// compiler keeps them scalar and the sums are SUNDIALS' bit for bit.
sunrealtype dot_product(N_Vector x, N_Vector y) {
  const double* xd = values(x);
  const double* yd = values(y);
  sunrealtype sum = 0.0;
  for (sunindextype i = 0, n = length(x); i < n; ++i) sum += xd[i] * yd[i];
  return sum;
}

/// max |x_i| from 0, a NaN entry passed over (its comparison is false), as SUNDIALS does.
sunrealtype max_norm(N_Vector x) {
  const double* xd = values(x);
  sunrealtype largest = 0.0;
  for (sunindextype i = 0, n = length(x); i < n; ++i) {
    if (std::fabs(xd[i]) > largest) largest = std::fabs(xd[i]);
  }
  return largest;
}

sunrealtype weighted_square_sum(N_Vector x, N_Vector w) {
  const double* xd = values(x);
  const double* wd = values(w);
  sunrealtype sum = 0.0;
  for (sunindextype i = 0, n = length(x); i < n; ++i) {
    const sunrealtype p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

/// The sum over the entries whose id is positive (IDA's differential components).
sunrealtype weighted_square_sum_mask(N_Vector x, N_Vector w, N_Vector id) {
  const double* xd = values(x);
  const double* wd = values(w);
  const double* idd = values(id);
  sunrealtype sum = 0.0;
  for (sunindextype i = 0, n = length(x); i < n; ++i) {
    if (idd[i] > 0.0) {
      const sunrealtype p = xd[i] * wd[i];
      sum += p * p;
    }
  }
  return sum;
}

sunrealtype wrms_norm(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(x, w) / static_cast<sunrealtype>(length(x)));
}

sunrealtype wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  return std::sqrt(weighted_square_sum_mask(x, w, id) / static_cast<sunrealtype>(length(x)));
}

sunrealtype minimum(N_Vector x) {
  const double* xd = values(x);
  sunrealtype smallest = xd[0];
  for (sunindextype i = 1, n = length(x); i < n; ++i) {
    if (xd[i] < smallest) smallest = xd[i];
  }
  return smallest;
}

sunrealtype weighted_l2_norm(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(x, w));
}

sunrealtype l1_norm(N_Vector x) {
  const double* xd = values(x);
  sunrealtype sum = 0.0;
  for (sunindextype i = 0, n = length(x); i < n; ++i) sum += std::fabs(xd[i]);
  return sum;
}

void compare(sunrealtype c, N_Vector x, N_Vector z) {
  const double* xd = values(x);
  double* zd = values(z);
  for (sunindextype i = 0, n = length(x); i < n; ++i) zd[i] = std::fabs(xd[i]) >= c ? 1.0 : 0.0;
}

/// z = 1/x where x ≠ 0 (z untouched elsewhere); false when some x is 0.
sunbooleantype inverse_test(N_Vector x, N_Vector z) {
  const double* xd = values(x);
  double* zd = values(z);
  sunbooleantype no_zero = SUNTRUE;
  for (sunindextype i = 0, n = length(x); i < n; ++i) {
    if (xd[i] == 0.0) {
      no_zero = SUNFALSE;
    } else {
      zd[i] = 1.0 / xd[i];
    }
  }
  return no_zero;
}

}  // namespace

void use_compiled_serial_ops(N_Vector v) {
  if (v == nullptr || N_VGetVectorID(v) != SUNDIALS_NVEC_SERIAL) {
    throw std::invalid_argument("use_compiled_serial_ops: not a serial vector");
  }
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = linear_sum;
  ops->nvconst = constant;
  ops->nvprod = product;
  ops->nvdiv = quotient;
  ops->nvscale = scale;
  ops->nvabs = absolute;
  ops->nvinv = inverse;
  ops->nvaddconst = add_constant;
  ops->nvdotprod = dot_product;
  ops->nvmaxnorm = max_norm;
  ops->nvwrmsnormmask = wrms_norm_mask;
  ops->nvwrmsnorm = wrms_norm;
  ops->nvmin = minimum;
  ops->nvwl2norm = weighted_l2_norm;
  ops->nvl1norm = l1_norm;
  ops->nvcompare = compare;
  ops->nvinvtest = inverse_test;
  ops->nvdotprodlocal = dot_product;
  ops->nvmaxnormlocal = max_norm;
  ops->nvminlocal = minimum;
  ops->nvl1normlocal = l1_norm;
  ops->nvinvtestlocal = inverse_test;
  ops->nvwsqrsumlocal = weighted_square_sum;
  ops->nvwsqrsummasklocal = weighted_square_sum_mask;
}

}  // namespace flexref::reference::sundials
