#pragma once
/// \file serial_vector_ops.hpp
/// SUNDIALS' serial N_Vector operations compiled with flexref's own optimisation flags, put in
/// place of the library's (docs/performance.md, "Andrews' squeezer": the vector operations of
/// Debian 12's SUNDIALS 6.4.1).
///
/// Why. Debian 12's libsundials (6.4.1+dfsg1-3) is compiled without optimisation: every loop of
/// nvector_serial.c keeps its index and its sum on the stack (objdump of N_VLinearSum_Serial and
/// N_VWSqrSumLocal_Serial in libsundials_cvode.so.6 and libsundials_ida.so.6). The integrators'
/// own vector arithmetic — CVODE's predictor (q(q+1)/2 N_VLinearSum per step), its error tests
/// and norms (N_VWrmsNorm), the fixed-point and Newton iterations — then cost as much as the
/// model's evaluations on a small mechanism.
///
/// What. Each operation is the one of SUNDIALS 6.4.1's src/nvector/serial/nvector_serial.c
/// (BSD-3-Clause, Lawrence Livermore National Security and Southern Methodist University), term
/// for term and case for case: N_VLinearSum's special cases (axpy in place, a = b = 1,
/// a = ±1 and b = ∓1, a = b, a = −b) round differently from the general a x + b y, and the
/// reductions (dot products, weighted sums of squares, the L1 norm) add in index order. flexref
/// compiles without -ffast-math, and this file with -ffp-contract=off whatever the target
/// (reference/CMakeLists.txt), so the results are the library's bit for bit (serial_vector_ops_test
/// compares every operation and case with SUNDIALS' own). The content (N_VectorContent_Serial) and
/// the constructors, clones and destructors stay SUNDIALS': a clone copies the operations table
/// (N_VCopyOps), so the integrators' internal vectors get them too. The fused and vector-array
/// operations stay unset (as in N_VNew_Serial): SUNDIALS' generic fallbacks then call the
/// operations here.
#include <sundials/sundials_nvector.h>

namespace flexref::reference::sundials {

/// Replaces the arithmetic operations of serial vector `v` (N_VNew_Serial, N_VMake_Serial or a
/// clone of one) with the compiled ones. Throws std::invalid_argument if `v` is not serial.
void use_compiled_serial_ops(N_Vector v);

/// True if `v` carries the compiled operations (a test of use_compiled_serial_ops and of the
/// clones the integrators make).
bool has_compiled_serial_ops(N_Vector v);

}  // namespace flexref::reference::sundials
