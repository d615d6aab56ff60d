// The layout check between the REngine library and the code that includes its headers.
//
// A game and the library must agree on the size and alignment of every public struct they
// pass to each other. Eigen's fixed-size vectorisable types (RQuat, RVec4) take the
// alignment of the widest SIMD the compiler targets: 16 bytes for baseline x86-64, 32 with
// -mavx or -mavx2, 64 with -mavx512f. REngine::Math therefore carries
// EIGEN_MAX_STATIC_ALIGN_BYTES=16 as a public compile definition, so every target that links
// REngine through CMake sees the library's layouts whatever its SIMD flags. A game built
// another way (its own flags, no CMake target) could still disagree, and would then read
// fields at the wrong offsets: each public header checks its types' layouts against the
// library's once per translation unit, at static initialisation, and a mismatch stops the
// program before main with a message that names the type (as Jolt's VerifyJoltVersionID
// does at start-up).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <iterator>

namespace REngine {

// One public type as a translation unit compiled it: its name, size and alignment, bytes.
struct RAbiLayout {
  const char* type;
  std::size_t size;
  std::size_t align;
};

// Compares `count` layouts, as the calling translation unit sees them, with the library's
// own. When any differs (or names a type the library does not know), prints each difference
// and the likely cause to standard error and aborts. Returns true otherwise.
bool RVerifyAbi(const RAbiLayout* layouts, std::size_t count) noexcept;

}  // namespace REngine

#define RENGINE_ABI_LAYOUT(T) ::REngine::RAbiLayout{#T, sizeof(::REngine::T), alignof(::REngine::T)},
// The alignment Eigen gives its vectorisable types here, checked with every header's types.
#define RENGINE_ABI_EIGEN_LAYOUT \
  ::REngine::RAbiLayout{"EIGEN_MAX_STATIC_ALIGN_BYTES", EIGEN_MAX_STATIC_ALIGN_BYTES, 0},

// Checks the layouts of the types a header lists (TYPES(X) applies X to each) once per
// translation unit that includes it, before main. The library's own table (RAbi.cpp) is made
// from the same lists. NAME must be unique among the headers (it names the unit's flag).
#define RENGINE_ABI_CHECK(NAME, TYPES)                                      \
  namespace REngine::abi_check {                                            \
  [[maybe_unused]] static const bool NAME = [] {                            \
    static const ::REngine::RAbiLayout kLayouts[] = {                       \
        RENGINE_ABI_EIGEN_LAYOUT TYPES(RENGINE_ABI_LAYOUT)};                \
    return ::REngine::RVerifyAbi(kLayouts, std::size(kLayouts));            \
  }();                                                                      \
  }
