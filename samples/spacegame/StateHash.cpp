#include "StateHash.h"

#include <cstdio>
#include <cstring>

namespace spacegame {
using namespace REngine;

namespace {
struct Fnv1a {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void Bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 0x100000001b3ull;
  }
  // Doubles by their bits: -0.0 and 0.0 differ, which a bit-for-bit check wants.
  void Vec(const RVec3& v) { Bytes(v.data(), 3 * sizeof(double)); }
  template <class T>
  void Pod(const T& v) {
    Bytes(&v, sizeof v);
  }
};
}  // namespace

std::uint64_t HashState(const RBodies& bodies) {
  Fnv1a f;
  f.Pod(std::uint64_t(bodies.EnabledCount()));
  for (std::size_t i = 0; i < bodies.EnabledCount(); ++i) {
    const RRigidBody& b = bodies.At(i);
    const RBodyHandle h = bodies.HandleAt(i);
    f.Pod(h.index), f.Pod(h.generation);
    f.Vec(b.Position_W());
    f.Bytes(b.Orientation_WB().coeffs().data(), 4 * sizeof(double));
    f.Vec(b.Velocity_W());
    f.Vec(b.AngularVelocity_B());
    f.Pod(std::uint8_t(b.IsSleeping()));
  }
  f.Pod(std::uint64_t(bodies.JointCount()));
  for (std::size_t j = 0; j < bodies.JointCount(); ++j) {
    const RJointHandle h = bodies.JointHandleAt(j);
    f.Pod(h.index), f.Pod(h.generation);
  }
  return f.h;
}

std::string HashHex(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace spacegame
