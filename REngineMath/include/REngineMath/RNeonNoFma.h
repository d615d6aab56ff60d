// Included ahead of every translation unit that uses the engine when clang compiles for
// 64-bit ARM (REngineMath/CMakeLists.txt, -include): Eigen's NEON packet math fuses a
// multiply and an add into one instruction (vfmaq) wherever __ARM_FEATURE_FMA is defined,
// which it always is on 64-bit ARM, whatever -ffp-contract says. A fused product rounds once
// where x86-64's SSE2 kernels round twice, and runs would differ by platform. gcc takes
// -U__ARM_FEATURE_FMA on its command line; clang's arm_neon.h declares its FMA intrinsics
// only while the macro is defined, and Eigen's matrix kernels call some of them whatever the
// macro says, so here arm_neon.h is read first, with the macro, and the macro is dropped
// before Eigen is: Eigen's packet math then multiplies, then adds.
#pragma once
#if defined(__aarch64__) && defined(__clang__)
#include <arm_neon.h>
#undef __ARM_FEATURE_FMA
#endif
