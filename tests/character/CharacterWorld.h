// A world for character tests: bodies, an integrator, queries and characters, stepped as a
// game steps them (the world, then each character).
#pragma once

#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RCharacter.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RQueries.h>

#include <array>
#include <cmath>
#include <vector>

namespace REngine::test {

constexpr RScalar kG = 9.81;
constexpr RScalar kDt = 1.0 / 60;

struct CharacterWorld {
  RBodies bodies;
  RIntegrator integrator;
  RQueries queries;
  RVec3 gravity = RVec3(0, -kG, 0);

  explicit CharacterWorld(int threads = 1) {
    integrator.Settings().gravity_W = gravity;
    integrator.Settings().threads = threads;
  }
  void SetGravity(const RVec3& g) { gravity = g, integrator.Settings().gravity_W = g; }

  RBodyHandle Box(const RVec3& half, const RVec3& centre, RBodyKind kind = RBodyKind::kStatic,
                  const RQuat& q = RQuat::Identity()) {
    RBodyDef def;
    def.shape = RShape::Box(half);
    def.kind = kind;
    def.position_W = centre;
    def.q_WS = q;
    def.density = 200;  // a wooden crate's, not water's thousandth: 25 kg for a 0.5 m cube
    return bodies.Add(def);
  }
  // A floor of n tiles 1 m long along x, side by side, top at y = 0.
  void Tiles(int n, RScalar x0 = -2) {
    for (int i = 0; i < n; ++i) Box(RVec3(0.5, 0.1, 2), RVec3(x0 + 0.5 + i, -0.1, 0));
  }
  void Step(std::vector<RCharacter*> characters, int steps = 1) {
    for (int k = 0; k < steps; ++k) {
      integrator.Update(bodies, kDt);
      for (RCharacter* c : characters) c->Update(bodies, queries, kDt, gravity);
    }
  }
};

// A capsule standing with its axis along y, its lowest point `gap` above y = floor.
inline RCharacterDef Capsule(RScalar radius = 0.3, RScalar halfHeight = 0.6, RScalar floor = 0,
                             RScalar x = 0, RScalar gap = 0.01) {
  RCharacterDef def;
  def.name = "player";
  def.shape = RShape::Capsule(radius, halfHeight);
  def.position_W = RVec3(x, floor + halfHeight + radius + gap, 0);
  return def;
}

}  // namespace REngine::test
