/// Tests of reference/serial_vector_ops: every replaced operation gives SUNDIALS' own serial
/// result bit for bit (the library's N_V*_Serial called directly on the same inputs), for every
/// case of the linear sum and the scale and every aliasing of their operands; and an integrator's
/// clones carry the replaced table.
#include "reference/serial_vector_ops.hpp"

#include <nvector/nvector_serial.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace flexref::reference::sundials {
namespace {

struct VectorOpsContext {
  VectorOpsContext() { SUNContext_Create(nullptr, &context); }
  ~VectorOpsContext() { SUNContext_Free(&context); }
  SUNContext context = nullptr;
};

constexpr sunindextype kLength = 37;  // odd: a vectorized loop's remainder is exercised too

/// A serial vector of generic values (random magnitudes over decades and signs, so that
/// c (x + y) and c x + c y, or a x + y fused and unfused, round differently somewhere).
N_Vector generic_vector(SUNContext context, unsigned seed) {
  N_Vector v = N_VNew_Serial(kLength, context);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-6, 6);
  for (sunindextype i = 0; i < kLength; ++i) {
    NV_Ith_S(v, i) = std::ldexp(mantissa(random), exponent(random));
  }
  return v;
}

bool same_bits(N_Vector a, N_Vector b) {
  return std::memcmp(NV_DATA_S(a), NV_DATA_S(b), sizeof(double) * kLength) == 0;
}
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

/// Operands x, y, z for one aliasing: 0 distinct, 1 z = x, 2 z = y, 3 x = y, 4 x = y = z.
struct Operands {
  N_Vector x, y, z;
};

/// Runs op on a fresh copy of the operands with SUNDIALS' table and with the compiled one, and
/// compares z (and x, y, which an in-place case may write).
template <typename Op>
void check_same(SUNContext context, int aliasing, Op&& op) {
  N_Vector own[3], compiled[3];
  for (int k = 0; k < 3; ++k) {
    own[k] = generic_vector(context, 11u + static_cast<unsigned>(k));
    compiled[k] = N_VClone(own[k]);
    N_VScale_Serial(1.0, own[k], compiled[k]);
  }
  use_compiled_serial_ops(compiled[0]);
  use_compiled_serial_ops(compiled[1]);
  use_compiled_serial_ops(compiled[2]);
  const auto pick = [aliasing](N_Vector* v) {
    Operands o{v[0], v[1], v[2]};
    if (aliasing == 1) o.z = o.x;
    if (aliasing == 2) o.z = o.y;
    if (aliasing == 3) o.y = o.x;
    if (aliasing == 4) o.y = o.z = o.x;
    return o;
  };
  op(pick(own), pick(compiled));
  for (int k = 0; k < 3; ++k) {
    CHECK(same_bits(own[k], compiled[k]));
    N_VDestroy(own[k]);
    N_VDestroy(compiled[k]);
  }
}

TEST_CASE("the compiled linear sum is SUNDIALS' bit for bit in every case and aliasing",
          "[reference][vector]") {
  VectorOpsContext s;
  // SUNDIALS' cases: 1 and −1 on either side, a = b, a = −b, 0, and generic pairs.
  const std::vector<double> coefficients{1.0, -1.0, 0.0, 0.3, -0.3, 2.5, 1.0 / 3.0};
  for (const double a : coefficients) {
    for (const double b : coefficients) {
      for (int aliasing = 0; aliasing < 5; ++aliasing) {
        CAPTURE(a, b, aliasing);
        check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
          N_VLinearSum_Serial(a, own.x, b, own.y, own.z);
          N_VLinearSum(a, compiled.x, b, compiled.y, compiled.z);
        });
      }
    }
  }
}

TEST_CASE("the compiled element-wise operations are SUNDIALS' bit for bit", "[reference][vector]") {
  VectorOpsContext s;
  for (int aliasing : {0, 1}) {
    CAPTURE(aliasing);
    for (const double c : {1.0, -1.0, 0.7, 0.0}) {
      CAPTURE(c);
      check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
        N_VScale_Serial(c, own.x, own.z);
        N_VScale(c, compiled.x, compiled.z);
      });
      check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
        N_VConst_Serial(c, own.z);
        N_VConst(c, compiled.z);
      });
      check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
        N_VAddConst_Serial(own.x, c, own.z);
        N_VAddConst(compiled.x, c, compiled.z);
      });
      check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
        N_VCompare_Serial(std::fabs(c) * 1e-2, own.x, own.z);
        N_VCompare(std::fabs(c) * 1e-2, compiled.x, compiled.z);
      });
    }
    check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
      N_VProd_Serial(own.x, own.y, own.z);
      N_VProd(compiled.x, compiled.y, compiled.z);
    });
    check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
      N_VDiv_Serial(own.x, own.y, own.z);
      N_VDiv(compiled.x, compiled.y, compiled.z);
    });
    check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
      N_VAbs_Serial(own.x, own.z);
      N_VAbs(compiled.x, compiled.z);
    });
    check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
      N_VInv_Serial(own.x, own.z);
      N_VInv(compiled.x, compiled.z);
    });
    // A zero entry: the test's false, z left there as it was.
    check_same(s.context, aliasing, [&](Operands own, Operands compiled) {
      NV_Ith_S(own.x, 5) = 0.0;
      NV_Ith_S(compiled.x, 5) = 0.0;
      CHECK(N_VInvTest_Serial(own.x, own.z) == N_VInvTest(compiled.x, compiled.z));
    });
  }
}

TEST_CASE("the compiled reductions are SUNDIALS' bit for bit", "[reference][vector]") {
  VectorOpsContext s;
  check_same(s.context, 0, [&](Operands own, Operands compiled) {
    // An id with differential (1) and algebraic (0) entries, as IDA's.
    for (sunindextype i = 0; i < kLength; ++i) {
      NV_Ith_S(own.z, i) = NV_Ith_S(compiled.z, i) = i % 3 == 0 ? 0.0 : 1.0;
    }
    CHECK(same_bits(N_VDotProd_Serial(own.x, own.y), N_VDotProd(compiled.x, compiled.y)));
    CHECK(same_bits(N_VMaxNorm_Serial(own.x), N_VMaxNorm(compiled.x)));
    CHECK(same_bits(N_VWrmsNorm_Serial(own.x, own.y), N_VWrmsNorm(compiled.x, compiled.y)));
    CHECK(same_bits(N_VWrmsNormMask_Serial(own.x, own.y, own.z),
                    N_VWrmsNormMask(compiled.x, compiled.y, compiled.z)));
    CHECK(same_bits(N_VWSqrSumLocal_Serial(own.x, own.y), N_VWSqrSumLocal(compiled.x, compiled.y)));
    CHECK(same_bits(N_VWSqrSumMaskLocal_Serial(own.x, own.y, own.z),
                    N_VWSqrSumMaskLocal(compiled.x, compiled.y, compiled.z)));
    CHECK(same_bits(N_VMin_Serial(own.x), N_VMin(compiled.x)));
    CHECK(same_bits(N_VMin_Serial(own.x), N_VMinLocal(compiled.x)));
    CHECK(same_bits(N_VWL2Norm_Serial(own.x, own.y), N_VWL2Norm(compiled.x, compiled.y)));
    CHECK(same_bits(N_VL1Norm_Serial(own.x), N_VL1Norm(compiled.x)));
    CHECK(same_bits(N_VL1Norm_Serial(own.x), N_VL1NormLocal(compiled.x)));
    CHECK(same_bits(N_VDotProd_Serial(own.x, own.y), N_VDotProdLocal(compiled.x, compiled.y)));
    CHECK(same_bits(N_VMaxNorm_Serial(own.x), N_VMaxNormLocal(compiled.x)));
    // A NaN entry is passed over by the max norm's comparison and spreads through the sums.
    NV_Ith_S(own.x, 3) = NV_Ith_S(compiled.x, 3) = std::numeric_limits<double>::quiet_NaN();
    CHECK(same_bits(N_VMaxNorm_Serial(own.x), N_VMaxNorm(compiled.x)));
    CHECK(std::isnan(N_VWrmsNorm(compiled.x, compiled.y)));
  });
}

TEST_CASE("clones carry the compiled operations; other vectors are refused",
          "[reference][vector]") {
  VectorOpsContext s;
  N_Vector v = N_VNew_Serial(kLength, s.context);
  use_compiled_serial_ops(v);
  N_Vector clone = N_VClone(v);
  CHECK(clone->ops->nvlinearsum == v->ops->nvlinearsum);
  CHECK(clone->ops->nvwsqrsummasklocal == v->ops->nvwsqrsummasklocal);
  CHECK(v->ops->nvlinearsum != N_VLinearSum_Serial);
  // The fused operations stay SUNDIALS' choice (disabled): its fallbacks call the ones above.
  CHECK(clone->ops->nvlinearcombination == nullptr);
  N_VDestroy(clone);
  N_VDestroy(v);
  CHECK_THROWS_AS(use_compiled_serial_ops(nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace flexref::reference::sundials
