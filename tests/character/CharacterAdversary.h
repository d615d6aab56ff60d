// Shared by the character's adversarial tests (character_adversarial_*_test.cpp): the shapes
// they try and the floor they stand on.
#pragma once

#include "character/CharacterWorld.h"

#include <cmath>
#include <cstring>
#include <random>

namespace REngine::test {

inline constexpr RScalar kOff = 1e-3;

inline bool Finite(const RVec3& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

inline RCharacterDef BoxChar(RScalar hx = 0.3, RScalar hy = 0.9, RScalar hz = 0.3, RScalar gap = 0.01) {
  RCharacterDef d;
  d.shape = RShape::Box(RVec3(hx, hy, hz));
  d.position_W = RVec3(0, hy + gap, 0);
  return d;
}
inline RCharacterDef CylChar(RScalar r = 0.3, RScalar hh = 0.9, RScalar gap = 0.01) {
  RCharacterDef d;
  d.shape = RShape::Cylinder(r, hh);
  d.position_W = RVec3(0, hh + gap, 0);
  return d;
}
inline RScalar HalfHeight(const RCharacterDef& d) {
  switch (d.shape.type) {
    case RShapeType::kBox: return d.shape.halfExtents.y();
    case RShapeType::kCapsule: return d.shape.halfHeight + d.shape.radius;
    case RShapeType::kCylinder: return d.shape.halfHeight;
    case RShapeType::kSphere: return d.shape.radius;
    default: return 0;
  }
}
inline RBodyHandle Big(CharacterWorld& w, RScalar half = 20) { return w.Box(RVec3(half, 0.1, half), RVec3(0, -0.1, 0)); }


inline RCharacterDef SphereChar(RScalar r = 0.4) { RCharacterDef d; d.shape = RShape::Sphere(r); d.position_W = RVec3(0, r + 0.01, 0); return d; }
inline RCharacterDef YawedBox(RScalar yaw) {
  RCharacterDef d = BoxChar(0.3, 0.9, 0.2);
  d.q_WS = RQuat(Eigen::AngleAxisd(yaw, RVec3::UnitY()));
  return d;
}

inline RBodyDef MeshGrid(RScalar cell, int nx, int nz, RVec3 origin, RScalar bump = 0, unsigned seed = 1) {
  std::vector<RVec3> v;
  std::vector<std::array<std::uint32_t, 3>> t;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= nz; ++j) v.emplace_back(origin + RVec3(cell * i, bump * u(rng), cell * j));
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nz; ++j) {
      const std::uint32_t a = i * (nz + 1) + j, b = a + nz + 1;
      if ((i + j) % 2) { t.push_back({a, a + 1, b}); t.push_back({b, a + 1, b + 1}); }
      else { t.push_back({a, a + 1, b + 1}); t.push_back({a, b + 1, b}); }
    }
  RBodyDef d;
  d.shape = RShape::Mesh(v, t);
  d.kind = RBodyKind::kStatic;
  return d;
}

}  // namespace REngine::test
