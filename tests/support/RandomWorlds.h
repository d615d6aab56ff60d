// Random worlds that are hard on a solver and on a broad phase alike: bodies from 1 cm to
// 100 m, spheres, boxes and tetrahedral hulls, at rest and at 3 km/s, static, not
// responding, spawned inside each other, plus a floor and a resting stack. The broad phase
// tests compare the pairs found in them; the response tests bound their energy.
// Header-only.
#pragma once

#include "TestBodies.h"

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace REngine::test {

// Draws in a fixed order. The order in which a call's arguments are evaluated is
// unspecified: written as RVec3(u(rng), u(rng), u(rng)), gcc draws the last component first
// and clang the first, and the worlds differed between the two compilers. These draw as gcc
// did (last first), so the worlds the tests were written against stay the same.
inline RVec3 DrawVec3(std::uniform_real_distribution<RScalar>& u, std::mt19937_64& rng) {
  const RScalar z = u(rng);
  const RScalar y = u(rng);
  const RScalar x = u(rng);
  return RVec3(x, y, z);
}
inline RQuat DrawQuat(std::uniform_real_distribution<RScalar>& u, std::mt19937_64& rng) {
  const RVec3 v = DrawVec3(u, rng);
  const RScalar w = u(rng);
  return RQuat(w - 0.5, v.x() - 0.5, v.y() - 0.5, v.z() - 0.5).normalized();
}

// A body drawn from rng around `origin` in a cube of side `side`.
inline RBodyDef DrawRandomBody(std::mt19937_64& rng, const RVec3& origin, RScalar side, int i) {
  std::uniform_real_distribution<RScalar> u(0, 1);
  // 1 cm to 3 m, and one body in 50 of 10 to 100 m (a station among debris).
  const RScalar size = u(rng) < 0.02 ? std::pow(10.0, 1 + u(rng)) : std::pow(10.0, -2 + 2.5 * u(rng));
  BodyDef d;
  switch (i % 3) {
    case 0: d = SphereDef(size); break;
    case 1: {
      const RScalar hz = size * (0.2 + u(rng));
      const RScalar hy = size * (0.2 + u(rng));
      d = BoxDef(RVec3(size, hy, hz));
      break;
    }
    default:
      d = HullDef({RVec3(0, 0, 0), RVec3(size, 0, 0), RVec3(0, size, 0), RVec3(0, 0, size),
                   RVec3(size, size, size) * 0.6});
  }
  d.position_W = origin + DrawVec3(u, rng) * side;
  d.q_WS = DrawQuat(u, rng);
  RScalar speed = 3000;
  if (u(rng) >= 0.05) {
    const RScalar a = u(rng);
    speed = 20 * a * u(rng);
  }
  d.velocity_W = (DrawVec3(u, rng) - RVec3::Constant(0.5)) * speed;
  d.angularVelocity_W = (DrawVec3(u, rng) - RVec3::Constant(0.5)) * 4;
  d.mass = 1 + 10 * u(rng);
  d.kind = u(rng) < 0.1 ? RBodyKind::kStatic : RBodyKind::kDynamic;
  d.responds = u(rng) > 0.05;
  d.name = "b" + std::to_string(i);
  return d;
}

// n bodies drawn from `seed` in a cube of side `side` at `origin`, then a floor below the
// cube and a stack of four 1 kg boxes resting on it (contacts touching exactly, then asleep).
inline std::vector<RBodyDef> RandomWorld(std::uint64_t seed, const RVec3& origin, int n, RScalar side) {
  std::mt19937_64 rng(seed);
  std::vector<RBodyDef> defs;
  for (int i = 0; i < n; ++i) defs.push_back(DrawRandomBody(rng, origin, side, i));
  BodyDef floor = BoxDef(RVec3(side, 0.5, side));
  floor.At(origin + RVec3(0, -0.5 - side, 0)).Static().Named("floor");
  defs.push_back(floor);
  for (int k = 0; k < 4; ++k) {
    defs.push_back(BoxDef(RVec3::Constant(0.5)).At(origin + RVec3(0, 0.5 + k - side, 0)).Mass(1).Named("s" + std::to_string(k)));
  }
  return defs;
}

}  // namespace REngine::test
