#include "reference/serial_vector_ops.hpp"

#include <nvector/nvector_serial.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace flexref::reference::sundials {
namespace {

// Each function below is its namesake of SUNDIALS 6.4.1's nvector_serial.c (see the header);
// the comments give the formula, the library's name of the special case where it has one.

sunindextype length_of(N_Vector v) { return NV_LENGTH_S(v); }
double* values_of(N_Vector v) { return NV_DATA_S(v); }

/// y ← a x + y (Vaxpy_Serial), with its cases a = 1 and a = −1.
void axpy(double a, N_Vector x, N_Vector y) {
  const sunindextype n = length_of(x);
  const double* xd = values_of(x);
  double* yd = values_of(y);
  if (a == 1.0) {
    for (sunindextype i = 0; i < n; ++i) yd[i] += xd[i];
    return;
  }
  if (a == -1.0) {
    for (sunindextype i = 0; i < n; ++i) yd[i] -= xd[i];
    return;
  }
  for (sunindextype i = 0; i < n; ++i) yd[i] += a * xd[i];
}

/// z ← f(x_i, y_i) element by element (x, y, z may alias: each element is read before written).
template <class F>
void binary(N_Vector x, N_Vector y, N_Vector z, F f) {
  const sunindextype n = length_of(x);
  const double* xd = values_of(x);
  const double* yd = values_of(y);
  double* zd = values_of(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = f(xd[i], yd[i]);
}

template <class F>
void unary(N_Vector x, N_Vector z, F f) {
  const sunindextype n = length_of(x);
  const double* xd = values_of(x);
  double* zd = values_of(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = f(xd[i]);
}

/// z ← a x + b y (N_VLinearSum_Serial), its special cases in the library's order.
void linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  if (b == 1.0 && z == y) return axpy(a, x, y);
  if (a == 1.0 && z == x) return axpy(b, y, x);
  if (a == 1.0 && b == 1.0) return binary(x, y, z, [](double p, double q) { return p + q; });
  // VDiff: x − y for (1, −1), y − x for (−1, 1).
  if (a == 1.0 && b == -1.0) return binary(x, y, z, [](double p, double q) { return p - q; });
  if (a == -1.0 && b == 1.0) return binary(y, x, z, [](double p, double q) { return p - q; });
  // VLin1: c v1 + v2 with (c, v1, v2) = (b, y, x) if a = 1, else (a, x, y) (b = 1).
  if (a == 1.0) return binary(y, x, z, [b](double p, double q) { return (b * p) + q; });
  if (b == 1.0) return binary(x, y, z, [a](double p, double q) { return (a * p) + q; });
  // VLin2: c v1 − v2 with (c, v1, v2) = (b, y, x) if a = −1, else (a, x, y) (b = −1).
  if (a == -1.0) return binary(y, x, z, [b](double p, double q) { return (b * p) - q; });
  if (b == -1.0) return binary(x, y, z, [a](double p, double q) { return (a * p) - q; });
  // VScaleSum and VScaleDiff: a (x + y), a (x − y).
  if (a == b) return binary(x, y, z, [a](double p, double q) { return a * (p + q); });
  if (a == -b) return binary(x, y, z, [a](double p, double q) { return a * (p - q); });
  binary(x, y, z, [a, b](double p, double q) { return (a * p) + (b * q); });
}

void constant(double c, N_Vector z) { std::fill(values_of(z), values_of(z) + length_of(z), c); }

void product(N_Vector x, N_Vector y, N_Vector z) {
  binary(x, y, z, [](double p, double q) { return p * q; });
}

void quotient(N_Vector x, N_Vector y, N_Vector z) {
  binary(x, y, z, [](double p, double q) { return p / q; });
}

/// z ← c x (N_VScale_Serial): in place (VScaleBy), a copy for c = 1, a negation for c = −1.
void scale(double c, N_Vector x, N_Vector z) {
  if (z == x) {
    double* xd = values_of(x);
    for (sunindextype i = 0; i < length_of(x); ++i) xd[i] *= c;
    return;
  }
  if (c == 1.0) return unary(x, z, [](double p) { return p; });
  if (c == -1.0) return unary(x, z, [](double p) { return -p; });
  unary(x, z, [c](double p) { return c * p; });
}

void absolute(N_Vector x, N_Vector z) {
  unary(x, z, [](double p) { return std::abs(p); });
}

void inverse(N_Vector x, N_Vector z) {
  unary(x, z, [](double p) { return 1.0 / p; });
}

void add_constant(N_Vector x, double b, N_Vector z) {
  unary(x, z, [b](double p) { return p + b; });
}

/// Σ x_i y_i in index order.
double dot(N_Vector x, N_Vector y) {
  const double* xd = values_of(x);
  const double* yd = values_of(y);
  double sum = 0.0;
  for (sunindextype i = 0; i < length_of(x); ++i) sum += xd[i] * yd[i];
  return sum;
}

double max_norm(N_Vector x) {
  const double* xd = values_of(x);
  double max = 0.0;
  for (sunindextype i = 0; i < length_of(x); ++i) {
    if (std::abs(xd[i]) > max) max = std::abs(xd[i]);
  }
  return max;
}

/// Σ (x_i w_i)² in index order (N_VWSqrSumLocal_Serial).
double weighted_square_sum(N_Vector x, N_Vector w) {
  const double* xd = values_of(x);
  const double* wd = values_of(w);
  double sum = 0.0;
  for (sunindextype i = 0; i < length_of(x); ++i) {
    const double product = xd[i] * wd[i];
    sum += product * product;
  }
  return sum;
}

/// Σ over id_i > 0 of (x_i w_i)² in index order (N_VWSqrSumMaskLocal_Serial).
double weighted_square_sum_mask(N_Vector x, N_Vector w, N_Vector id) {
  const double* xd = values_of(x);
  const double* wd = values_of(w);
  const double* idd = values_of(id);
  double sum = 0.0;
  for (sunindextype i = 0; i < length_of(x); ++i) {
    if (idd[i] > 0.0) {
      const double product = xd[i] * wd[i];
      sum += product * product;
    }
  }
  return sum;
}

double wrms_norm(N_Vector x, N_Vector w) {
  return std::sqrt(weighted_square_sum(x, w) / static_cast<double>(length_of(x)));
}

double wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  return std::sqrt(weighted_square_sum_mask(x, w, id) / static_cast<double>(length_of(x)));
}

/// min x_i; reads x_0 whatever the length, as the library does.
double minimum(N_Vector x) {
  const double* xd = values_of(x);
  double min = xd[0];
  for (sunindextype i = 1; i < length_of(x); ++i) {
    if (xd[i] < min) min = xd[i];
  }
  return min;
}

double weighted_l2_norm(N_Vector x, N_Vector w) { return std::sqrt(weighted_square_sum(x, w)); }

double l1_norm(N_Vector x) {
  const double* xd = values_of(x);
  double sum = 0.0;
  for (sunindextype i = 0; i < length_of(x); ++i) sum += std::abs(xd[i]);
  return sum;
}

/// z_i ← 1 if |x_i| ≥ c, else 0.
void compare(double c, N_Vector x, N_Vector z) {
  unary(x, z, [c](double p) { return std::abs(p) >= c ? 1.0 : 0.0; });
}

/// z_i ← 1/x_i where x_i ≠ 0 (z_i left alone elsewhere); false if some x_i = 0.
sunbooleantype inverse_test(N_Vector x, N_Vector z) {
  const double* xd = values_of(x);
  double* zd = values_of(z);
  sunbooleantype no_zero_found = SUNTRUE;
  for (sunindextype i = 0; i < length_of(x); ++i) {
    if (xd[i] == 0.0) {
      no_zero_found = SUNFALSE;
    } else {
      zd[i] = 1.0 / xd[i];
    }
  }
  return no_zero_found;
}

/// m_i ← 1 where x_i violates constraint c_i (|c_i| = 2: strict sign, 1: sign or zero).
sunbooleantype constraint_mask(N_Vector c, N_Vector x, N_Vector m) {
  const double* cd = values_of(c);
  const double* xd = values_of(x);
  double* md = values_of(m);
  bool violated = false;
  for (sunindextype i = 0; i < length_of(x); ++i) {
    md[i] = 0.0;
    if (cd[i] == 0.0) continue;
    if ((std::abs(cd[i]) > 1.5 && xd[i] * cd[i] <= 0.0) ||
        (std::abs(cd[i]) > 0.5 && xd[i] * cd[i] < 0.0)) {
      md[i] = 1.0;
      violated = true;
    }
  }
  return violated ? SUNFALSE : SUNTRUE;
}

/// min over d_i ≠ 0 of n_i / d_i; BIG_REAL if every d_i = 0.
double min_quotient(N_Vector num, N_Vector denom) {
  const double* nd = values_of(num);
  const double* dd = values_of(denom);
  bool first = true;
  double min = BIG_REAL;
  for (sunindextype i = 0; i < length_of(num); ++i) {
    if (dd[i] == 0.0) continue;
    if (!first) {
      min = std::min(min, nd[i] / dd[i]);
    } else {
      min = nd[i] / dd[i];
      first = false;
    }
  }
  return min;
}

}  // namespace

void use_compiled_serial_ops(N_Vector v) {
  if (v == nullptr || N_VGetVectorID(v) != SUNDIALS_NVEC_SERIAL) {
    throw std::invalid_argument("use_compiled_serial_ops: not a serial N_Vector");
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
  ops->nvdotprod = dot;
  ops->nvmaxnorm = max_norm;
  ops->nvwrmsnormmask = wrms_norm_mask;
  ops->nvwrmsnorm = wrms_norm;
  ops->nvmin = minimum;
  ops->nvwl2norm = weighted_l2_norm;
  ops->nvl1norm = l1_norm;
  ops->nvcompare = compare;
  ops->nvinvtest = inverse_test;
  ops->nvconstrmask = constraint_mask;
  ops->nvminquotient = min_quotient;
  ops->nvdotprodlocal = dot;
  ops->nvmaxnormlocal = max_norm;
  ops->nvminlocal = minimum;
  ops->nvl1normlocal = l1_norm;
  ops->nvinvtestlocal = inverse_test;
  ops->nvconstrmasklocal = constraint_mask;
  ops->nvminquotientlocal = min_quotient;
  ops->nvwsqrsumlocal = weighted_square_sum;
  ops->nvwsqrsummasklocal = weighted_square_sum_mask;
}

bool has_compiled_serial_ops(N_Vector v) {
  return v != nullptr && v->ops != nullptr && v->ops->nvlinearsum == linear_sum &&
         v->ops->nvwrmsnorm == wrms_norm && v->ops->nvwsqrsumlocal == weighted_square_sum;
}

}  // namespace flexref::reference::sundials
