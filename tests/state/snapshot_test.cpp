// Rollback snapshots (RSnapshot.h): a world saved every frame, rolled back a few frames again
// and again and simulated forward, passes through exactly the states of a run that never
// rolled back (every body's public state, the contact events and the sleepers, bit for
// bit, after every step), across removals, spawns, a parked body enabled, sleepers, joints,
// kinematic bodies, a body tumbling on the exact rotation's cache and forces pending at the
// save; in delta mode too, on one and two threads. A snapshot from another world or
// integrator is refused with the world unchanged.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RSnapshot.h>

#include "support/BodiesHash.h"
#include "support/CountingNew.h"  // this binary's operator new counts allocations
#include "support/TestBodies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>


using namespace REngine;
using namespace REngine::test;

// CountingNew.h counts plain allocations; the bodies' storage is over-aligned (RBodyCore is
// alignas(64)), so the aligned forms are counted here too.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t n, std::align_val_t a) {
  if (g_countAllocations) ++g_allocations;
  const std::size_t align = static_cast<std::size_t>(a);
  if (void* p = std::aligned_alloc(align, ((n ? n : 1) + align - 1) / align * align)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr int kEnd = 420;

// BodiesHash and the step's events and sleepers: equal for bit-identical worlds after a step.
std::uint64_t WorldHash(const RIntegrator& integrator, const RBodies& bodies) {
  std::uint64_t h = BodiesHash(bodies);
  for (const RContactEvent& e : integrator.Events()) {
    Fold(h, e.type), Fold(h, e.handleA.index), Fold(h, e.handleB.index);
    FoldVec(h, e.point_W), Fold(h, e.normalImpulse);
  }
  Fold(h, integrator.PairStats().sleepingBodies);
  Fold(h, integrator.StepCount());
  return h;
}

// A pile that sleeps, a meteor that wakes it, a kinematic turntable with a crate, a satellite
// of three distinct moments tumbling (the rotation cache), a pendulum on a ball joint, a
// locked roller, a dragged box; a removal, a spawn, a parked body enabled, an impulse, a
// thrust (a force pending when the frame is saved), a joint added and one removed.
struct Game {
  RBodyHandle crate, doomed, lifted, parked, late, bob, satellite;
  RJointHandle rope;

  void Build(RBodies& bodies) {
    bodies.Add(GroundDef());
    for (int layer = 0; layer < 2; ++layer) {
      for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
          const RBodyHandle h = bodies.Add(BoxDef(RVec3::Constant(0.5)).Mass(1).Restitution(0.1)
                                     .At(RVec3(-6 + 1.02 * i + 0.1 * layer, 0.6 + 1.1 * layer, 1.02 * k + 0.05 * layer)));
          if (layer == 1 && i == 2 && k == 2) lifted = h;
        }
      }
    }
    bodies.Add(SphereDef(0.4).Mass(3).Restitution(0.3).At(RVec3(-4.9, 60, 1.1)).Named("meteor"));
    bodies.Add(BoxDef(RVec3(2, 0.25, 2)).Kinematic().At(RVec3(6, 0.25, 0)).Spinning(RVec3(0, 1, 0)));
    crate = bodies.Add(BoxDef(RVec3::Constant(0.3)).Mass(1).Friction(0.8).At(RVec3(7, 0.8, 0)));
    satellite = bodies.Add(BoxDef(RVec3(0.2, 0.5, 0.9)).Mass(2).GravityScale(0).At(RVec3(0, 20, 0))
                               .Spinning(RVec3(0.01, 3, 0.02)));
    bodies.Add(SphereDef(0.5).Mass(1).At(RVec3(0, 0.5, -4)).Moving(RVec3(2, 0, 0)).LockLinear(false, false, true)
                   .LockAngular(true, true, false));
    bodies.Add(BoxDef(RVec3::Constant(0.4)).Mass(1).Damping(0.3, 0.2).At(RVec3(2, 3, 4)).Moving(RVec3(-1, 4, 0))
                   .Spinning(RVec3(1, 2, 3)));
    doomed = bodies.Add(BoxDef(RVec3::Constant(0.5)).Mass(1).At(RVec3(0, 0.5, 6)));
    parked = bodies.Add(SphereDef(0.3).Mass(1).At(RVec3(3, 5, -3)));
    bodies.Disable(parked);
    bob = bodies.Add(SphereDef(0.3).Mass(2).At(RVec3(10, 6, 0)));
    RJointDef j;
    j.a = bob, j.anchor_W = RVec3(8.5, 7, 0);
    rope = bodies.AddJoint(j);
  }

  // What the game does after step s (before the frame is saved).
  void Script(RBodies& bodies, int s) {
    if (s == 40) bodies.Remove(doomed);
    if (s % 7 == 0 && s < 300) bodies[crate].AddForce_W(RVec3(0, 30, 0));  // pending at the save
    if (s == 150) bodies[crate].AddImpulse_W(RVec3(0.5, 2, 0));
    if (s == 200) late = bodies.Add(SphereDef(0.35).Mass(1).At(RVec3(-5, 6, 1.2)));
    if (s == 230) bodies.Enable(parked);
    if (s == 260) bodies.RemoveJoint(rope);
    if (s == 300) bodies.Remove(lifted);
    if (s == 330) bodies[satellite].SetGravityScale(0.5);  // a definition edit
  }
};

// The run that never rolls back, on one thread: every rolled-back run, on any thread count,
// must pass through its states (the step is bit-identical for any thread count). Computed
// once for the binary.
const std::vector<std::uint64_t>& Reference() {
  static const std::vector<std::uint64_t> hashes = [] {
    Game game;
    RBodies bodies;
    game.Build(bodies);
    RWorldSettings settings = EarthGravity();
    settings.threads = 1;
    RIntegrator integrator(settings);
    std::vector<std::uint64_t> out;
    for (int s = 1; s <= kEnd; ++s) {
      integrator.Update(bodies, kDt);
      game.Script(bodies, s);
      out.push_back(WorldHash(integrator, bodies));
    }
    return out;
  }();
  return hashes;
}

// Every `every` steps the world goes back `depth` frames and simulates them again; every
// step, first or again, must give the reference's hash (run on one thread).
void ExpectRollbacksReplay(int threads, std::size_t keyInterval, int every, int depth) {
  const std::vector<std::uint64_t>& reference = Reference();
  Game game;
  RBodies bodies;
  game.Build(bodies);
  RWorldSettings settings = EarthGravity();
  settings.threads = threads;
  RIntegrator integrator(settings);
  RSnapshotRing ring(16, keyInterval);
  ring.Save(integrator, bodies);
  int rollbacks = 0;
  std::size_t mostAsleep = 0;
  for (int s = 1; s <= kEnd; ++s) {
    integrator.Update(bodies, kDt);
    game.Script(bodies, s);
    mostAsleep = std::max(mostAsleep, integrator.PairStats().sleepingBodies);
    ASSERT_EQ(WorldHash(integrator, bodies), reference[s - 1]) << "step " << s;
    ring.Save(integrator, bodies);
    if (s % every == 0 && s >= depth) {
      ring.Restore(integrator, bodies, static_cast<std::uint64_t>(s - depth));
      ++rollbacks;
      ASSERT_EQ(integrator.StepCount(), static_cast<std::uint64_t>(s - depth));
      for (int r = s - depth + 1; r <= s; ++r) {
        integrator.Update(bodies, kDt);
        game.Script(bodies, r);
        ASSERT_EQ(WorldHash(integrator, bodies), reference[r - 1]) << "step " << r << " simulated again after a "
                                                                   << "rollback from " << s;
        ring.Save(integrator, bodies);
      }
    }
  }
  EXPECT_GT(rollbacks, 40);
  // The scenario did what it is for: frames rolled back over a sleeping pile.
  EXPECT_GT(mostAsleep, 10u);
}

TEST(Snapshot, RollbacksReplayTheUninterruptedRunOnOneThread) { ExpectRollbacksReplay(1, 1, 5, 8); }
TEST(Snapshot, RollbacksReplayTheUninterruptedRunOnTwoThreads) { ExpectRollbacksReplay(2, 1, 4, 8); }
TEST(Snapshot, DeltaSnapshotsReplayTheUninterruptedRun) { ExpectRollbacksReplay(1, 4, 4, 7); }
TEST(Snapshot, OneFrameRollbacksEveryStep) { ExpectRollbacksReplay(1, 1, 1, 1); }

// A snapshot restored into another container of the same integrator (the game's world
// rebuilt) copies its layout in whole and continues as the world it came from.
TEST(Snapshot, RestoreIntoAnotherContainerCopiesTheLayout) {
  const std::vector<std::uint64_t>& reference = Reference();
  Game game;
  RBodies bodies;
  game.Build(bodies);
  RIntegrator integrator(EarthGravity());
  RSnapshot saved;
  for (int s = 1; s <= 250; ++s) {
    integrator.Update(bodies, kDt);
    game.Script(bodies, s);
    if (s == 210) SaveSnapshot(integrator, bodies, saved);
  }
  RBodies other;  // empty
  RestoreSnapshot(integrator, other, saved);
  Game replay = game;
  for (int s = 211; s <= kEnd; ++s) {
    integrator.Update(other, kDt);
    replay.Script(other, s);
    ASSERT_EQ(WorldHash(integrator, other), reference[s - 1]) << "step " << s;
  }
}

// A body's definition edited after the save (and a spawn) is put back by the restore.
TEST(Snapshot, DefinitionEditsAfterTheSaveAreUndone) {
  Game game;
  RBodies bodies;
  game.Build(bodies);
  RIntegrator integrator(EarthGravity());
  for (int s = 1; s <= 20; ++s) integrator.Update(bodies, kDt), game.Script(bodies, s);
  RSnapshot saved;
  SaveSnapshot(integrator, bodies, saved);
  const std::uint64_t atSave = BodiesHash(bodies);
  RBodies copy = bodies;
  RIntegrator copyIntegrator = integrator;  // the same world, stepped apart as the reference
  bodies[game.satellite].SetGravityScale(1);
  bodies[game.crate].SetCollisionFilter(2, 0);
  bodies.Add(SphereDef(1).Mass(1).At(RVec3(0, 40, 0)));
  integrator.Update(bodies, kDt);
  RestoreSnapshot(integrator, bodies, saved);
  EXPECT_EQ(BodiesHash(bodies), atSave);
  EXPECT_EQ(bodies[game.satellite].GravityScale(), 0.0);
  EXPECT_EQ(bodies[game.crate].Category(), 1u);
  for (int s = 21; s <= 80; ++s) {
    integrator.Update(bodies, kDt), game.Script(bodies, s);
    copyIntegrator.Update(copy, kDt), game.Script(copy, s);
    ASSERT_EQ(WorldHash(integrator, bodies), WorldHash(copyIntegrator, copy)) << "step " << s;
  }
}

// What a snapshot of a field of free bodies costs: one record a body, the layout shared.
TEST(Snapshot, AFrameHoldsOnlyWhatAStepChanges) {
  RBodies bodies;
  for (int k = 0; k < 200; ++k) {
    bodies.Add(BoxDef(RVec3(0.2 + 0.01 * (k % 7), 0.5, 0.9)).Mass(2).At(RVec3(3.0 * k, 0, 0)).Spinning(RVec3(0.1, 2, 0.3)));
  }
  RIntegrator integrator;  // no gravity
  RSnapshot a, b;
  integrator.Update(bodies, kDt);
  SaveSnapshot(integrator, bodies, a);
  integrator.Update(bodies, kDt);
  RSnapshotOptions share;
  share.shareWith = &a;
  SaveSnapshot(integrator, bodies, b, share);
  // 120 bytes of pose, velocities and sleeping, 32 of rotation phase, and the snapshot's own
  // fixed part spread over the bodies.
  EXPECT_LE(b.FrameBytes(), 200u * (120 + 32) + 1024);
  EXPECT_EQ(b.SharedBytes(), a.SharedBytes()) << "the layout and the polhodes are shared";
  EXPECT_EQ(b.StoredBodies(), 200u);
}

// Once a ring's buffers have grown, a frame's save and a restore into the same container
// allocate nothing: the layout and polhodes are shared, the records written in place.
TEST(Snapshot, SavingAndRestoringAFrameAllocatesNothingOnceGrown) {
  RBodies bodies;
  for (int k = 0; k < 100; ++k) {
    bodies.Add(BoxDef(RVec3(0.2, 0.5, 0.9)).Mass(2).At(RVec3(3.0 * k, 0, 0)).Spinning(RVec3(0.1, 2, 0.3)));
  }
  RWorldSettings settings;
  settings.threads = 1;
  RIntegrator integrator(settings);
  RSnapshotRing ring(4);
  for (int s = 0; s < 12; ++s) integrator.Update(bodies, kDt), ring.Save(integrator, bodies);
  ring.Restore(integrator, bodies, 10);
  integrator.Update(bodies, kDt), ring.Save(integrator, bodies);
  g_allocations = 0;
  g_countAllocations = true;
  ring.Save(integrator, bodies);  // frame 11 again, over itself
  ring.Restore(integrator, bodies, 10);
  ring.Save(integrator, bodies);
  g_countAllocations = false;
  EXPECT_EQ(g_allocations.load(), 0);
}

// Refused: nothing saved, another world's tag, another integrator's snapshot; the world
// is left as it was.
TEST(Snapshot, SnapshotsThatCannotApplyAreRefused) {
  Game game;
  RBodies bodies;
  game.Build(bodies);
  RIntegrator integrator(EarthGravity());
  for (int s = 1; s <= 10; ++s) integrator.Update(bodies, kDt);
  RSnapshot saved;
  RSnapshotOptions tagged;
  tagged.worldTag = 7;
  SaveSnapshot(integrator, bodies, saved, tagged);
  integrator.Update(bodies, kDt);
  const std::uint64_t before = WorldHash(integrator, bodies);
  auto refused = [&](RIntegrator& i, const RSnapshot& s, std::uint64_t tag) {
    try {
      RestoreSnapshot(i, bodies, s, tag);
    } catch (const RStateError& e) {
      return e.Field();
    }
    return std::string("(restored)");
  };
  EXPECT_EQ(refused(integrator, RSnapshot(), 7), "snapshot");
  EXPECT_EQ(refused(integrator, saved, 0), "snapshot.world_tag");
  RIntegrator stranger(EarthGravity());
  EXPECT_EQ(refused(stranger, saved, 7), "snapshot.integrator");
  EXPECT_EQ(WorldHash(integrator, bodies), before) << "a refused restore changes nothing";
  RestoreSnapshot(integrator, bodies, saved, 7);
  EXPECT_EQ(integrator.StepCount(), 10u);
  RSnapshotRing ring(4);
  EXPECT_THROW(ring.At(3), RStateError);
  EXPECT_THROW(RSnapshotRing(0), RStateError);
}

}  // namespace
