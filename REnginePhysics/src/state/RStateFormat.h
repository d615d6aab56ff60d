// Private to REnginePhysics (and its tests): the byte format of a saved world state
// (RWorldState.h): the header's layout, the checksum, and the little-endian writer and the
// bounds-checked reader every record goes through.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RWorldState.h>

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace REngine::state {

// The header: magic (8 bytes), version (u32), reserved 0 (u32), payload length (u64),
// payload checksum (u64). The magic's first byte is not ASCII and it holds a newline, so a
// text file, or a state passed through a text-mode copy, is told apart at once (PNG's trick).
inline constexpr unsigned char kMagic[8] = {0x89, 'R', 'S', 'T', 'A', 'T', 'E', '\n'};
inline constexpr std::uint32_t kVersion = 3;  // 2: an RBodies' joints; 3: one-way bodies, characters
inline constexpr std::size_t kVersionAt = 8, kReservedAt = 12, kLengthAt = 16, kChecksumAt = 24;
inline constexpr std::size_t kHeaderBytes = 32;

inline std::uint64_t LoadU64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int k = 7; k >= 0; --k) v = (v << 8) | p[k];
  return v;
}
inline void StoreU64(std::uint8_t* p, std::uint64_t v) {
  for (int k = 0; k < 8; ++k) p[k] = static_cast<std::uint8_t>(v >> (8 * k));
}

// The payload's checksum: each little-endian 8-byte word (the tail zero-padded) scrambled by
// SplitMix64's finaliser and folded in with a multiply; the length last. Every bit of the
// payload reaches every bit of the sum, so a flipped bit or a cut changes it (2^-64 chance
// of missing); it is not a cryptographic hash.
inline std::uint64_t Mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
inline std::uint64_t Checksum(const std::uint8_t* data, std::size_t size) {
  std::uint64_t h = 0x6a09e667f3bcc909ULL;
  std::size_t k = 0;
  for (; k + 8 <= size; k += 8) h = (h ^ Mix(LoadU64(data + k))) * 0x9e3779b97f4a7c15ULL;
  if (k < size) {
    std::uint8_t tail[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    std::memcpy(tail, data + k, size - k);
    h = (h ^ Mix(LoadU64(tail))) * 0x9e3779b97f4a7c15ULL;
  }
  return Mix(h ^ size);
}

// Writes the header of `bytes` (whose payload follows it) for the payload as it stands.
inline void Seal(std::vector<std::uint8_t>& bytes) {
  std::uint8_t* p = bytes.data();
  std::memcpy(p, kMagic, sizeof kMagic);
  for (int k = 0; k < 4; ++k) p[kVersionAt + k] = static_cast<std::uint8_t>(kVersion >> (8 * k));
  for (int k = 0; k < 4; ++k) p[kReservedAt + k] = 0;
  const std::size_t length = bytes.size() - kHeaderBytes;
  StoreU64(p + kLengthAt, length);
  StoreU64(p + kChecksumAt, Checksum(p + kHeaderBytes, length));
}

// Appends values little-endian, doubles as their bits.
class RWriter {
 public:
  explicit RWriter(std::vector<std::uint8_t>& out) : m_out(out) {}
  void U8(std::uint8_t v) { m_out.push_back(v); }
  void Bool(bool v) { U8(v ? 1 : 0); }
  void U32(std::uint32_t v) {
    for (int k = 0; k < 4; ++k) m_out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  }
  void I32(std::int32_t v) { U32(static_cast<std::uint32_t>(v)); }
  void U64(std::uint64_t v) {
    for (int k = 0; k < 8; ++k) m_out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  }
  void F64(double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    U64(bits);
  }
  void Vec3(const RVec3& v) { F64(v.x()), F64(v.y()), F64(v.z()); }
  void Quat(const RQuat& q) { F64(q.w()), F64(q.x()), F64(q.y()), F64(q.z()); }
  template <int R, int C>
  void Matrix(const Eigen::Matrix<RScalar, R, C>& m) {  // column by column
    for (int c = 0; c < C; ++c) {
      for (int r = 0; r < R; ++r) F64(m(r, c));
    }
  }
  void String(const std::string& s) {
    U64(s.size());
    m_out.insert(m_out.end(), s.begin(), s.end());
  }

 private:
  std::vector<std::uint8_t>& m_out;
};

// Reads what RWriter wrote, never past the end: a value cut short throws RStateError naming
// it (the current record, set by the caller, and the field) and the byte where it stopped.
class RReader {
 public:
  RReader(const std::uint8_t* data, std::size_t size, std::size_t at) : m_data(data), m_size(size), m_at(at) {}

  // The record being read ("bodies[3]"), prefixed to the fields named in errors.
  void SetRecord(std::string record) { m_record = std::move(record); }
  std::string Where(const char* field) const {
    return m_record.empty() ? std::string(field) : m_record + "." + field;
  }
  [[noreturn]] void Fail(const char* field, const std::string& problem) const {
    throw RStateError(Where(field), problem);
  }
  [[noreturn]] void Fail(const std::string& field, const std::string& problem) const {
    Fail(field.c_str(), problem);
  }

  std::uint8_t U8(const char* field) { return *Take(field, 1); }
  bool Bool(const char* field) {
    const std::uint8_t v = U8(field);
    if (v > 1) Fail(field, "must be 0 or 1 (got " + std::to_string(v) + ")");
    return v == 1;
  }
  std::uint32_t U32(const char* field) {
    const std::uint8_t* p = Take(field, 4);
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
  }
  std::int32_t I32(const char* field) { return static_cast<std::int32_t>(U32(field)); }
  std::uint64_t U64(const char* field) { return LoadU64(Take(field, 8)); }
  double F64(const char* field) {
    const std::uint64_t bits = U64(field);
    double v = 0;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  // A double the engine never leaves non-finite (a pose, a velocity).
  double Finite(const char* field) {
    const double v = F64(field);
    if (!std::isfinite(v)) Fail(field, "must be finite (got " + Number(v) + ")");
    return v;
  }
  RVec3 Vec3(const char* field) {
    RVec3 v;
    v.x() = F64(field), v.y() = F64(field), v.z() = F64(field);
    return v;
  }
  RVec3 FiniteVec3(const char* field) {
    const RVec3 v = Vec3(field);
    if (!AllFinite(v)) Fail(field, "must be finite (got a NaN or an infinity)");
    return v;
  }
  RQuat Quat(const char* field) {
    const double w = F64(field), x = F64(field), y = F64(field), z = F64(field);
    return RQuat(w, x, y, z);
  }
  // The ranges a world's values stay in (RLimits.h): a state holds what the engine's doors
  // let in, and an edited one is refused by the field's name.
  double Within(const char* field, double limit) {
    const double v = F64(field);
    if (!(std::abs(v) <= limit)) Fail(field, "must be finite and within " + Number(limit) + " (got " + Number(v) + ")");
    return v;
  }
  RVec3 WithinVec3(const char* field, double limit) {
    const RVec3 v = Vec3(field);
    if (!(AllFinite(v) && v.cwiseAbs().maxCoeff() <= limit)) {
      Fail(field, "must be finite and within " + Number(limit) + " (got " + Text(v) + ")");
    }
    return v;
  }
  double NonNegative(const char* field) {
    const double v = F64(field);
    if (!(std::isfinite(v) && v >= 0)) Fail(field, "must be finite and >= 0 (got " + Number(v) + ")");
    return v;
  }
  // Unit length within 1e-6, as the engine keeps orientations and axes (normalised each step).
  RVec3 UnitVec3(const char* field) {
    const RVec3 v = Vec3(field);
    if (!(AllFinite(v) && std::abs(v.norm() - 1) <= 1e-6)) Fail(field, "must be a unit vector (got " + Text(v) + ")");
    return v;
  }
  RQuat UnitQuat(const char* field) {
    const RQuat q = Quat(field);
    if (!(AllFinite(q) && std::abs(q.norm() - 1) <= 1e-6)) {
      Fail(field, "must be a finite unit quaternion (got " + Text(RVec3(q.x(), q.y(), q.z())) + ", w " + Number(q.w()) + ")");
    }
    return q;
  }
  static std::string Number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
  }
  static std::string Text(const RVec3& v) { return "[" + Number(v.x()) + ", " + Number(v.y()) + ", " + Number(v.z()) + "]"; }
  template <int R, int C>
  Eigen::Matrix<RScalar, R, C> Matrix(const char* field) {
    Eigen::Matrix<RScalar, R, C> m;
    for (int c = 0; c < C; ++c) {
      for (int r = 0; r < R; ++r) m(r, c) = F64(field);
    }
    return m;
  }
  std::string String(const char* field) {
    const std::uint64_t n = U64(field);
    if (n > Left()) Cut(field, n);
    const char* p = reinterpret_cast<const char*>(m_data + m_at);
    m_at += static_cast<std::size_t>(n);
    return std::string(p, static_cast<std::size_t>(n));
  }
  // A count of records of at least `bytesEach` bytes each: one the rest of the state cannot
  // hold is refused before anything is allocated for it.
  std::size_t Count(const char* field, std::size_t bytesEach) {
    const std::uint64_t n = U64(field);
    if (n > Left() / bytesEach) {
      Fail(field, "says " + std::to_string(n) + " entries of at least " + std::to_string(bytesEach) +
                      " bytes, more than the " + std::to_string(Left()) + " bytes left");
    }
    return static_cast<std::size_t>(n);
  }

  std::size_t Offset() const { return m_at; }
  std::size_t Left() const { return m_size - m_at; }

 private:
  const std::uint8_t* Take(const char* field, std::size_t n) {
    if (n > Left()) Cut(field, n);
    const std::uint8_t* p = m_data + m_at;
    m_at += n;
    return p;
  }
  [[noreturn]] void Cut(const char* field, std::uint64_t n) const {
    Fail(field, "needs " + std::to_string(n) + " bytes at byte " + std::to_string(m_at) +
                    ", but the state ends at byte " + std::to_string(m_size) + " (cut short or corrupt)");
  }

  const std::uint8_t* m_data;
  std::size_t m_size;
  std::size_t m_at;
  std::string m_record;
};

}  // namespace REngine::state
