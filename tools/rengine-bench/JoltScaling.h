// rengine-bench --scaling's Jolt series: a scene file's bodies as a Jolt Physics world, timed
// like REngine's and Bullet's (scaling.cpp). This header names no Jolt type, so scaling.cpp
// includes it with or without Jolt; JoltScaling.cpp, which does, is compiled only when CMake
// is given -DREngine_JOLT_DIR=<install prefix of Jolt 5.5 built with DOUBLE_PRECISION=ON>
// (tools/CMakeLists.txt defines RENGINE_HAVE_JOLT then).
#pragma once

#include <REnginePhysics/RScene.h>

#include <algorithm>
#include <cstddef>
#include <string>

namespace rbench {

// What a world holds after a run, printed beside REngine's so that a scene Jolt does not
// simulate as REngine does (bodies through the ground, a pile that falls apart, everything
// asleep from the first step) shows in the output. Dynamic bodies only.
struct WorldSummary {
  std::size_t bodies = 0;   // every body, static ones included
  std::size_t dynamic = 0;
  std::size_t awake = 0;    // dynamic bodies not asleep
  double meanHeight = 0;    // mean y of the centres of mass, m
  double minHeight = 0;     // lowest centre of mass, m
  double kineticEnergy = 0; // sum of 1/2 m v^2 + 1/2 w.I.w, J
};

// REngine's summary of the same quantities (inline: scaling.cpp uses it without Jolt too).
inline WorldSummary Summarize(const REngine::RSceneWorld& world) {
  WorldSummary s;
  s.bodies = world.Live().size();
  for (REngine::RBodyHandle handle : world.Live()) {
    const REngine::RRigidBody& b = world.Bodies()[handle];
    if (b.IsStatic() || b.IsKinematic()) continue;
    const double y = b.Position_W().y();
    s.minHeight = s.dynamic == 0 ? y : std::min(s.minHeight, y);
    s.meanHeight += y;
    ++s.dynamic;
    s.awake += b.IsSleeping() ? 0 : 1;
    const REngine::RVec3 w = b.Orientation_WB().conjugate() * b.AngularVelocity_W();  // body frame
    s.kineticEnergy += 0.5 * b.Mass() * b.Velocity_W().squaredNorm() +
                       0.5 * w.dot(b.Inertia_B().cwiseProduct(w));
  }
  if (s.dynamic) s.meanHeight /= static_cast<double>(s.dynamic);
  return s;
}

struct JoltRun {
  double ms = 0;         // per step, the step loop alone
  WorldSummary summary;  // after the last step
  // Set when the run did not happen (a shape or setting this series does not map: ran is
  // false) or when Jolt dropped contacts (its caches full: the figure is for less work).
  std::string error;
  bool ran = false;
};

// "5.5.0", from the headers the series was built with.
std::string JoltVersion();

// Builds the scene's world in Jolt (not timed), then times scene.steps calls of
// PhysicsSystem::Update(scene.dt, 1 collision step) on a JobSystemThreadPool of threads - 1
// workers (the calling thread works too, Jolt's own convention; 0: Jolt's default, one
// worker per hardware thread but the caller's).
JoltRun RunJolt(const REngine::RScene& scene, int threads);

}  // namespace rbench
