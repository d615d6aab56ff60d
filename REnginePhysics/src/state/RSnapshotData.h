// Private to REnginePhysics: what a rollback snapshot (RSnapshot.h) holds. Frame data are
// plain records in arrays that keep their capacity (a save is a pass over the bodies writing
// one 120-byte record each, no per-field calls, no allocation once grown); what a step never
// changes lives in immutable parts shared through std::shared_ptr with the snapshots before
// and after, compared by version numbers, never by content.
#pragma once

#include <REnginePhysics/RSnapshot.h>

#include "world/RWorldStep.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace REngine {

// One body's frame data: the state a step writes (RBodyCore's pose, velocities, sleeping),
// doubles as the body holds them. 120 bytes, no padding.
struct RBodyFrame {
  double x[3];       // m_x_W, m
  double q[4];       // m_q_WB (w, x, y, z)
  double v[3];       // m_v_W, m/s
  double w[3];       // m_w_B, rad/s
  double restTime;   // s
  std::uint32_t sleepIsland;
  std::uint32_t flags;  // kFrame* below
};
static_assert(sizeof(RBodyFrame) == 120, "RBodyFrame is packed");

// RBodyFrame::flags.
inline constexpr std::uint32_t kFrameSleeping = 1u << 0;
inline constexpr std::uint32_t kFrameStaticMoved = 1u << 1;
inline constexpr std::uint32_t kFrameWakeFromSet = 1u << 2;
inline constexpr std::uint32_t kFrameSlotDense = 1u << 3;    // m_slot is its dense index
inline constexpr std::uint32_t kFrameSlotNone = 1u << 4;     // m_slot is kNoIsland (never stepped)
inline constexpr std::uint32_t kFrameOwnWorld = 1u << 5;     // m_slotWorld is the saving integrator's id
inline constexpr std::uint32_t kFrameZeroWorld = 1u << 6;    // m_slotWorld is 0
inline constexpr std::uint32_t kFrameExtra = 1u << 7;        // its RBodyExtra holds slot, world, world spin, accumulators
inline constexpr std::uint32_t kFrameRotation = 1u << 8;     // a valid exact-rotation cache: an RRotationFrame

// What few bodies need beyond RBodyFrame: accumulators the game set before the save, the
// world spin of a kinematic or locked body, a slot that is not its dense index, another
// integrator's id, a rotation cache keyed to another spin than the body's (an impulse after
// the rotation's flow).
struct RBodyExtra {
  std::uint32_t body = 0, slot = 0;
  std::uint64_t slotWorld = 0;
  double w_W[3], force[3], torque[3], linearImpulse[3], angularImpulse[3], cacheW_B[3];
};

// The exact rotation's phase, which each step advances (RFreeRotationCore::m_phase); the
// rest of the cache is the body's RRotationConstants, or recomputed bit for bit (m_align0
// is QuatFromTo of the cached spin, m_cacheW_B the body's spin unless its extra says).
struct RRotationFrame {
  double sn, cn, dn;
  std::uint32_t body, pad = 0;
};
static_assert(sizeof(RRotationFrame) == 32, "RRotationFrame is packed");

// The exact rotation's constants for one polhode (RFreeRotationCore minus the phase): they
// change only when the body's angular momentum does. Compared field by field (SameAs), never
// with memcmp: the struct's padding is not set.
struct RRotationConstants {
  RFreeRotationCore core;
  static RRotationConstants Of(const RFreeRotationCore& f);
  bool SameAs(const RFreeRotationCore& f) const;
};
// Per dense body (null: no valid cache), shared while no body's polhode changes.
using RRotationTable = std::vector<std::shared_ptr<const RRotationConstants>>;

// The container as a step never changes it: its tables and bodies (definitions, shapes,
// mass properties) as they were copied, with the version numbers that say it is current.
struct RSnapshotLayout {
  std::uint64_t containerStamp = 0;           // RBodiesCore::m_definitionStamp
  std::vector<std::uint64_t> definitions;     // per dense body, RBodyCore::m_definition
  RBodiesCore::RBodySlots slots;
  std::size_t enabled = 0;
  RBodiesCore::RJointSlots jointSlots;
  std::vector<std::uint64_t> noCollide;
  std::size_t Bytes() const;
};

struct RSnapshotData {
  bool saved = false;
  std::uint64_t worldTag = 0, worldId = 0, stepCount = 0;
  std::shared_ptr<const RSnapshotLayout> layout;
  // Full: one record per dense body. Delta: records of the bodies `deltaBodies` lists; the
  // others are base's (a full snapshot's records, kept alive here).
  std::shared_ptr<std::vector<RBodyFrame>> frames;
  std::vector<std::uint32_t> deltaBodies;
  std::shared_ptr<const std::vector<RBodyFrame>> base;
  std::vector<RBodyExtra> extras;        // by body, ascending
  std::vector<RRotationFrame> rotations; // by body, ascending
  std::shared_ptr<const RRotationTable> rotationTable;
  // The integrator.
  RWorldSettings settings;
  std::uint64_t warmBodyCount = 0;
  RSleeping::RSaved sleep;
  std::optional<RNonFiniteBody> nonFinite;
  std::vector<RWarmStart> warm;
  std::vector<RManifoldMemory> manifolds;
  std::vector<RContactEventLog::RTouchingPair> touching;
  std::vector<RContactMaterials::RRemembered> materials;
  // The container's pending wakes and the joints (their impulses are warm starts).
  std::vector<std::uint32_t> wakeIslands;
  bool wakeAll = false;
  std::vector<RVec3> wakeBoxes;
  std::vector<RJoint> joints;

  std::size_t FrameBytes() const;
  std::size_t SharedBytes() const;
};

// Save and restore (RSnapshot.cpp, RSnapshotRestore.cpp), reaching the bodies, container and
// integrator through body/RBodyAccess.h.
struct RSnapshotAccess {
  static void Save(const RIntegrator& integrator, const RBodies& bodies, RSnapshot& out,
                   const RSnapshotOptions& options);
  static void Restore(RIntegrator& integrator, RBodies& bodies, const RSnapshot& snapshot, std::uint64_t worldTag);
  static RSnapshotData& Data(RSnapshot& s) { return *s.m_data; }
  static const RSnapshotData& Data(const RSnapshot& s) { return *s.m_data; }
};

}  // namespace REngine
