#include "Arena.h"

#include <REnginePhysics/RShape.h>

#include <cstring>
#include <vector>

using namespace REngine;

namespace rollback {

namespace {

RWorldSettings Settings(int threads) {
  RWorldSettings s;
  s.gravity_W = RVec3(0, -9.81, 0);
  s.threads = threads;
  return s;
}

RBodyDef Box(const RVec3& half, const RVec3& at, double mass) {
  RBodyDef d;
  d.shape = RShape::Box(half);
  d.position_W = at;
  d.mass = mass;
  d.friction = 0.5;
  d.restitution = 0.1;
  return d;
}

template <class T>
void Fold(std::uint64_t& h, const T& value) {
  unsigned char bytes[sizeof value];
  std::memcpy(bytes, &value, sizeof value);
  for (unsigned char b : bytes) h = (h ^ b) * 0x100000001b3ULL;
}
void FoldVec(std::uint64_t& h, const RVec3& v) { Fold(h, v.x()), Fold(h, v.y()), Fold(h, v.z()); }

}  // namespace

std::uint64_t Player::Random() {
  std::uint64_t z = (m_state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

Input Player::Next() {
  if (m_hold-- <= 0) {
    for (std::int8_t& t : m_held.thrust) t = static_cast<std::int8_t>(static_cast<int>(Random() % 3) - 1);
    m_held.fire = Random() % 4 == 0;
    m_hold = 3 + static_cast<int>(Random() % 12);
  }
  Input now = m_held;
  now.fire = m_held.fire && m_hold % 4 == 0;  // a shot every few frames while held
  return now;
}

Arena::Arena(int threads) : integrator(Settings(threads)) {
  RBodyDef ground = Box(RVec3(40, 0.5, 40), RVec3(0, -0.5, 0), 0);
  ground.kind = RBodyKind::kStatic;
  bodies.Add(ground);
  // The pile: 3 x 3 x 2 crates off to the side, which settle and sleep.
  for (int layer = 0; layer < 2; ++layer) {
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        bodies.Add(Box(RVec3::Constant(0.5), RVec3(12 + 1.02 * i, 0.5 + 1.02 * layer, 1.02 * k), 1));
      }
    }
  }
  for (int p = 0; p < kPlayers; ++p) {
    for (int s = 0; s < kShipsEach; ++s) {
      RBodyDef ship = Box(RVec3(0.6, 0.3, 0.4), RVec3(-6 + 4.0 * s, 0.3, p == 0 ? -6 : 6), 2);
      ship.locks.angular = {true, false, true};  // ships stay upright, turning about y
      ships[p * kShipsEach + s] = bodies.Add(ship);
    }
  }
}

void Arena::Advance(const FrameInputs& inputs) {
  const std::uint64_t frame = integrator.StepCount() + 1;
  // Shots whose time is up, oldest first by dense order (the same on every peer).
  std::vector<RBodyHandle> expired;
  for (std::size_t d = 0; d < bodies.Size(); ++d) {
    const std::uintptr_t born = bodies.At(d).UserData();
    if (born != 0 && born + kShotLife <= frame) expired.push_back(bodies.HandleAt(d));
  }
  for (RBodyHandle h : expired) bodies.Remove(h);
  for (int p = 0; p < kPlayers; ++p) {
    const Input& in = inputs[p];
    for (int s = 0; s < kShipsEach; ++s) {
      const RVec3 thrust(in.thrust[2 * s], 0, in.thrust[2 * s + 1]);
      if (!thrust.isZero(0)) bodies[ships[p * kShipsEach + s]].AddImpulse_W(0.4 * thrust);
    }
    if (in.fire) {
      const RRigidBody& ship = bodies[ships[p * kShipsEach]];
      RBodyDef shot;
      shot.shape = RShape::Sphere(0.15);
      shot.mass = 0.5;
      shot.restitution = 0.6;
      shot.position_W = ship.Position_W() + RVec3(0, 0.9, 0);
      // Towards the pile, lobbed: most shots land near it, some hit it and wake it.
      shot.velocity_W = RVec3((12.5 - shot.position_W.x()) * 0.9, 6, (1 - shot.position_W.z()) * 0.9);
      shot.userData = static_cast<std::uintptr_t>(frame);
      bodies.Add(shot);
    }
  }
  integrator.Update(bodies, kDt);
}

std::uint64_t Arena::Hash() const {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  Fold(h, integrator.StepCount());
  for (std::size_t d = 0; d < bodies.Size(); ++d) {
    const RRigidBody& b = bodies.At(d);
    Fold(h, bodies.HandleAt(d).index), Fold(h, bodies.HandleAt(d).generation);
    FoldVec(h, b.Position_W()), FoldVec(h, b.Velocity_W()), FoldVec(h, b.AngularVelocity_W());
    Fold(h, b.Orientation_WB().w()), FoldVec(h, b.Orientation_WB().vec());
    Fold(h, b.IsSleeping());
  }
  return h;
}

std::size_t Arena::Shots() const {
  std::size_t n = 0;
  for (std::size_t d = 0; d < bodies.Size(); ++d) n += bodies.At(d).UserData() != 0;
  return n;
}

}  // namespace rollback
