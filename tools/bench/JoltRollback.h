// Jolt Physics' side of bench_rollback: the same rocks as a JPH::PhysicsSystem (double
// precision, one thread: JobSystemSingleThreaded), saved and restored with
// PhysicsSystem::SaveState / RestoreState through a StateRecorderImpl per frame. Built only
// when CMake is given -DREngine_JOLT_DIR=<Jolt's install prefix> (found in tools/CMakeLists.txt).
#pragma once

#include <Jolt/Jolt.h>

#include <Jolt/Core/Factory.h>
#include <Jolt/Core/JobSystemSingleThreaded.h>
#include <Jolt/Core/StreamWrapper.h>
#include <Jolt/Core/TempAllocator.h>
#include <Jolt/Physics/Body/BodyCreationSettings.h>
#include <Jolt/Physics/Collision/Shape/ConvexHullShape.h>
#include <Jolt/Physics/PhysicsSystem.h>
#include <Jolt/Physics/StateRecorderImpl.h>
#include <Jolt/RegisterTypes.h>

#include <memory>
#include <vector>

namespace bench {

// One object layer and one broad-phase layer: every rock collides with every rock.
class JoltLayers final : public JPH::BroadPhaseLayerInterface {
 public:
  JPH::uint GetNumBroadPhaseLayers() const override { return 1; }
  JPH::BroadPhaseLayer GetBroadPhaseLayer(JPH::ObjectLayer) const override { return JPH::BroadPhaseLayer(0); }
#if defined(JPH_EXTERNAL_PROFILE) || defined(JPH_PROFILE_ENABLED)
  const char* GetBroadPhaseLayerName(JPH::BroadPhaseLayer) const override { return "rocks"; }
#endif
};
class JoltObjectVsBroad final : public JPH::ObjectVsBroadPhaseLayerFilter {
 public:
  bool ShouldCollide(JPH::ObjectLayer, JPH::BroadPhaseLayer) const override { return true; }
};
class JoltObjectPairs final : public JPH::ObjectLayerPairFilter {
 public:
  bool ShouldCollide(JPH::ObjectLayer, JPH::ObjectLayer) const override { return true; }
};

struct JoltRock {
  std::vector<JPH::Vec3> points;  // shape frame, m
  JPH::RVec3 position;
  JPH::Quat rotation;
  JPH::Vec3 velocity, spin;  // m/s, rad/s, world
  float density;             // kg/m^3
  float restitution;
};

class JoltWorld {
 public:
  explicit JoltWorld(const std::vector<JoltRock>& rocks) {
    static bool registered = [] {
      JPH::RegisterDefaultAllocator();
      JPH::Factory::sInstance = new JPH::Factory();
      JPH::RegisterTypes();
      return true;
    }();
    (void)registered;
    m_temp = std::make_unique<JPH::TempAllocatorImpl>(64 * 1024 * 1024);
    m_jobs = std::make_unique<JPH::JobSystemSingleThreaded>(JPH::cMaxPhysicsJobs);
    const JPH::uint n = static_cast<JPH::uint>(rocks.size());
    m_system.Init(n, 0, 4 * n + 1024, 8 * n + 1024, m_layers, m_objectVsBroad, m_pairs);
    m_system.SetGravity(JPH::Vec3::sZero());  // space, as REngine's field
    JPH::BodyInterface& bi = m_system.GetBodyInterface();
    for (const JoltRock& r : rocks) {
      JPH::ConvexHullShapeSettings hull(r.points.data(), static_cast<int>(r.points.size()));
      hull.SetDensity(r.density);
      JPH::BodyCreationSettings settings(hull.Create().Get(), r.position, r.rotation, JPH::EMotionType::Dynamic, 0);
      settings.mLinearVelocity = r.velocity;
      settings.mAngularVelocity = r.spin;
      settings.mRestitution = r.restitution;
      settings.mLinearDamping = 0, settings.mAngularDamping = 0;
      bi.CreateAndAddBody(settings, JPH::EActivation::Activate);
    }
    m_system.OptimizeBroadPhase();
  }

  void Step(float dt) { m_system.Update(dt, 1, m_temp.get(), m_jobs.get()); }
  // Into a recorder kept from frame to frame (cleared, its buffer reused as Jolt allows).
  void Save(JPH::StateRecorderImpl& out) const {
    out.Clear();
    m_system.SaveState(out);
  }
  bool Restore(JPH::StateRecorderImpl& in) {
    in.Rewind();
    return m_system.RestoreState(in);
  }
  JPH::PhysicsSystem& System() { return m_system; }

 private:
  JoltLayers m_layers;
  JoltObjectVsBroad m_objectVsBroad;
  JoltObjectPairs m_pairs;
  JPH::PhysicsSystem m_system;
  std::unique_ptr<JPH::TempAllocatorImpl> m_temp;
  std::unique_ptr<JPH::JobSystemSingleThreaded> m_jobs;
};

}  // namespace bench
