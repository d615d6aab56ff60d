// Rollback snapshots: the world saved every frame and restored in-process, so that a game
// predicting remote inputs can go back a few frames and simulate them again (GGPO-style
// rollback netcode). RWorldState.h's SaveState/LoadState are for files: self-contained,
// versioned, checked bytes. A snapshot is for the same process: it copies only what a step
// changes and shares the rest with the snapshot before it.
//
//   RSnapshotRing ring(16);                     // the last 16 frames
//   ring.Save(integrator, bodies);              // after every Update (frame = StepCount())
//   ...                                         // a late input for frame f arrives:
//   ring.Restore(integrator, bodies, f);        // back at frame f, bit for bit
//   ... re-simulate frames f+1 .. now with the corrected inputs, saving each again ...
//
// What a snapshot copies every frame (what a step changes): each body's pose, velocities,
// rest time, sleeping and island, its slot bookkeeping, its pending forces and impulses
// (only where non-zero), the exact rotation's phase (three distinct moments); the joints'
// impulses (warm starts); the integrator's step count, settings, warm starts, manifold memory
// (with block inverses), touching pairs (contact events), sleeping's bookkeeping and
// NonFinite(); the container's pending wakes. 120 bytes a body, 152 with a rotation phase.
//
// What it shares (std::shared_ptr, immutable) with the snapshot it was saved after, while
// unchanged: the container's layout (bodies' definitions, shapes, mass properties, filters,
// slot tables, joints' table) and the exact rotation's constants (each body's polhode: they
// change only when its angular momentum does). A layout is copied again after an Add, Remove,
// Enable, Disable, a joint's change, or a body's definition edit (SetCollisionFilter, drag,
// gravity scale, user data, an immovable body's SetShapePose, RBodies::IgnoreCollisions):
// each body and the container carry a version number those bump. Velocities, forces and a
// dynamic body's SetShapePose are frame data and never cost a layout.
//
// Restore puts back exactly what was saved: bodies spawned or removed since come and go
// (a removed body returns with its handle, shape and contact memory), sleepers sleep, and
// the same steps from there give the same bodies, contacts and events bit for bit, on any
// thread count. Restoring into the container the snapshot came from, unchanged in layout,
// writes the frame data in place and allocates nothing once buffers have grown; otherwise
// the layout is copied in whole (a body edited since: that body alone). A save allocates
// only when a body on the exact rotation's cache (three distinct moments) has changed its
// angular momentum since the frame it shares with: a new table of the polhodes (a pointer a
// body) and the changed bodies' constants.
//
// Refused (RStateError, the world left as it was): an empty snapshot, another world's (a
// worldTag other than the one it was saved under, or another RIntegrator than the one that
// saved it: its contact memory names that integrator's bodies), and a snapshot whose
// records do not match its layout.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RWorldState.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace REngine {

struct RSnapshotData;  // private to the engine (src/state/RSnapshotData.h)

class RSnapshot {
 public:
  RSnapshot();
  ~RSnapshot();
  RSnapshot(RSnapshot&&) noexcept;
  RSnapshot& operator=(RSnapshot&&) noexcept;
  RSnapshot(const RSnapshot&) = delete;             // a snapshot owns buffers it reuses;
  RSnapshot& operator=(const RSnapshot&) = delete;  // Save into another one instead

  bool Empty() const;
  // RIntegrator::StepCount() when saved (the frame).
  std::uint64_t StepCount() const;
  // Bytes of frame data this snapshot holds of its own (what a save writes), and of what it
  // shares with other snapshots (layout, rotation constants; counted once per snapshot that
  // holds them, so a ring's total is the sum of FrameBytes plus one SharedBytes).
  std::size_t FrameBytes() const;
  std::size_t SharedBytes() const;
  // Bodies whose frame data a delta snapshot holds (all of them for a full one).
  std::size_t StoredBodies() const;

 private:
  friend struct RSnapshotAccess;
  std::unique_ptr<RSnapshotData> m_data;
};

struct RSnapshotOptions {
  // The game's name for the world (as SaveState's): RestoreSnapshot refuses another.
  std::uint64_t worldTag = 0;
  // An earlier snapshot of this world (normally the last frame's): its layout and rotation
  // constants are shared where unchanged instead of copied. Null: `out`'s own earlier ones.
  const RSnapshot* shareWith = nullptr;
  // Delta mode: store only the bodies whose frame data differ bit for bit from this full
  // snapshot's (a key frame of a ring); the rest are read from its records, which this
  // snapshot keeps alive (a key frame saved over while deltas hold its records writes new
  // ones). Bodies added or removed since the key frame: a full save. Null: a full save.
  const RSnapshot* deltaFrom = nullptr;
};

// Saves the world between two Updates into `out`, reusing its buffers.
void SaveSnapshot(const RIntegrator& integrator, const RBodies& bodies, RSnapshot& out,
                  const RSnapshotOptions& options = {});
// Puts the world back as `snapshot` holds it (see the top of this file). Throws RStateError
// before changing anything when the snapshot cannot be applied.
void RestoreSnapshot(RIntegrator& integrator, RBodies& bodies, const RSnapshot& snapshot,
                     std::uint64_t worldTag = 0);

// The last `frames` snapshots of one world, by frame (StepCount). Each save shares with the
// one before it; with keyInterval > 1 every keyInterval-th frame is full and those between
// are deltas against it (less memory when most bodies rest; a restore reads two snapshots;
// a key frame's records are new memory while deltas of the frame it replaces still read them).
class RSnapshotRing {
 public:
  explicit RSnapshotRing(std::size_t frames, std::size_t keyInterval = 1, std::uint64_t worldTag = 0);
  // Saves the world's present frame (its StepCount) over the oldest.
  void Save(const RIntegrator& integrator, const RBodies& bodies);
  bool Has(std::uint64_t frame) const;
  const RSnapshot& At(std::uint64_t frame) const;  // RStateError when not held
  // Restores frame `frame` and forgets the frames after it (they are to be simulated again).
  void Restore(RIntegrator& integrator, RBodies& bodies, std::uint64_t frame);
  std::size_t Frames() const { return m_slots.size(); }
  // FrameBytes of every frame held plus each distinct shared part once.
  std::size_t TotalBytes() const;

 private:
  std::vector<RSnapshot> m_slots;
  std::vector<std::uint64_t> m_frame;
  std::vector<bool> m_held;
  std::size_t m_keyInterval;
  std::uint64_t m_worldTag;
  std::size_t m_last = 0;  // slot of the newest frame
  bool m_any = false;
};

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_SNAPSHOT(X) \
  X(RSnapshot) \
  X(RSnapshotOptions) \
  X(RSnapshotRing)
RENGINE_ABI_CHECK(kSnapshot, RENGINE_ABI_TYPES_SNAPSHOT)
