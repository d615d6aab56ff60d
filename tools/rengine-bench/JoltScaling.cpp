// rengine-bench --scaling's Jolt series (JoltScaling.h): the scene's bodies as Jolt Physics
// 5.5 bodies (double precision), built as a Jolt user would build them, with what REngine's
// world is given copied over:
//
//  * Bodies: the ones CreateBodies makes for REngine (so masses, inertia and poses are
//    REngine's): each at REngine's centre of mass and principal axes (its body frame B), its
//    shape expressed in B, mass and principal moments given to Jolt
//    (EOverrideMassProperties::MassAndInertiaProvided, as tools/bench/BulletWorld.h gives
//    Bullet REngine's), velocity and angular velocity, friction and restitution; static,
//    kinematic or dynamic; sensors (bodies that do not respond) as Jolt sensors. No damping
//    (Jolt's default is 0.05; REngine and Bullet have none). Boxes and spheres share one Jolt
//    shape per size, as Jolt's samples do; hulls get Jolt's default convex radius (5 cm).
//  * Combine rules: Jolt's defaults are geometric friction and max restitution; REngine's
//    are the scene's (geometric and min by default), so Jolt is given REngine's rules
//    (SetCombineFriction / SetCombineRestitution).
//  * Settings: gravity; the scene's sleeping switch as Jolt's mAllowSleeping (per body and
//    in PhysicsSettings; Jolt's own sleep thresholds, 0.5 s under 3 cm/s); velocity steps =
//    the scene's solver iterations (10 in every scaling scene, which is also Jolt's default)
//    and Jolt's default 2 position steps (REngine has no separate position iterations; 2 is
//    what Jolt is tuned and benchmarked with); restitution from REngine's threshold (0.5 m/s,
//    Jolt's default 1 m/s). Discrete motion quality (Jolt's default). One Update per step,
//    one collision step (Update(dt, 1, ...)), as REngine and Bullet take one step of dt.
//  * Layers: Jolt's usual two (static and moving, static never tested against static), each
//    its own broad-phase tree; OptimizeBroadPhase after the bodies are added, as Jolt asks.
//
// Not mapped (the run reports it and is skipped): compound and mesh shapes, the scene's
// ignore lists, joints. The scaling scenes use boxes and hulls only.
#include "JoltScaling.h"

#include <Jolt/Jolt.h>

#include <Jolt/Core/Factory.h>
#include <Jolt/Core/JobSystemThreadPool.h>
#include <Jolt/Core/TempAllocator.h>
#include <Jolt/Physics/Body/BodyCreationSettings.h>
#include <Jolt/Physics/Collision/Shape/BoxShape.h>
#include <Jolt/Physics/Collision/Shape/CapsuleShape.h>
#include <Jolt/Physics/Collision/Shape/ConvexHullShape.h>
#include <Jolt/Physics/Collision/Shape/CylinderShape.h>
#include <Jolt/Physics/Collision/Shape/RotatedTranslatedShape.h>
#include <Jolt/Physics/Collision/Shape/SphereShape.h>
#include <Jolt/Physics/PhysicsSystem.h>
#include <Jolt/RegisterTypes.h>

#include <REnginePhysics/RIntegrator.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <map>
#include <memory>
#include <vector>

using namespace REngine;

namespace rbench {

namespace {

namespace Layers {
constexpr JPH::ObjectLayer kStatic = 0, kMoving = 1, kCount = 2;
}

class BroadLayers final : public JPH::BroadPhaseLayerInterface {
 public:
  JPH::uint GetNumBroadPhaseLayers() const override { return 2; }
  JPH::BroadPhaseLayer GetBroadPhaseLayer(JPH::ObjectLayer layer) const override {
    return JPH::BroadPhaseLayer(static_cast<JPH::BroadPhaseLayer::Type>(layer));
  }
#if defined(JPH_EXTERNAL_PROFILE) || defined(JPH_PROFILE_ENABLED)
  const char* GetBroadPhaseLayerName(JPH::BroadPhaseLayer layer) const override {
    return layer.GetValue() == Layers::kStatic ? "static" : "moving";
  }
#endif
};
class ObjectVsBroad final : public JPH::ObjectVsBroadPhaseLayerFilter {
 public:
  bool ShouldCollide(JPH::ObjectLayer object, JPH::BroadPhaseLayer broad) const override {
    return object == Layers::kMoving || broad.GetValue() == Layers::kMoving;
  }
};
class ObjectPairs final : public JPH::ObjectLayerPairFilter {
 public:
  bool ShouldCollide(JPH::ObjectLayer a, JPH::ObjectLayer b) const override {
    return a == Layers::kMoving || b == Layers::kMoving;
  }
};

// Jolt's combine hooks are plain function pointers: one instance per REngine rule.
template <RCombineMode M>
float CombineFriction(const JPH::Body& a, const JPH::SubShapeID&, const JPH::Body& b, const JPH::SubShapeID&) {
  return static_cast<float>(Combine(M, a.GetFriction(), b.GetFriction()));
}
template <RCombineMode M>
float CombineRestitution(const JPH::Body& a, const JPH::SubShapeID&, const JPH::Body& b, const JPH::SubShapeID&) {
  return static_cast<float>(Combine(M, a.GetRestitution(), b.GetRestitution()));
}
JPH::ContactConstraintManager::CombineFunction FrictionRule(RCombineMode mode) {
  switch (mode) {
    case RCombineMode::kMin: return CombineFriction<RCombineMode::kMin>;
    case RCombineMode::kMax: return CombineFriction<RCombineMode::kMax>;
    case RCombineMode::kProduct: return CombineFriction<RCombineMode::kProduct>;
    case RCombineMode::kAverage: return CombineFriction<RCombineMode::kAverage>;
    case RCombineMode::kGeometric: break;
  }
  return CombineFriction<RCombineMode::kGeometric>;
}
JPH::ContactConstraintManager::CombineFunction RestitutionRule(RCombineMode mode) {
  switch (mode) {
    case RCombineMode::kMax: return CombineRestitution<RCombineMode::kMax>;
    case RCombineMode::kProduct: return CombineRestitution<RCombineMode::kProduct>;
    case RCombineMode::kAverage: return CombineRestitution<RCombineMode::kAverage>;
    case RCombineMode::kGeometric: return CombineRestitution<RCombineMode::kGeometric>;
    case RCombineMode::kMin: break;
  }
  return CombineRestitution<RCombineMode::kMin>;
}

JPH::Vec3 J(const RVec3& v) {
  return JPH::Vec3(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
}
JPH::Quat J(const RQuat& q) {
  return JPH::Quat(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()),
                   static_cast<float>(q.w())).Normalized();
}

// The body's shape in its body frame B. Boxes, spheres, capsules and cylinders whose frame is
// B are shared by size; "" or the reason the shape cannot be mapped.
std::string MakeShape(const RRigidBody& b, std::map<std::array<double, 4>, JPH::RefConst<JPH::Shape>>& shared,
                      JPH::RefConst<JPH::Shape>& out) {
  const RShape& s = b.Shape();
  const bool offset = b.ShapeOffset_B().norm() > 0 ||
                      b.ShapeRotation_BS().angularDistance(RQuat::Identity()) > 0;
  JPH::ShapeSettings::ShapeResult made;
  if (s.type == RShapeType::kHull) {
    // The points taken into B, as BulletWorld.h does: the hull's centre of mass is then B's
    // origin (up to rounding of Jolt's own volume integral).
    JPH::Array<JPH::Vec3> points;
    points.reserve(s.points.size());
    for (const RVec3& p_S : s.points) points.push_back(J(RVec3(b.ShapeOffset_B() + b.ShapeRotation_BS() * p_S)));
    made = JPH::ConvexHullShapeSettings(points).Create();
  } else if (s.type == RShapeType::kMesh || s.type == RShapeType::kCompound) {
    return s.type == RShapeType::kMesh ? "mesh shapes are not mapped to Jolt"
                                       : "compound shapes are not mapped to Jolt";
  } else {
    const double kind = static_cast<double>(s.type);
    const std::array<double, 4> key = s.type == RShapeType::kBox
        ? std::array<double, 4>{kind, s.halfExtents.x(), s.halfExtents.y(), s.halfExtents.z()}
        : std::array<double, 4>{kind, s.radius, s.halfHeight, 0};
    if (!offset) {
      if (auto it = shared.find(key); it != shared.end()) {
        out = it->second;
        return "";
      }
    }
    const float r = static_cast<float>(s.radius), h = static_cast<float>(s.halfHeight);
    if (s.type == RShapeType::kBox) {
      made = JPH::BoxShapeSettings(J(s.halfExtents)).Create();
    } else if (s.type == RShapeType::kSphere) {
      made = JPH::SphereShapeSettings(r).Create();
    } else if (s.type == RShapeType::kCapsule) {  // both along y, h = half the segment
      made = JPH::CapsuleShapeSettings(h, r).Create();
    } else {  // cylinder, both along y; Jolt's rounding no larger than the cylinder allows
      made = JPH::CylinderShapeSettings(h, r, std::min(JPH::cDefaultConvexRadius, 0.5f * std::min(h, r))).Create();
    }
    if (made.IsValid() && offset) {  // not expected (their frame is B), but correct
      made = JPH::RotatedTranslatedShapeSettings(J(b.ShapeOffset_B()), J(b.ShapeRotation_BS()), made.Get()).Create();
    } else if (made.IsValid()) {
      shared[key] = made.Get();
    }
  }
  if (made.HasError()) return std::string("Jolt could not make the shape: ") + made.GetError().c_str();
  out = made.Get();
  return "";
}

// One Jolt world for one run: the system, its allocator and its job system.
struct JoltWorld {
  BroadLayers broadLayers;
  ObjectVsBroad objectVsBroad;
  ObjectPairs pairs;
  JPH::PhysicsSystem system;
  // Jolt's step takes its scratch memory from here; past 64 MB (the largest scenes) it falls
  // back to malloc instead of failing.
  JPH::TempAllocatorImplWithMallocFallback temp{64 * 1024 * 1024};
  std::unique_ptr<JPH::JobSystemThreadPool> jobs;
  std::vector<JPH::BodyID> ids;  // in scene order
};

void RegisterJolt() {
  static const bool registered = [] {
    JPH::RegisterDefaultAllocator();
    JPH::Factory::sInstance = new JPH::Factory();
    JPH::RegisterTypes();
    return true;
  }();
  (void)registered;
}

// Builds the world; "" or the reason it cannot be built.
std::string Build(const RScene& scene, const std::vector<RRigidBody>& reference, int threads, JoltWorld& w) {
  for (const std::vector<std::size_t>& ignored : scene.ignore) {
    if (!ignored.empty()) return "the scene's ignore lists are not mapped to Jolt";
  }
  if (!scene.joints.empty()) return "joints are not mapped to Jolt";
  const JPH::uint n = static_cast<JPH::uint>(reference.size());
  // Room for every pair of boxes that overlap and every contact of a settled pile (Jolt's
  // PerformanceTest gives 65536 pairs and 20480 contacts to 10240 bodies); a full cache
  // drops contacts, which Update reports and RunJolt turns into an error.
  const JPH::uint maxPairs = std::max<JPH::uint>(65536, 16 * n);
  const JPH::uint maxContacts = std::max<JPH::uint>(20480, 8 * n);
  w.system.Init(n, 0, maxPairs, maxContacts, w.broadLayers, w.objectVsBroad, w.pairs);
  const RWorldSettings& settings = scene.settings;
  const bool sleeping = settings.shortcuts.sleeping;
  JPH::PhysicsSettings physics;
  physics.mNumVelocitySteps = static_cast<JPH::uint>(settings.solverIterations);
  physics.mMinVelocityForRestitution = static_cast<float>(settings.restitutionThreshold);
  physics.mAllowSleeping = sleeping;
  w.system.SetPhysicsSettings(physics);
  w.system.SetGravity(J(settings.gravity_W));
  w.system.SetCombineFriction(FrictionRule(settings.frictionCombine));
  w.system.SetCombineRestitution(RestitutionRule(settings.restitutionCombine));

  std::map<std::array<double, 4>, JPH::RefConst<JPH::Shape>> shared;
  JPH::BodyInterface& bodies = w.system.GetBodyInterfaceNoLock();
  std::vector<JPH::BodyID> dynamic, fixed;
  for (const RRigidBody& b : reference) {
    JPH::RefConst<JPH::Shape> shape;
    if (std::string error = MakeShape(b, shared, shape); !error.empty()) return error;
    const JPH::EMotionType motion = b.IsStatic()      ? JPH::EMotionType::Static
                                    : b.IsKinematic() ? JPH::EMotionType::Kinematic
                                                      : JPH::EMotionType::Dynamic;
    const JPH::RVec3 position(b.Position_W().x(), b.Position_W().y(), b.Position_W().z());
    JPH::BodyCreationSettings body(shape, position, J(b.Orientation_WB()), motion,
                                   b.IsStatic() ? Layers::kStatic : Layers::kMoving);
    if (motion == JPH::EMotionType::Dynamic) {
      body.mOverrideMassProperties = JPH::EOverrideMassProperties::MassAndInertiaProvided;
      body.mMassPropertiesOverride.mMass = static_cast<float>(b.Mass());
      body.mMassPropertiesOverride.mInertia = JPH::Mat44::sScale(J(b.Inertia_B()));
    }
    if (motion != JPH::EMotionType::Static) {
      body.mLinearVelocity = J(b.Velocity_W());
      body.mAngularVelocity = J(b.AngularVelocity_W());
    }
    body.mFriction = static_cast<float>(b.Friction());
    body.mRestitution = static_cast<float>(b.Restitution());
    body.mLinearDamping = 0;
    body.mAngularDamping = 0;
    body.mAllowSleeping = sleeping;
    body.mIsSensor = !b.Responds();
    JPH::Body* created = bodies.CreateBody(body);
    if (!created) return "Jolt ran out of bodies";
    w.ids.push_back(created->GetID());
    (motion == JPH::EMotionType::Static ? fixed : dynamic).push_back(created->GetID());
  }
  // Added in two batches (static, then the rest), then the broad phase's trees rebuilt once.
  for (std::vector<JPH::BodyID>* batch : {&fixed, &dynamic}) {
    if (batch->empty()) continue;
    const int count = static_cast<int>(batch->size());
    const JPH::EActivation activation =
        batch == &fixed ? JPH::EActivation::DontActivate : JPH::EActivation::Activate;
    JPH::BodyInterface::AddState state = bodies.AddBodiesPrepare(batch->data(), count);
    bodies.AddBodiesFinalize(batch->data(), count, state, activation);
  }
  w.system.OptimizeBroadPhase();
  // Jolt's convention: the thread that calls Update works too, so N threads are N - 1
  // workers; -1 asks for Jolt's default (one per hardware thread but the caller's).
  w.jobs = std::make_unique<JPH::JobSystemThreadPool>(JPH::cMaxPhysicsJobs, JPH::cMaxPhysicsBarriers,
                                                      threads > 0 ? threads - 1 : -1);
  return "";
}

WorldSummary Summarize(const JoltWorld& w, const std::vector<RRigidBody>& reference) {
  WorldSummary s;
  s.bodies = w.system.GetNumBodies();
  const JPH::BodyLockInterfaceNoLock& lock = w.system.GetBodyLockInterfaceNoLock();
  for (std::size_t i = 0; i < w.ids.size(); ++i) {
    const JPH::Body* body = lock.TryGetBody(w.ids[i]);
    if (!body || !body->IsDynamic()) continue;
    const double y = body->GetCenterOfMassPosition().GetY();
    s.minHeight = s.dynamic == 0 ? y : std::min(s.minHeight, y);
    s.meanHeight += y;
    ++s.dynamic;
    s.awake += body->IsActive() ? 1 : 0;
    // REngine's mass and moments (given to Jolt), the spin in the body frame.
    const JPH::Vec3 v = body->GetLinearVelocity();
    const JPH::Vec3 w_B = body->GetRotation().Conjugated() * body->GetAngularVelocity();
    const RVec3& inertia = reference[i].Inertia_B();
    s.kineticEnergy += 0.5 * reference[i].Mass() * static_cast<double>(v.LengthSq()) +
                       0.5 * (inertia.x() * w_B.GetX() * w_B.GetX() + inertia.y() * w_B.GetY() * w_B.GetY() +
                              inertia.z() * w_B.GetZ() * w_B.GetZ());
  }
  if (s.dynamic) s.meanHeight /= static_cast<double>(s.dynamic);
  return s;
}

}  // namespace

std::string JoltVersion() {
  return std::to_string(JPH_VERSION_MAJOR) + "." + std::to_string(JPH_VERSION_MINOR) + "." +
         std::to_string(JPH_VERSION_PATCH);
}

JoltRun RunJolt(const RScene& scene, int threads) {
  RegisterJolt();
  const std::vector<RRigidBody> reference = CreateBodies(scene);
  auto world = std::make_unique<JoltWorld>();
  JoltRun run;
  run.error = Build(scene, reference, threads, *world);
  if (!run.error.empty()) return run;
  const float dt = static_cast<float>(scene.dt);
  JPH::EPhysicsUpdateError errors = JPH::EPhysicsUpdateError::None;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::uint64_t s = 0; s < scene.steps; ++s) {
    errors |= world->system.Update(dt, 1, &world->temp, world->jobs.get());
  }
  const auto t1 = std::chrono::steady_clock::now();
  run.ran = true;
  run.ms = std::chrono::duration<double, std::milli>(t1 - t0).count() / static_cast<double>(scene.steps);
  run.summary = Summarize(*world, reference);
  if (errors != JPH::EPhysicsUpdateError::None) {
    run.error = "Jolt dropped contacts (its caches were full: EPhysicsUpdateError " +
                std::to_string(static_cast<unsigned>(errors)) + ")";
  }
  return run;
}

}  // namespace rbench
