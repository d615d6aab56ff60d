// REngine bodies -> a Bullet world: the builder shared by bench_bullet (scene files against
// Bullet) and rengine-bench (work-precision runs, Bullet as a series). Header-only; include it
// only where Bullet is found (tools/bench/CMakeLists.txt).
//
// The Bullet world is what a Bullet user would build for the scene: btDbvtBroadphase,
// btSequentialImpulseConstraintSolver with the settings' solver iterations, the settings'
// gravity, no motion states. The caller steps it with stepSimulation(dt, 0): maxSubSteps 0
// makes Bullet take exactly one internal step of dt per call (no fixed-step accumulator, no
// interpolation). Each body gets REngine's mass and principal moments (exact for every shape;
// Bullet's own hull inertia is a bounding-box estimate) and its pose in REngine's body frame
// (centre of mass, principal axes), which is what Bullet's rigid-body frame is. Static bodies
// are mass 0.
//
// What still differs:
//  * Combine modes: Bullet multiplies the two bodies' restitutions and frictions, REngine
//    combines them as RWorldSettings says (min restitution and geometric friction by
//    default). ChooseCoefficients(..., match = true) gives Bullet per-body values whose
//    products are REngine's combined values when one map does it for every pair (sqrt for
//    geometric friction; the values themselves for a product, or for min over values in
//    {0, 1}); the largest remaining difference is reported.
//  * Sleeping: the builder switches Bullet's deactivation off unless asked (REngine's own
//    sleeping is exact for drifting bodies; see RWorldSettings::RShortcuts).
//  * Bullet's collision margin (0.04 m, inside a box, outside a hull: a hull is 0.04 m larger
//    in Bullet) and its restitution threshold (0.2 m/s; REngine's is 0.5 m/s).
#pragma once

#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace REngine::bench {

inline btScalar Bt(RScalar x) { return static_cast<btScalar>(x); }
inline btVector3 Bt(const RVec3& v) { return btVector3(Bt(v.x()), Bt(v.y()), Bt(v.z())); }
inline btQuaternion Bt(const RQuat& q) {
  return btQuaternion(Bt(q.x()), Bt(q.y()), Bt(q.z()), Bt(q.w()));
}
inline RVec3 R(const btVector3& v) { return RVec3(v.x(), v.y(), v.z()); }
inline RQuat R(const btQuaternion& q) { return RQuat(q.w(), q.x(), q.y(), q.z()); }

// Per-body coefficients handed to Bullet, which multiplies a pair's two values.
struct BulletCoefficients {
  std::vector<RScalar> restitution, friction;
  // Largest |Bullet's pair value - REngine's combined value| over the pairs that can
  // collide (not static with static), and one such pair's two values.
  RScalar restitutionError = 0, frictionError = 0;
  std::string restitutionExample, frictionExample;
};

// Maps each body's coefficient (get(body)) to a Bullet value: the value itself, or its
// square root, the first that makes every product equal to the combined value (when
// matching), and reports how far the products are from the combine rule.
template <class Get>
std::vector<RScalar> MapCoefficients(const std::vector<RRigidBody>& bodies, RCombineMode mode,
                                     bool match, Get get, RScalar& maxError,
                                     std::string& example) {
  // Distinct (value, static) pairs are all that matter: a few, whatever the body count.
  std::vector<std::pair<RScalar, bool>> values;
  for (const RRigidBody& b : bodies) values.emplace_back(get(b), b.IsStatic());
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());

  using Map = RScalar (*)(RScalar);
  const std::array<Map, 2> maps = {[](RScalar x) { return x; },
                                   [](RScalar x) { return std::sqrt(x); }};
  auto errorOf = [&](Map f, std::string* ex) {
    RScalar worst = 0;
    for (std::size_t i = 0; i < values.size(); ++i) {
      for (std::size_t j = i; j < values.size(); ++j) {
        if (values[i].second && values[j].second) continue;  // static pairs never touch
        const RScalar a = values[i].first, b = values[j].first;
        const RScalar err = std::abs(f(a) * f(b) - Combine(mode, a, b));
        if (err > worst) {
          worst = err;
          if (ex) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "%g with %g: REngine %g, Bullet %g", a, b,
                          Combine(mode, a, b), f(a) * f(b));
            *ex = buf;
          }
        }
      }
    }
    return worst;
  };
  Map chosen = maps[0];
  if (match) {
    for (Map f : maps) {
      if (errorOf(f, nullptr) <= 1e-12) {
        chosen = f;
        break;
      }
    }
  }
  maxError = errorOf(chosen, &example);
  std::vector<RScalar> out;
  out.reserve(bodies.size());
  for (const RRigidBody& b : bodies) out.push_back(chosen(get(b)));
  return out;
}

inline BulletCoefficients ChooseCoefficients(const RWorldSettings& settings,
                                             const std::vector<RRigidBody>& bodies, bool match) {
  BulletCoefficients c;
  c.restitution = MapCoefficients(
      bodies, settings.restitutionCombine, match,
      [](const RRigidBody& b) { return b.Restitution(); }, c.restitutionError,
      c.restitutionExample);
  c.friction = MapCoefficients(
      bodies, settings.frictionCombine, match, [](const RRigidBody& b) { return b.Friction(); },
      c.frictionError, c.frictionExample);
  return c;
}

// A Bullet world owns everything it steps. Bodies leave the world before it is destroyed.
struct BulletWorld {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btTriangleMesh>> meshes;  // the triangles a mesh shape reads
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  // REngine's body for each, for mass properties; the caller keeps them alive.
  std::vector<const RRigidBody*> reference;

  BulletWorld() = default;
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;
  ~BulletWorld() {
    for (auto& b : bodies) world.removeRigidBody(b.get());
  }
};

// The body's collision shape in its body frame B (centre of mass, principal axes), shared
// between bodies with the same box or sphere as a Bullet user would.
inline btCollisionShape* MakeShape(BulletWorld& w, const RRigidBody& b,
                                   std::map<std::array<RScalar, 4>, btCollisionShape*>& shared) {
  const RShape& s = b.Shape();
  const bool offset = b.ShapeOffset_B().norm() > 0 ||
                      b.ShapeRotation_BS().angularDistance(RQuat::Identity()) > 0;
  std::unique_ptr<btCollisionShape> shape;
  if (s.type == RShapeType::kMesh) {
    // Bullet's triangle mesh with its own tree, the vertices taken into B (static only there).
    auto triangles = std::make_unique<btTriangleMesh>();
    const auto at = [&](std::uint32_t i) { return Bt(b.ShapeOffset_B() + b.ShapeRotation_BS() * s.points[i]); };
    for (const auto& t : s.triangles) triangles->addTriangle(at(t[0]), at(t[1]), at(t[2]));
    shape = std::make_unique<btBvhTriangleMeshShape>(triangles.get(), true);
    w.meshes.push_back(std::move(triangles));
  } else if (s.type == RShapeType::kCompound) {
    // Bullet's compound of the children, each child's shape posed in B as REngine poses it.
    auto compound = std::make_unique<btCompoundShape>();
    const RPreparedShape& prepared = *b.PreparedShape();
    for (std::size_t i = 0; i < prepared.children.size(); ++i) {
      const RShape& cs = prepared.childShapes[i]->shape;
      const RShapeChild& c = prepared.children[i];
      const RPreparedShape& cp = *prepared.childShapes[i];
      std::unique_ptr<btCollisionShape> child;
      if (cs.type == RShapeType::kHull) {
        auto hull = std::make_unique<btConvexHullShape>();
        for (const RVec3& p_S : cs.points) hull->addPoint(Bt(cp.p_BS + cp.q_BS * p_S), false);
        hull->recalcLocalAabb();
        child = std::move(hull);
      } else if (cs.type == RShapeType::kBox) {
        child = std::make_unique<btBoxShape>(Bt(cs.halfExtents));
      } else if (cs.type == RShapeType::kCapsule) {
        child = std::make_unique<btCapsuleShape>(btScalar(cs.radius), btScalar(2 * cs.halfHeight));
      } else if (cs.type == RShapeType::kCylinder) {
        child = std::make_unique<btCylinderShape>(btVector3(btScalar(cs.radius), btScalar(cs.halfHeight), btScalar(cs.radius)));
      } else {
        child = std::make_unique<btSphereShape>(Bt(cs.radius));
      }
      compound->addChildShape(btTransform(Bt(RQuat(c.R_BC)), Bt(c.p_BC)), child.get());
      w.shapes.push_back(std::move(child));
    }
    shape = std::move(compound);
  } else if (s.type == RShapeType::kHull) {
    // Points taken into B; the hull of the points, as REngine builds it.
    auto hull = std::make_unique<btConvexHullShape>();
    for (const RVec3& p_S : s.points) {
      hull->addPoint(Bt(b.ShapeOffset_B() + b.ShapeRotation_BS() * p_S), false);
    }
    hull->recalcLocalAabb();
    hull->optimizeConvexHull();
    shape = std::move(hull);
  } else {
    const std::array<RScalar, 4> key =
        s.type == RShapeType::kBox
            ? std::array<RScalar, 4>{0, s.halfExtents.x(), s.halfExtents.y(), s.halfExtents.z()}
        : s.type == RShapeType::kCapsule  ? std::array<RScalar, 4>{2, s.radius, s.halfHeight, 0}
        : s.type == RShapeType::kCylinder ? std::array<RScalar, 4>{3, s.radius, s.halfHeight, 0}
                                          : std::array<RScalar, 4>{1, s.radius, 0, 0};
    if (!offset) {
      if (auto it = shared.find(key); it != shared.end()) return it->second;
    }
    if (s.type == RShapeType::kBox) {
      shape = std::make_unique<btBoxShape>(Bt(s.halfExtents));
    } else if (s.type == RShapeType::kCapsule) {  // Bullet's is along y too, height between centres
      shape = std::make_unique<btCapsuleShape>(btScalar(s.radius), btScalar(2 * s.halfHeight));
    } else if (s.type == RShapeType::kCylinder) {  // Bullet's btCylinderShape is along y, half extents (r, h, r)
      shape = std::make_unique<btCylinderShape>(btVector3(btScalar(s.radius), btScalar(s.halfHeight), btScalar(s.radius)));
    } else {
      shape = std::make_unique<btSphereShape>(Bt(s.radius));
    }
    if (offset) {
      // Not expected (a box's and a sphere's body frame is their shape frame), but correct.
      auto compound = std::make_unique<btCompoundShape>();
      compound->addChildShape(btTransform(Bt(b.ShapeRotation_BS()), Bt(b.ShapeOffset_B())),
                              shape.get());
      w.shapes.push_back(std::move(shape));
      shape = std::move(compound);
    } else {
      shared[key] = shape.get();
    }
  }
  w.shapes.push_back(std::move(shape));
  return w.shapes.back().get();
}

// Builds the Bullet twin of `reference` (REngine's bodies, in their current state), which
// must outlive the world. ignore[i]: indices of the bodies body i never collides with (a
// scene's ignore lists; empty: none). sleep: leave Bullet's deactivation on.
inline std::unique_ptr<BulletWorld> BuildBullet(
    const RWorldSettings& settings, const std::vector<RRigidBody>& reference,
    const BulletCoefficients& coeffs, bool sleep,
    const std::vector<std::vector<std::size_t>>& ignore = {}) {
  auto w = std::make_unique<BulletWorld>();
  w->world.setGravity(Bt(settings.gravity_W));
  w->world.getSolverInfo().m_numIterations = settings.solverIterations;
  std::map<std::array<RScalar, 4>, btCollisionShape*> shared;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const RRigidBody& b = reference[i];
    btCollisionShape* shape = MakeShape(*w, b, shared);
    const btScalar mass = b.IsStatic() ? btScalar(0) : Bt(b.Mass());
    const btVector3 inertia = b.IsStatic() ? btVector3(0, 0, 0) : Bt(b.Inertia_B());
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape, inertia);
    info.m_startWorldTransform = btTransform(Bt(b.Orientation_WB()), Bt(b.Position_W()));
    info.m_restitution = Bt(coeffs.restitution[i]);
    info.m_friction = Bt(coeffs.friction[i]);
    auto body = std::make_unique<btRigidBody>(info);
    if (!b.IsStatic()) {
      body->setLinearVelocity(Bt(b.Velocity_W()));
      body->setAngularVelocity(Bt(b.AngularVelocity_W()));
      if (!sleep) body->setActivationState(DISABLE_DEACTIVATION);
    }
    if (!b.Responds()) {
      body->setCollisionFlags(body->getCollisionFlags() |
                              btCollisionObject::CF_NO_CONTACT_RESPONSE);
    }
    w->world.addRigidBody(body.get());
    w->bodies.push_back(std::move(body));
    w->reference.push_back(&b);
  }
  for (std::size_t i = 0; i < ignore.size(); ++i) {
    for (std::size_t j : ignore[i]) {
      w->bodies[i]->setIgnoreCollisionCheck(w->bodies[j].get(), true);
    }
  }
  return w;
}

}  // namespace REngine::bench
