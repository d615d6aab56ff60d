// Reads typed values from a fuzzer's bytes; past the end every read returns zeros, so any
// input decodes to something (libFuzzer then learns which bytes matter).
#pragma once

#include <REngineMath/RMath.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace REngine::fuzz {

class FuzzInput {
 public:
  FuzzInput(const std::uint8_t* data, std::size_t size) : m_data(data), m_size(size) {}

  std::uint8_t Byte() { return m_pos < m_size ? m_data[m_pos++] : 0; }
  // Any bit pattern: NaN, infinities, subnormals, 1e300 included.
  double RawDouble() {
    std::uint64_t bits = 0;
    for (int i = 0; i < 8; ++i) bits |= std::uint64_t(Byte()) << (8 * i);
    double x;
    std::memcpy(&x, &bits, sizeof x);
    return x;
  }
  // A finite number in [lo, hi] from two bytes.
  double Range(double lo, double hi) {
    const unsigned v = Byte() | (unsigned(Byte()) << 8);
    return lo + (hi - lo) * (v / 65535.0);
  }
  // 10^Range(lo, hi): sizes and ratios spread over decades.
  double Decades(double lo, double hi) { return std::pow(10.0, Range(lo, hi)); }
  // (Reads are sequenced one per statement: the order in which a function's arguments are
  // evaluated differs between compilers, and an input must mean the same to all of them.)
  RVec3 Vec(double lo, double hi) {
    const double x = Range(lo, hi), y = Range(lo, hi), z = Range(lo, hi);
    return RVec3(x, y, z);
  }
  RVec3 RawVec() {
    const double x = RawDouble(), y = RawDouble(), z = RawDouble();
    return RVec3(x, y, z);
  }
  RQuat RawQuat() {  // (w, x, y, z), as read
    const double w = RawDouble(), x = RawDouble(), y = RawDouble(), z = RawDouble();
    return RQuat(w, x, y, z);
  }
  RQuat Rotation() {
    const double w = Range(-1, 1), x = Range(-1, 1), y = Range(-1, 1), z = Range(-1, 1);
    const RQuat q(w, x, y, z);
    return q.norm() > 1e-3 ? q.normalized() : RQuat::Identity();
  }
  bool Empty() const { return m_pos >= m_size; }

 private:
  const std::uint8_t* m_data;
  std::size_t m_size;
  std::size_t m_pos = 0;
};

// Stops the fuzzer with a message when an invariant fails (libFuzzer keeps the input).
#define RENGINE_FUZZ_CHECK(cond, ...)                                        \
  do {                                                                        \
    if (!(cond)) {                                                            \
      std::fprintf(stderr, "check failed: %s: ", #cond);                      \
      std::fprintf(stderr, __VA_ARGS__);                                      \
      std::fprintf(stderr, "\n");                                             \
      std::abort();                                                           \
    }                                                                         \
  } while (0)

}  // namespace REngine::fuzz
