// What the triangle mesh suites (mesh_test, mesh_physics_test) share: a grid mesh of
// heights y(x, z), a box's and a sphere's shape, and a static body of a shape.
#pragma once

#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RShape.h>

#include <cstdint>
#include <functional>

#include "support/TestBodies.h"

namespace REngine::test {

// A grid of nx x nz quads over [x0, x0 + nx d] x [z0, z0 + nz d], heights y(x, z), two
// triangles a quad (diagonals alternating, as terrain exporters do).
inline RShape GridMesh(int nx, int nz, RScalar d, RScalar x0, RScalar z0,
                       const std::function<RScalar(RScalar, RScalar)>& y) {
  RShape s;
  s.type = RShapeType::kMesh;
  for (int j = 0; j <= nz; ++j) {
    for (int i = 0; i <= nx; ++i) {
      const RScalar x = x0 + i * d, z = z0 + j * d;
      s.points.emplace_back(x, y(x, z), z);
    }
  }
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < nz; ++j) {
    for (int i = 0; i < nx; ++i) {
      if ((i + j) % 2 == 0) {
        s.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
        s.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
      } else {
        s.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j)});
        s.triangles.push_back({at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
      }
    }
  }
  return s;
}

inline RShape Box(const RVec3& half) { return BoxDef(half).shape; }
inline RShape Sphere(RScalar r) { return SphereDef(r).shape; }

inline RBodyDef StaticBody(const RShape& shape, const RVec3& x = RVec3::Zero(),
                           const RQuat& q = RQuat::Identity()) {
  RBodyDef d;
  d.restitution = 0.5;
  d.name = "floor";
  d.kind = RBodyKind::kStatic;
  d.shape = shape;
  d.position_W = x, d.q_WS = q;
  return d;
}

}  // namespace REngine::test
