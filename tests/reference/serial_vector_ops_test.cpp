/// Tests of the compiled serial vector operations (reference/serial_vector_ops.hpp): every
/// operation, and every special case of N_VLinearSum and N_VScale with every aliasing of its
/// output, gives SUNDIALS' own N_V*_Serial result bit for bit (so a change of the rounding — a
/// (x + y) written a x + a y, a sum in another order — or of a sign fails); the integrators'
/// vectors (sundials::make_vector) and their clones carry them.
#include "reference/serial_vector_ops.hpp"

#include <nvector/nvector_serial.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "reference/sundials_handle.hpp"

namespace flexref::reference {
namespace {

namespace sun = sundials;

/// 1 000 components: the reductions' sums over them round differently in any other order.
constexpr int kLength = 1000;

/// Two vectors of one length: `lib` with SUNDIALS' operations, `ours` with the compiled ones.
struct OpsVectorPair {
  sun::Vector lib;
  sun::Vector ours;
};

/// Values over 12 decades with both signs and some exact zeros, ones and minus ones (the cases
/// N_VInvTest, N_VMinQuotient and N_VConstrMask treat apart).
std::vector<double> ops_sample_values(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-6, 6);
  std::uniform_int_distribution<int> special(0, 19);
  std::vector<double> v(kLength);
  for (double& x : v) {
    const int s = special(rng);
    x = s == 0 ? 0.0 : s == 1 ? 1.0 : s == 2 ? -1.0 : mantissa(rng) * std::pow(10.0, exponent(rng));
  }
  return v;
}

OpsVectorPair make_vector_pair(SUNContext context, const std::vector<double>& values) {
  OpsVectorPair p{sun::Vector(N_VNew_Serial(kLength, context)), sun::make_vector(kLength, context)};
  std::copy(values.begin(), values.end(), N_VGetArrayPointer(p.lib.get()));
  std::copy(values.begin(), values.end(), N_VGetArrayPointer(p.ours.get()));
  return p;
}

/// The two vectors' components are the same doubles (bit for bit, so −0 ≠ +0 and NaNs compare).
bool ops_identical(const OpsVectorPair& p) {
  return std::memcmp(N_VGetArrayPointer(p.lib.get()), N_VGetArrayPointer(p.ours.get()),
                     sizeof(double) * kLength) == 0;
}

bool ops_identical(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

/// Three vectors x, y, z of each kind with fresh values.
struct OpsTriple {
  OpsVectorPair x, y, z;
};

OpsTriple make_ops_triple(SUNContext context, unsigned seed) {
  return {make_vector_pair(context, ops_sample_values(seed)),
          make_vector_pair(context, ops_sample_values(seed + 1)),
          make_vector_pair(context, ops_sample_values(seed + 2))};
}

TEST_CASE("the compiled serial vector operations are SUNDIALS' bit for bit",
          "[serial_vector_ops]") {
  const sun::Context context = sun::make_context();
  REQUIRE_FALSE(sun::has_compiled_serial_ops(
      make_vector_pair(context.get(), ops_sample_values(1)).lib.get()));

  SECTION("N_VLinearSum: every special case, every aliasing of z") {
    // 1 and −1 in every combination select the library's special cases (axpy in place, sum,
    // difference, a x ± y), equal and opposite coefficients its scaled sum and difference.
    const std::vector<double> coefficients{1.0, -1.0, 0.0, 0.3, -0.3, 2.5, -7.0 / 3.0};
    for (double a : coefficients) {
      for (double b : coefficients) {
        for (int alias = 0; alias < 3; ++alias) {  // z separate, z = x, z = y
          CAPTURE(a, b, alias);
          OpsTriple t = make_ops_triple(context.get(), 10);
          const OpsVectorPair& z = alias == 0 ? t.z : alias == 1 ? t.x : t.y;
          N_VLinearSum_Serial(a, t.x.lib.get(), b, t.y.lib.get(), z.lib.get());
          N_VLinearSum(a, t.x.ours.get(), b, t.y.ours.get(), z.ours.get());
          CHECK(ops_identical(t.x));
          CHECK(ops_identical(t.y));
          CHECK(ops_identical(t.z));
        }
      }
    }
  }

  SECTION("N_VScale in place and out of place, c = ±1 and others") {
    for (double c : {1.0, -1.0, 0.0, 0.3, -7.0 / 3.0}) {
      for (bool in_place : {false, true}) {
        CAPTURE(c, in_place);
        OpsTriple t = make_ops_triple(context.get(), 20);
        N_VScale_Serial(c, t.x.lib.get(), in_place ? t.x.lib.get() : t.z.lib.get());
        N_VScale(c, t.x.ours.get(), in_place ? t.x.ours.get() : t.z.ours.get());
        CHECK(ops_identical(t.x));
        CHECK(ops_identical(t.z));
      }
    }
  }

  SECTION("the element-wise operations") {
    OpsTriple t = make_ops_triple(context.get(), 30);
    N_VConst_Serial(-0.7, t.z.lib.get());
    N_VConst(-0.7, t.z.ours.get());
    CHECK(ops_identical(t.z));
    N_VProd_Serial(t.x.lib.get(), t.y.lib.get(), t.z.lib.get());
    N_VProd(t.x.ours.get(), t.y.ours.get(), t.z.ours.get());
    CHECK(ops_identical(t.z));
    N_VDiv_Serial(t.x.lib.get(), t.y.lib.get(), t.z.lib.get());  // x/0 = ±inf, 0/0 = NaN
    N_VDiv(t.x.ours.get(), t.y.ours.get(), t.z.ours.get());
    CHECK(ops_identical(t.z));
    N_VAbs_Serial(t.x.lib.get(), t.z.lib.get());
    N_VAbs(t.x.ours.get(), t.z.ours.get());
    CHECK(ops_identical(t.z));
    N_VInv_Serial(t.y.lib.get(), t.z.lib.get());
    N_VInv(t.y.ours.get(), t.z.ours.get());
    CHECK(ops_identical(t.z));
    N_VAddConst_Serial(t.x.lib.get(), 0.3, t.z.lib.get());
    N_VAddConst(t.x.ours.get(), 0.3, t.z.ours.get());
    CHECK(ops_identical(t.z));
    N_VCompare_Serial(0.01, t.x.lib.get(), t.z.lib.get());
    N_VCompare(0.01, t.x.ours.get(), t.z.ours.get());
    CHECK(ops_identical(t.z));
    // x has zeros: InvTest reports them and leaves those z_i alone.
    CHECK(N_VInvTest_Serial(t.x.lib.get(), t.z.lib.get()) ==
          N_VInvTest(t.x.ours.get(), t.z.ours.get()));
    CHECK(ops_identical(t.z));
    N_VAbs_Serial(t.y.lib.get(), t.y.lib.get());
    N_VAbs(t.y.ours.get(), t.y.ours.get());
    CHECK(N_VInvTest_Serial(t.y.lib.get(), t.z.lib.get()) ==
          N_VInvTest(t.y.ours.get(), t.z.ours.get()));
    CHECK(ops_identical(t.z));
  }

  SECTION("the constraint mask: codes 0, ±1, ±2 against signs and zeros") {
    OpsTriple t = make_ops_triple(context.get(), 40);
    const double codes[] = {0.0, 1.0, -1.0, 2.0, -2.0};
    for (int i = 0; i < kLength; ++i) {
      N_VGetArrayPointer(t.y.lib.get())[i] = codes[i % 5];
      N_VGetArrayPointer(t.y.ours.get())[i] = codes[i % 5];
    }
    const sunbooleantype lib = N_VConstrMask_Serial(t.y.lib.get(), t.x.lib.get(), t.z.lib.get());
    CHECK(lib == SUNFALSE);  // random signs violate some constraint
    CHECK(N_VConstrMask(t.y.ours.get(), t.x.ours.get(), t.z.ours.get()) == lib);
    CHECK(ops_identical(t.z));
    N_VAbs_Serial(t.x.lib.get(), t.x.lib.get());
    N_VAbs(t.x.ours.get(), t.x.ours.get());
    N_VAddConst_Serial(t.x.lib.get(), 1.0, t.x.lib.get());
    N_VAddConst(t.x.ours.get(), 1.0, t.x.ours.get());
    N_VAbs_Serial(t.y.lib.get(), t.y.lib.get());
    N_VAbs(t.y.ours.get(), t.y.ours.get());
    CHECK(N_VConstrMask_Serial(t.y.lib.get(), t.x.lib.get(), t.z.lib.get()) == SUNTRUE);
    CHECK(N_VConstrMask(t.y.ours.get(), t.x.ours.get(), t.z.ours.get()) == SUNTRUE);
    CHECK(ops_identical(t.z));
  }

  SECTION("the reductions, summed in the library's order") {
    OpsTriple t = make_ops_triple(context.get(), 50);
    N_Vector xl = t.x.lib.get(), yl = t.y.lib.get(), zl = t.z.lib.get();
    N_Vector xo = t.x.ours.get(), yo = t.y.ours.get(), zo = t.z.ours.get();
    CHECK(ops_identical(N_VDotProd_Serial(xl, yl), N_VDotProd(xo, yo)));
    CHECK(ops_identical(N_VMaxNorm_Serial(xl), N_VMaxNorm(xo)));
    CHECK(ops_identical(N_VWrmsNorm_Serial(xl, yl), N_VWrmsNorm(xo, yo)));
    CHECK(ops_identical(N_VWrmsNormMask_Serial(xl, yl, zl), N_VWrmsNormMask(xo, yo, zo)));
    CHECK(ops_identical(N_VMin_Serial(xl), N_VMin(xo)));
    CHECK(ops_identical(N_VWL2Norm_Serial(xl, yl), N_VWL2Norm(xo, yo)));
    CHECK(ops_identical(N_VL1Norm_Serial(xl), N_VL1Norm(xo)));
    CHECK(ops_identical(N_VMinQuotient_Serial(xl, yl), N_VMinQuotient(xo, yo)));
    CHECK(ops_identical(N_VWSqrSumLocal_Serial(xl, yl), N_VWSqrSumLocal(xo, yo)));
    CHECK(ops_identical(N_VWSqrSumMaskLocal_Serial(xl, yl, zl), N_VWSqrSumMaskLocal(xo, yo, zo)));
    CHECK(ops_identical(N_VDotProd_Serial(xl, yl), N_VDotProdLocal(xo, yo)));
    CHECK(ops_identical(N_VMaxNorm_Serial(xl), N_VMaxNormLocal(xo)));
    CHECK(ops_identical(N_VMin_Serial(xl), N_VMinLocal(xo)));
    CHECK(ops_identical(N_VL1Norm_Serial(xl), N_VL1NormLocal(xo)));
    CHECK(ops_identical(N_VMinQuotient_Serial(xl, yl), N_VMinQuotientLocal(xo, yo)));
    // Every denominator zero: the library's BIG_REAL.
    N_VConst_Serial(0.0, yl);
    N_VConst(0.0, yo);
    CHECK(ops_identical(N_VMinQuotient_Serial(xl, yl), N_VMinQuotient(xo, yo)));
  }

  SECTION("the integrators' vectors and their clones carry the compiled operations") {
    const sun::Vector v = sun::make_vector(7, context.get());
    CHECK(sun::has_compiled_serial_ops(v.get()));
    const sun::Vector clone(N_VClone(v.get()));
    CHECK(sun::has_compiled_serial_ops(clone.get()));
    CHECK(N_VGetVectorID(clone.get()) == SUNDIALS_NVEC_SERIAL);
    CHECK(N_VGetLength(clone.get()) == 7);
  }
}

}  // namespace
}  // namespace flexref::reference
