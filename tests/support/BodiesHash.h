// A hash of a container's public state for tests that compare worlds bit for bit (save and
// load, snapshots): FNV-1a over raw bytes (doubles by their bits, so -0.0 and 0.0 differ).
#pragma once

#include <REnginePhysics/RBodies.h>

#include <cstdint>
#include <cstring>

namespace REngine::test {

template <class T>
void Fold(std::uint64_t& h, const T& value) {
  unsigned char bytes[sizeof value];
  std::memcpy(bytes, &value, sizeof value);
  for (unsigned char b : bytes) h = (h ^ b) * 0x100000001b3ULL;
}
inline void FoldVec(std::uint64_t& h, const RVec3& v) { Fold(h, v.x()), Fold(h, v.y()), Fold(h, v.z()); }

// Every body's public state in dense order with its handle and whether it is enabled, and
// the joints' impulses: equal for bit-identical worlds.
inline std::uint64_t BodiesHash(const RBodies& bodies) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (std::size_t d = 0; d < bodies.Size(); ++d) {
    const RRigidBody& b = bodies.At(d);
    Fold(h, bodies.HandleAt(d).index), Fold(h, bodies.HandleAt(d).generation);
    Fold(h, bodies.IsEnabled(bodies.HandleAt(d)));
    FoldVec(h, b.Position_W()), FoldVec(h, b.Velocity_W());
    FoldVec(h, b.AngularVelocity_B()), FoldVec(h, b.AngularVelocity_W());
    Fold(h, b.Orientation_WB().w()), FoldVec(h, b.Orientation_WB().vec());
    Fold(h, b.IsSleeping());
  }
  for (std::size_t k = 0; k < bodies.JointCount(); ++k) FoldVec(h, bodies.JointAt(k).impulse_W);
  return h;
}

}  // namespace REngine::test
