// The scenes of seams_test: a row (or grid) of immovable tiles laid flush, and one body that
// slides or rolls across them. Everything is built in a scene frame (x the direction of
// motion, y the floor's normal, the tiles' tops at y = 0) that the frame maps to the world,
// so a floor laid along a diagonal, far from the origin, or turned into a wall is the same
// scene. Header-only.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RShape.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace REngine::test {

enum class Mover : std::uint8_t {
  kBox,              // 0.6 x 0.4 x 0.5 m, frictionless, sliding
  kSphere,           // radius 0.25 m, rolling (w = v / r)
  kCapsuleSliding,   // radius 0.15 m, core 0.6 m along the motion, frictionless
  kCapsuleRolling,   // the same capsule across the motion, rolling
  kCylinderRolling,  // radius 0.25 m, 0.4 m long, on its side across the motion, rolling
  kCylinderOnCap,    // the same cylinder standing on an end, frictionless, sliding
  kHull,             // a hexagonal prism (hull of 12 points), turned 0.3 rad, frictionless
};
constexpr std::array<Mover, 7> kMovers{Mover::kBox, Mover::kSphere, Mover::kCapsuleSliding, Mover::kCapsuleRolling,
                                       Mover::kCylinderRolling, Mover::kCylinderOnCap, Mover::kHull};
inline const char* Name(Mover m) {
  static const char* const names[] = {"box", "sphere", "capsule sliding", "capsule rolling", "cylinder rolling",
                                      "cylinder on cap", "hull"};
  return names[static_cast<int>(m)];
}

enum class Tiles : std::uint8_t {
  kBoxes,       // boxes 1 m (along x) x 0.2 m x 4 m
  kHulls,       // hulls of the same top, their sides slanting in z (trapezoid prisms)
  kMeshes,      // one mesh body per tile: a flat quad of two triangles
  kKinematic,   // the boxes, kinematic and still
  kOneFloor,    // the reference: one box under the whole row
  kCompound,    // one compound body whose children are the box tiles
};
inline const char* Name(Tiles t) {
  static const char* const names[] = {"boxes", "hulls", "meshes", "kinematic boxes", "one floor", "compound"};
  return names[static_cast<int>(t)];
}

// The scene frame in the world: p_W = R p + origin; gravity is -g along R y.
struct SceneFrame {
  const char* name;
  RMat3 R;
  RVec3 origin;
};
inline std::vector<SceneFrame> Frames() {
  const RMat3 yaw = Eigen::AngleAxisd(0.6, RVec3::UnitY()).toRotationMatrix();
  const RMat3 wall = Eigen::AngleAxisd(M_PI / 2, RVec3::UnitX()).toRotationMatrix();  // y -> z
  return {{"flat", RMat3::Identity(), RVec3::Zero()},
          {"diagonal", yaw, RVec3::Zero()},
          {"far (1e5 m)", yaw, RVec3(1e5, 1e5, -1e5)},
          {"wall", wall, RVec3::Zero()}};
}

// One crossing: the scene and what to change in it.
struct Crossing {
  Mover mover = Mover::kBox;
  Tiles tiles = Tiles::kBoxes;
  RScalar speed = 5;      // m/s along x
  bool gravity = true;    // 9.81 m/s^2 pressing the body on the tiles
  SceneFrame frame{"flat", RMat3::Identity(), RVec3::Zero()};
  int tileCount = 6;
  // Tile `raised` (-1: none) stands `rise` m higher than the others (a real step); a gap of
  // `gap` m opens before tile `gapAt` (-1: none), the tiles from it on moved along x.
  int raised = -1;
  RScalar rise = 0;
  int gapAt = -1;
  RScalar gap = 0;
  // Odd tiles moved along x by this (m): seams alternately this much open and closed.
  RScalar jitter = 0;
  // Grid: the tiles are 1 m squares in a grid turned by tileYaw about y (the body then
  // crosses seams of both directions and the corners where four tiles meet).
  bool grid = false;
  RScalar tileYaw = 0;
  RScalar restitution = 0;
  RScalar moverFriction = -1;  // >= 0: the mover's friction instead of its own (rollers 0.5, others 0)
};

inline RBodyDef Immovable(RBodyDef d, const Crossing& c) {
  d.kind = c.tiles == Tiles::kKinematic ? RBodyKind::kKinematic : RBodyKind::kStatic;
  d.friction = 0.5, d.restitution = c.restitution;
  return d;
}

// Tile k (scene frame): its top face spans x in [x0, x0 + 1], z in [z0, z0 + w], at y = top.
inline RBodyDef Tile(const Crossing& c, RScalar x0, RScalar z0, RScalar w, RScalar top, int k,
                     const RMat3& R_tiles) {
  RBodyDef d;
  const RScalar hx = 0.5, hz = w / 2;
  // The tile's shape frame at the centre of its top face.
  const RVec3 centre(x0 + hx, top, z0 + hz);
  switch (c.tiles) {
    case Tiles::kHulls:
      d.shape = RShape::Hull({RVec3(-hx, 0, -hz), RVec3(hx, 0, -hz), RVec3(hx, 0, hz), RVec3(-hx, 0, hz),
                              RVec3(-hx, -0.2, -0.75 * hz), RVec3(hx, -0.2, -0.75 * hz), RVec3(hx, -0.2, 0.75 * hz),
                              RVec3(-hx, -0.2, 0.75 * hz)});
      break;
    case Tiles::kMeshes: {
      // Diagonals alternate from tile to tile, as a terrain exporter lays them.
      std::vector<RVec3> v{RVec3(-hx, 0, -hz), RVec3(hx, 0, -hz), RVec3(hx, 0, hz), RVec3(-hx, 0, hz)};
      std::vector<std::array<std::uint32_t, 3>> t;
      if (k % 2 == 0) {
        t = {{0, 2, 1}, {0, 3, 2}};
      } else {
        t = {{0, 3, 1}, {1, 3, 2}};
      }
      d.shape = RShape::Mesh(std::move(v), std::move(t));
      break;
    }
    default:
      d.shape = RShape::Box(RVec3(hx, 0.1, hz));
      break;
  }
  RVec3 at = centre;
  if (c.tiles != Tiles::kHulls && c.tiles != Tiles::kMeshes) at.y() -= 0.1;  // a box's frame is its centre
  d.position_W = c.frame.R * (R_tiles * at) + c.frame.origin;
  d.q_WS = RQuat(c.frame.R * R_tiles);
  return Immovable(d, c);
}

// The moving body at scene position x (its lowest point on y = 0) with the crossing's speed.
inline RBodyDef MoverDef(const Crossing& c, RScalar x, RScalar& height, RVec3& w0) {
  RBodyDef d;
  d.mass = 1;
  d.restitution = c.restitution;
  d.friction = 0;
  RMat3 R_S = RMat3::Identity();  // the shape frame in the scene frame
  w0.setZero();
  const RMat3 lying = Eigen::AngleAxisd(M_PI / 2, RVec3::UnitX()).toRotationMatrix();  // S's y along z
  switch (c.mover) {
    case Mover::kBox:
      d.shape = RShape::Box(RVec3(0.3, 0.2, 0.25)), height = 0.2;
      break;
    case Mover::kSphere:
      d.shape = RShape::Sphere(0.25), height = 0.25, d.friction = 0.5, w0 = RVec3(0, 0, -c.speed / 0.25);
      break;
    case Mover::kCapsuleSliding:
      d.shape = RShape::Capsule(0.15, 0.3), height = 0.15;
      R_S = Eigen::AngleAxisd(-M_PI / 2, RVec3::UnitZ()).toRotationMatrix();  // S's y along x
      break;
    case Mover::kCapsuleRolling:
      d.shape = RShape::Capsule(0.15, 0.3), height = 0.15, R_S = lying, d.friction = 0.5;
      w0 = RVec3(0, 0, -c.speed / 0.15);
      break;
    case Mover::kCylinderRolling:
      d.shape = RShape::Cylinder(0.25, 0.2), height = 0.25, R_S = lying, d.friction = 0.5;
      w0 = RVec3(0, 0, -c.speed / 0.25);
      break;
    case Mover::kCylinderOnCap:
      d.shape = RShape::Cylinder(0.25, 0.2), height = 0.2;
      break;
    case Mover::kHull: {
      std::vector<RVec3> p;
      for (int k = 0; k < 6; ++k) {
        const RScalar a = 0.3 + k * M_PI / 3;
        p.emplace_back(0.3 * std::cos(a), -0.15, 0.3 * std::sin(a));
        p.emplace_back(0.3 * std::cos(a), 0.15, 0.3 * std::sin(a));
      }
      d.shape = RShape::Hull(std::move(p)), height = 0.15;
      break;
    }
  }
  if (c.moverFriction >= 0) d.friction = c.moverFriction;
  d.position_W = c.frame.R * RVec3(x, height, 0) + c.frame.origin;
  d.q_WS = RQuat(c.frame.R * R_S);
  d.velocity_W = c.frame.R * RVec3(c.speed, 0, 0);
  d.angularVelocity_W = c.frame.R * w0;
  return d;
}

// The tiles of a crossing, in the world, then the mover (the last body).
inline std::vector<RRigidBody> SeamScene(const Crossing& c, RScalar startX, RScalar& height, RVec3& w0) {
  std::vector<RRigidBody> bodies;
  if (c.tiles == Tiles::kOneFloor) {
    RBodyDef d;
    d.shape = RShape::Box(RVec3(0.5 * c.tileCount, 0.1, 2));
    d.position_W = c.frame.R * RVec3(0.5 * c.tileCount, -0.1, 0) + c.frame.origin;
    d.q_WS = RQuat(c.frame.R);
    bodies.emplace_back(Immovable(d, c));
  } else if (c.tiles == Tiles::kCompound) {
    std::vector<RCompoundChild> children;
    for (int k = 0; k < c.tileCount; ++k) {
      const RScalar x0 = k + (c.gapAt >= 0 && k >= c.gapAt ? c.gap : 0) + (k % 2 ? c.jitter : 0);
      children.push_back({RShape::Box(RVec3(0.5, 0.1, 2)), RVec3(x0 + 0.5, (k == c.raised ? c.rise : 0) - 0.1, 0)});
    }
    RBodyDef d;
    d.shape = RShape::Compound(std::move(children));
    d.position_W = c.frame.origin;
    d.q_WS = RQuat(c.frame.R);
    bodies.emplace_back(Immovable(d, c));
  } else if (c.grid) {
    const RMat3 R_tiles = Eigen::AngleAxisd(c.tileYaw, RVec3::UnitY()).toRotationMatrix();
    const int n = c.tileCount;
    for (int i = -2; i < n; ++i) {
      for (int j = -n / 2 - 2; j < n / 2 + 2; ++j) bodies.emplace_back(Tile(c, i, j, 1, 0, i + j, R_tiles));
    }
  } else {
    for (int k = 0; k < c.tileCount; ++k) {
      const RScalar x0 = k + (c.gapAt >= 0 && k >= c.gapAt ? c.gap : 0) + (k % 2 ? c.jitter : 0);
      bodies.emplace_back(Tile(c, x0, -2, 4, k == c.raised ? c.rise : 0, k, RMat3::Identity()));
    }
  }
  bodies.emplace_back(MoverDef(c, startX, height, w0));
  return bodies;
}

// What a crossing did, in the scene frame: the largest departures from the closed form
// (constant velocity v0 x along the floor and spin, constant height), the largest hop, the
// exit velocity. The velocity across the floor is not asked to be 0 at the end of a step: a
// body rolling on a line contact (a capsule, a cylinder) under gravity reports -g dt / 2 on
// one floor too (its end-of-step contact does not close), while its height stays constant.
struct CrossingResult {
  RScalar speedError = 0;   // max |(vx - v0, vz)|, m/s
  RScalar spinError = 0;    // max |w - w0|, rad/s
  RScalar heightError = 0;  // max |y - y0|, m
  RScalar hop = 0;          // max y - y0, m
  RVec3 exitV = RVec3::Zero();
  RScalar exitX = 0;        // the body's x at the end, m
  RScalar minY = 0;         // its lowest y over the run, m
};

inline void SetGravity(RIntegrator& integrator, const Crossing& c) {
  integrator.Settings().gravity_W = c.gravity ? RVec3(c.frame.R * RVec3(0, -9.81, 0)) : RVec3::Zero();
}

// Runs the crossing for `steps` steps of dt from x = startX.
inline CrossingResult RunCrossing(const Crossing& c, RScalar startX, int steps, RScalar dt = 1.0 / 60) {
  RScalar height = 0;
  RVec3 w0;
  std::vector<RRigidBody> bodies = SeamScene(c, startX, height, w0);
  RIntegrator integrator;
  SetGravity(integrator, c);
  integrator.Settings().shortcuts.sleeping = false;
  CrossingResult r;
  r.minY = height;
  const RMat3 RT = c.frame.R.transpose();
  const RVec3 v0(c.speed, 0, 0);
  for (int k = 0; k < steps; ++k) {
    integrator.Update(bodies, dt);
    const RRigidBody& m = bodies.back();
    const RVec3 x = RT * (m.Position_W() - c.frame.origin);
    const RVec3 v = RT * m.Velocity_W();
    const RVec3 w = RT * m.AngularVelocity_W();
    r.speedError = std::max(r.speedError, std::hypot(v.x() - v0.x(), v.z()));
    r.spinError = std::max(r.spinError, (w - w0).norm());
    r.heightError = std::max(r.heightError, std::abs(x.y() - height));
    r.hop = std::max(r.hop, x.y() - height);
    r.minY = std::min(r.minY, x.y());
    r.exitV = v, r.exitX = x.x();
  }
  return r;
}

}  // namespace REngine::test
