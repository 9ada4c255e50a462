#pragma once
/// \file serial_vector_ops.hpp
/// SUNDIALS' serial vector operations compiled with the project's optimization, installed into a
/// serial N_Vector's operation table (docs/decisions.md, "SUNDIALS' serial vector operations").
///
/// Debian 12's SUNDIALS 6.4.1 is built without optimization: its serial vector operations keep
/// every loop index and pointer on the stack (visible in their disassembly), and IDA's and
/// CVODE's per-step vector work (predictor, corrector updates, error norms) was a third of IDA's
/// profile on a 128-body chain. These are the same operations with the same arithmetic, element
/// by element and in the same order (the special cases of N_VLinearSum_Serial and N_VScale_Serial
/// included, since c (x + y) and a x + b y round differently), so an integration gives the same
/// bits: tests/reference/serial_vector_ops_test.cpp compares each with SUNDIALS' own on inputs
/// and aliasings of every case. The file is compiled with -ffp-contract=off (reference/
/// CMakeLists.txt): a fused multiply-add would round a x + y once instead of twice.
///
/// The operations replaced are those a step calls (the standard and local reduction operations);
/// fused and vector-array operations stay disabled as SUNDIALS leaves them, so its generic
/// fallbacks (N_VLinearCombination by N_VScale and N_VLinearSum) call these. Clones copy the
/// table (N_VCloneEmpty_Serial), so installing it into the vector an integrator is created from
/// reaches all of the integrator's own vectors.
#include <sundials/sundials_nvector.h>

namespace flexref::reference::sundials {

/// Replaces v's standard and local reduction operations by the compiled ones; v must be a serial
/// vector (N_VNew_Serial). Throws std::invalid_argument otherwise.
void use_compiled_serial_ops(N_Vector v);

}  // namespace flexref::reference::sundials
