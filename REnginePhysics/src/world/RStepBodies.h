// Private to REnginePhysics: the bodies one step works on (RStepBodies), as every subsystem
// of the step reads them: contiguous storage, each body's stable identity, the container's
// departures to wake and its joints; and the prefetch the passes over them use.
#pragma once

#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RJoint.h>

#include "body/RBodyAccess.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace REngine {

// A pass over the bodies in storage order waits for each body's first lines: bodies are 19
// cache lines apart, and the hardware's stream prefetch stops at every page (a body in
// three or four). A pass asks for the lines it reads (the first `bytes` of the body) a
// couple of bodies ahead: the motion of a 30000-body cloud 16.8 -> 11.2 ms a step
// (medians of 5 interleaved runs). Only speed depends on it.
// The lines of [from, from + bytes) (bytes > 0), the last one too when the range is not
// line-aligned (a 48-byte box may straddle two).
inline void PrefetchBytes(const void* from, std::size_t bytes) {
  const char* p = static_cast<const char*>(from);
  for (std::size_t line = 0; line < bytes; line += 64) __builtin_prefetch(p + line);
  __builtin_prefetch(p + bytes - 1);
}
inline void PrefetchBody(const RBodyCore& b, std::size_t bytes) { PrefetchBytes(&b, bytes); }

// The bodies one step works on: contiguous storage and each body's stable identity. From
// an RBodies, its enabled range and handles; from a plain vector, identity by position
// (a body's handle is its index, generation 0).
struct RStepBodies {
  RRigidBody* data = nullptr;
  std::size_t count = 0;
  const RBodyHandle* handles = nullptr;       // per dense index
  const std::uint32_t* denseOfSlot = nullptr; // per slot: dense index (>= count: not stepped)
  std::size_t slotCount = 0;
  // A plain vector: identity is position, so a change of count forgets contact memory and
  // wakes everything, and a body found at another index wakes everything.
  bool byIndex = true;
  // An RBodies' departures since the last step: islands to wake, or all (read and cleared).
  std::vector<std::uint32_t>* wakeIslands = nullptr;
  bool* wakeAll = nullptr;
  std::vector<RVec3>* wakeBoxes = nullptr;  // static and kinematic departures' boxes
  // An RBodies' joints (a plain vector has none), and the pairs of slots joined by a joint
  // whose bodies do not collide (lower slot << 32 | higher, sorted).
  RJoint* joints = nullptr;
  std::size_t jointCount = 0;
  const std::uint64_t* noCollidePairs = nullptr;
  std::size_t noCollideCount = 0;
  // Whether two bodies (dense indices) are joined by a joint that keeps them from colliding
  // (joints/RJoints.cpp).
  bool JointedNoCollide(std::size_t i, std::size_t j) const;

  // A body's state (the engine's view, body/RBodyAccess.h); Body(i) is the game's view of it.
  RBodyCore& operator[](std::size_t i) const { return Core(data[i]); }
  RRigidBody& Body(std::size_t i) const { return data[i]; }
  std::size_t size() const { return count; }
  // A pass over the bodies' states, in storage order.
  struct RIterator {
    RRigidBody* p;
    RBodyCore& operator*() const { return Core(*p); }
    RIterator& operator++() { return ++p, *this; }
    bool operator!=(const RIterator& other) const { return p != other.p; }
  };
  RIterator begin() const { return {data}; }
  RIterator end() const { return {data + count}; }
  std::uint32_t Slot(std::size_t i) const { return handles[i].index; }
};

}  // namespace REngine
