// Save and load (RWorldState.h): a world saved after step 300 and loaded into a fresh
// integrator and a fresh container, built as the game builds them, goes on exactly as the
// world that never stopped: every body bit for bit after every step, the same contact
// events, the same bodies asleep, the same handles for bodies added later. And a state that
// is not one, is cut short, altered, from another world or holds an impossible value is
// refused by name, with the world left as it was.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RWorldState.h>

#include "state/RStateFormat.h"  // the header's layout and checksum: to forge bad states
#include "support/BodiesHash.h"
#include "support/TestBodies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;

// The events' fields, as BodiesHash the bodies'.
std::uint64_t EventHash(const std::vector<RContactEvent>& events) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const RContactEvent& e : events) {
    Fold(h, e.type), Fold(h, e.handleA.index), Fold(h, e.handleA.generation);
    Fold(h, e.handleB.index), Fold(h, e.handleB.generation);
    FoldVec(h, e.point_W), FoldVec(h, e.normal_W), Fold(h, e.normalImpulse), Fold(h, e.frictionImpulse);
  }
  return h;
}

// The game: a pile that comes to rest and sleeps, a sphere dropped from 130 m that reaches
// it after step 300 and wakes it, a kinematic turntable carrying a crate (never asleep), a
// satellite tumbling near its intermediate axis out of gravity (the exact rotation's cache),
// a sensor around the pile (events without response), a rolling locked sphere, a box with
// drag, a box removed at step 100 (its slot on the free list when saved) and a sleeping one
// taken off the pile after step 300, a parked
// (disabled) sphere enabled at step 450, a body spawned at step 400, an impulse at step 350.
constexpr int kSave = 300, kEnd = 600;

struct Game {
  RBodyHandle crate, doomed, lifted, parked, late;
  std::vector<RBodyHandle> initial;

  static RWorldSettings Settings(int threads) {
    RWorldSettings s = EarthGravity();
    s.threads = threads;
    return s;
  }

  void Build(RBodies& bodies) {
    initial.clear();
    auto add = [&](const RBodyDef& d) {
      initial.push_back(bodies.Add(d));
      return initial.back();
    };
    add(GroundDef());
    for (int layer = 0; layer < 2; ++layer) {
      for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
          if (layer == 1 && i == 2 && k == 2) lifted = RBodyHandle{static_cast<std::uint32_t>(initial.size()), 0};
          add(BoxDef(RVec3::Constant(0.5)).Mass(1).Restitution(0.1)
                  .At(RVec3(-6 + 1.02 * i + 0.1 * layer, 0.6 + 1.1 * layer, 1.02 * k + 0.05 * layer))
                  .Named("pile" + std::to_string(layer) + std::to_string(i) + std::to_string(k)));
        }
      }
    }
    add(SphereDef(0.4).Mass(3).Restitution(0.3).At(RVec3(-4.9, 130, 1.1)).Named("meteor"));
    add(BoxDef(RVec3(2, 0.25, 2)).Kinematic().At(RVec3(6, 0.25, 0)).Spinning(RVec3(0, 1, 0)).Named("turntable"));
    crate = add(BoxDef(RVec3::Constant(0.3)).Mass(1).Friction(0.8).At(RVec3(7, 0.8, 0)).Named("crate"));
    add(BoxDef(RVec3(0.2, 0.5, 0.9)).Mass(2).GravityScale(0).At(RVec3(0, 20, 0))
            .Spinning(RVec3(0.01, 3, 0.02)).Named("satellite"));
    RBodyDef sensor = BoxDef(RVec3(2.5, 1.5, 2.5)).Static().At(RVec3(-5, 1.4, 1)).Named("sensor");
    sensor.responds = false;
    add(sensor);
    add(SphereDef(0.5).Mass(1).At(RVec3(0, 0.5, -4)).Moving(RVec3(2, 0, 0)).LockLinear(false, false, true)
            .LockAngular(true, true, false).Named("roller"));
    add(BoxDef(RVec3::Constant(0.4)).Mass(1).Damping(0.3, 0.2).At(RVec3(2, 3, 4)).Moving(RVec3(-1, 4, 0))
            .Spinning(RVec3(1, 2, 3)).Named("dragged"));
    doomed = add(BoxDef(RVec3::Constant(0.5)).Mass(1).At(RVec3(0, 0.5, 6)).Named("doomed"));
    parked = add(SphereDef(0.3).Mass(1).At(RVec3(3, 5, -3)).Named("parked"));
    bodies.Disable(parked);
  }

  static BodyDef LateDef() { return SphereDef(0.35).Mass(1).At(RVec3(-5, 6, 1.2)).Named("late"); }
  // The shapes the game spawns from, for a load into a world that does not hold them yet.
  static RLoadOptions Spawnable() {
    RLoadOptions options;
    options.shapes.push_back(PrepareShape(LateDef().shape));
    return options;
  }

  // What the game does after step s.
  void Script(RBodies& bodies, int s) {
    if (s == 100) bodies.Remove(doomed);
    // A sleeping box taken off the pile just before the save: the state holds the island
    // that the next step must wake.
    if (s == kSave) bodies.Remove(lifted);
    if (s == 350) bodies[crate].AddImpulse_W(RVec3(0.5, 2, 0));
    if (s == 400) late = bodies.Add(LateDef());
    if (s == 450) bodies.Enable(parked);
  }
};

// A run's record, step by step from `first` on.
struct Record {
  std::vector<std::uint64_t> state, events, sleeping;
  void Observe(const RIntegrator& integrator, const RBodies& bodies) {
    state.push_back(BodiesHash(bodies));
    events.push_back(EventHash(integrator.Events()));
    sleeping.push_back(integrator.PairStats().sleepingBodies);
  }
};

void Play(RIntegrator& integrator, RBodies& bodies, Game& game, int from, int to, Record* record) {
  for (int s = from + 1; s <= to; ++s) {
    integrator.Update(bodies, kDt);
    game.Script(bodies, s);
    if (record) record->Observe(integrator, bodies);
  }
}

// The uninterrupted run, steps save + 1 to kEnd recorded; and the run saved after `save`,
// loaded into a fresh integrator and container built as the game builds them (at step 0:
// the removal, the parked body, the spawn and the step count all come from the state), run
// on by the game with the handles it held at the save.
void ExpectLoadContinues(int saveThreads, int loadThreads, int save = kSave) {
  Game gameA;
  RBodies a;
  gameA.Build(a);
  RIntegrator ia(Game::Settings(saveThreads));
  Play(ia, a, gameA, 0, save, nullptr);
  if (save == kSave) {
    // The scenario does what it is for at the save: contacts warm-started and reused, a pile
    // asleep beside bodies awake, events, a free slot.
    EXPECT_GT(ia.PairStats().warmStarted, 0u);
    EXPECT_GT(ia.PairStats().reusedManifolds, 0u);
    EXPECT_GT(ia.PairStats().sleepingBodies, 10u);
    EXPECT_LT(ia.PairStats().sleepingBodies, a.EnabledCount() - 5);
    EXPECT_FALSE(ia.Events().empty());
    EXPECT_FALSE(a.Contains(gameA.doomed));
  }
  const std::uint64_t sleepersAtSave = ia.PairStats().sleepingBodies;
  const std::vector<std::uint8_t> saved = SaveState(ia, a);
  Game gameB = gameA;  // the game's handles, kept across the load
  Record uninterrupted;
  Play(ia, a, gameA, save, kEnd, &uninterrupted);

  RBodies b;
  Game().Build(b);
  RIntegrator ib(Game::Settings(loadThreads));
  LoadState(ib, b, saved, Game::Spawnable());
  EXPECT_EQ(ib.StepCount(), static_cast<std::uint64_t>(save));
  EXPECT_EQ(ib.Settings().threads, loadThreads) << "the loading integrator keeps its threads";
  EXPECT_FALSE(b.Contains(gameB.doomed));
  EXPECT_EQ(SaveState(ib, b), saved) << "save, load, save: the same bytes";
  Record loaded;
  Play(ib, b, gameB, save, kEnd, &loaded);

  EXPECT_EQ(gameA.late, gameB.late) << "a body spawned after the load takes the handle it took before";
  EXPECT_EQ(gameB.late.generation, 1u) << "the removed body's slot, from the restored free list";
  ASSERT_EQ(uninterrupted.state.size(), loaded.state.size());
  for (std::size_t k = 0; k < loaded.state.size(); ++k) {
    const int step = save + 1 + static_cast<int>(k);
    ASSERT_EQ(uninterrupted.state[k], loaded.state[k]) << "bodies differ after step " << step;
    ASSERT_EQ(uninterrupted.events[k], loaded.events[k]) << "events differ in step " << step;
    ASSERT_EQ(uninterrupted.sleeping[k], loaded.sleeping[k]) << "sleepers differ after step " << step;
  }
  // Islands fell asleep after the load; saved at step 300, the box taken off the pile and
  // the meteor woke the pile first.
  const auto fewest = *std::min_element(loaded.sleeping.begin(), loaded.sleeping.end());
  if (save == kSave) {
    EXPECT_LT(fewest, sleepersAtSave) << "nothing woke after the load";
  }
  EXPECT_GT(loaded.sleeping.back(), fewest) << "nothing fell asleep after the load";
}

}  // namespace

TEST(State, LoadedWorldContinuesBitIdenticallyOnOneThread) { ExpectLoadContinues(1, 1); }
TEST(State, LoadedWorldContinuesBitIdenticallyOnTwoThreads) { ExpectLoadContinues(2, 2); }
TEST(State, StateSavedOnOneThreadContinuesOnTwo) { ExpectLoadContinues(1, 2); }
// Saved while the pile the meteor woke settles, its bodies' rest times counting towards the
// sleep they reach some 15 steps later (a load that lost them differs from then on), and
// after the spawn of step 400, whose shape the game passes (Game::Spawnable).
TEST(State, WorldSavedWhileItSettlesContinuesBitIdentically) { ExpectLoadContinues(1, 1, 470); }

// The comparison above is sensitive to what the state carries: the same load followed by
// ForgetContacts (no warm starts, no manifold memory, every sleeper woken) goes on
// differently. (Dropping the warm starts alone from the state was tried when this was
// written: the hashes part in the first step after the load.)
TEST(State, ForgettingTheContactMemoryChangesTheContinuation) {
  Game gameA;
  RBodies a;
  gameA.Build(a);
  RIntegrator ia(Game::Settings(1));
  Play(ia, a, gameA, 0, kSave, nullptr);
  const std::vector<std::uint8_t> saved = SaveState(ia, a);
  Record uninterrupted, forgetful;
  Play(ia, a, gameA, kSave, kSave + 30, &uninterrupted);
  Game gameB;
  RBodies b;
  gameB.Build(b);
  RIntegrator ib(Game::Settings(1));
  LoadState(ib, b, saved);
  ib.ForgetContacts();
  Play(ib, b, gameB, kSave, kSave + 30, &forgetful);
  EXPECT_NE(uninterrupted.state.front(), forgetful.state.front());
}

// The broad phase's trees and pair list are not in the state because they change no result:
// the loaded world, run on with the all-pairs loop, matches the uninterrupted world run on
// with the trees every step.
TEST(State, BroadPhaseIsNotPartOfTheState) {
  Game gameA;
  RBodies a;
  gameA.Build(a);
  RWorldSettings settings = Game::Settings(1);
  settings.shortcuts.broadPhaseAlways = true;
  RIntegrator ia(settings);
  Play(ia, a, gameA, 0, kSave, nullptr);
  ASSERT_TRUE(ia.PairStats().broadPhase);
  const std::vector<std::uint8_t> saved = SaveState(ia, a);
  Record trees, loop;
  Play(ia, a, gameA, kSave, kSave + 150, &trees);
  Game gameB;
  RBodies b;
  gameB.Build(b);
  RIntegrator ib(Game::Settings(1));
  LoadState(ib, b, saved);
  EXPECT_TRUE(ib.Settings().shortcuts.broadPhaseAlways) << "settings come with the state";
  ib.Settings().shortcuts.broadPhase = false;
  Play(ib, b, gameB, kSave, kSave + 150, &loop);
  EXPECT_FALSE(ib.PairStats().broadPhase);
  EXPECT_EQ(trees.state, loop.state);
  EXPECT_EQ(trees.events, loop.events);
}

// Rollback in one world: save, run on (a spawn, a removal), load into the same integrator and
// container, run the same steps again: the same world, and the spawned body gets its handle
// again. The bodies removed since the save come back (their shapes are still in the
// container's other bodies).
TEST(State, RollbackInTheSameWorldReplaysTheSameSteps) {
  Game game;
  RBodies bodies;
  game.Build(bodies);
  RIntegrator integrator(Game::Settings(1));
  Play(integrator, bodies, game, 0, 380, nullptr);
  const std::vector<std::uint8_t> saved = SaveState(integrator, bodies);
  Record first, again;
  Play(integrator, bodies, game, 380, 460, &first);
  const RBodyHandle late = game.late, pileBox = game.initial[1];
  bodies.Remove(pileBox);
  LoadState(integrator, bodies, saved);
  EXPECT_TRUE(bodies.Contains(pileBox)) << "the box removed after the save is back";
  EXPECT_FALSE(bodies.Contains(late)) << "the body spawned after the save is gone";
  Play(integrator, bodies, game, 380, 460, &again);
  EXPECT_EQ(game.late, late);
  EXPECT_EQ(first.state, again.state);
  EXPECT_EQ(first.events, again.events);
}

// A copy of an integrator, with a copy of its bodies, is the same world: it goes on bit for
// bit, its sleepers asleep.
TEST(State, CopiedWorldContinuesBitIdentically) {
  Game game;
  RBodies a;
  game.Build(a);
  RIntegrator ia(Game::Settings(1));
  Play(ia, a, game, 0, kSave, nullptr);
  ASSERT_GT(ia.PairStats().sleepingBodies, 10u);
  RIntegrator ib = ia;
  RBodies b = a;
  Game copy = game;
  Record original, copied;
  Play(ia, a, game, kSave, kSave + 200, &original);
  Play(ib, b, copy, kSave, kSave + 200, &copied);
  EXPECT_EQ(original.state, copied.state);
  EXPECT_EQ(original.events, copied.events);
  EXPECT_EQ(original.sleeping, copied.sleeping);
}

// A plain vector of bodies (identity by position) saves and loads the same way.
TEST(State, PlainVectorWorldContinuesBitIdentically) {
  std::vector<BodyDef> defs = BoxStackDefs(6);
  defs.push_back(BoxDef(RVec3(0.2, 0.5, 0.9)).Mass(2).GravityScale(0).At(RVec3(0, 20, 0))
                     .Spinning(RVec3(0.01, 3, 0.02)).Named("satellite"));
  defs.push_back(SphereDef(0.4).Mass(1).At(RVec3(0.1, 60, 0.1)).Named("drop"));
  std::vector<RRigidBody> a = MakeBodies(defs);
  RIntegrator ia(EarthGravity());
  Step(ia, a, 150);
  ASSERT_EQ(Sleeping(a), 6);
  const std::vector<std::uint8_t> saved = SaveState(ia, a);
  std::vector<RRigidBody> b = MakeBodies(defs);
  RIntegrator ib(EarthGravity());
  LoadState(ib, b, saved);
  EXPECT_EQ(SaveState(ib, b), saved);
  int woke = 0;
  for (int s = 0; s < 150; ++s) {
    ia.Update(a, kDt), ib.Update(b, kDt);
    woke = std::max(woke, 6 - Sleeping(a));
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].Position_W(), b[i].Position_W()) << "body " << i << ", step " << s;
      ASSERT_EQ(a[i].Orientation_WB().coeffs(), b[i].Orientation_WB().coeffs()) << "body " << i << ", step " << s;
      ASSERT_EQ(a[i].AngularVelocity_B(), b[i].AngularVelocity_B()) << "body " << i << ", step " << s;
      ASSERT_EQ(a[i].IsSleeping(), b[i].IsSleeping()) << "body " << i << ", step " << s;
    }
  }
  EXPECT_GT(woke, 0) << "the drop woke the stack";
}

// ---- refused states ---------------------------------------------------------------------

namespace {

// A small world a few steps in, and its state.
struct Small {
  std::vector<BodyDef> defs = BoxStackDefs(2);
  RBodies bodies;
  RIntegrator integrator{EarthGravity()};
  Small() {
    for (const BodyDef& d : defs) bodies.Add(d);
  }
  std::vector<std::uint8_t> Saved() {
    for (int s = 0; s < 20; ++s) integrator.Update(bodies, kDt);
    return SaveState(integrator, bodies);
  }
};

// The field a refused load names, after checking that it left the world as it was.
std::string RefusedField(const std::vector<std::uint8_t>& state, const RLoadOptions& options = {}) {
  Small target;
  for (int s = 0; s < 7; ++s) target.integrator.Update(target.bodies, kDt);
  target.bodies.Remove(target.bodies.HandleAt(2));
  const std::vector<std::uint8_t> before = SaveState(target.integrator, target.bodies);
  try {
    LoadState(target.integrator, target.bodies, state.data(), state.size(), options);
  } catch (const RStateError& e) {
    EXPECT_FALSE(e.Problem().empty());
    EXPECT_EQ(SaveState(target.integrator, target.bodies), before) << "a refused load changed the world (" << e.what() << ")";
    return e.Field();
  }
  return "(loaded)";
}

// The offset of the first occurrence of a double's bits in the state.
std::size_t Find(const std::vector<std::uint8_t>& bytes, double value) {
  std::uint8_t pattern[8];
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  state::StoreU64(pattern, bits);
  const auto it = std::search(bytes.begin(), bytes.end(), pattern, pattern + 8);
  return it == bytes.end() ? std::string::npos : static_cast<std::size_t>(it - bytes.begin());
}

}  // namespace

TEST(State, EveryCutIsRefused) {
  const std::vector<std::uint8_t> saved = Small().Saved();
  ASSERT_EQ(RefusedField(saved), "(loaded)");
  for (std::size_t n = 0; n < saved.size(); ++n) {
    const std::vector<std::uint8_t> cut(saved.begin(), saved.begin() + static_cast<std::ptrdiff_t>(n));
    const std::string field = RefusedField(cut);
    ASSERT_TRUE(field == "header" || field == "header.magic" || field == "header.length")
        << "cut at byte " << n << " of " << saved.size() << ": " << field;
  }
}

TEST(State, WhatIsNotAStateIsRefusedByItsMagic) {
  std::vector<std::uint8_t> saved = Small().Saved();
  saved[1] ^= 0xff;
  EXPECT_EQ(RefusedField(saved), "header.magic");
  const std::string text = "{\"format\": \"rengine-scene/1\", \"bodies\": []}\n";
  EXPECT_EQ(RefusedField(std::vector<std::uint8_t>(text.begin(), text.end())), "header.magic");
  EXPECT_EQ(RefusedField({}), "header.magic");
}

TEST(State, AnotherVersionIsRefused) {
  std::vector<std::uint8_t> saved = Small().Saved();
  saved[state::kVersionAt] = static_cast<std::uint8_t>(state::kVersion + 1);
  EXPECT_EQ(RefusedField(saved), "header.version");
  saved[state::kVersionAt] = static_cast<std::uint8_t>(state::kVersion - 1);  // before joints were saved
  EXPECT_EQ(RefusedField(saved), "header.version");
}

TEST(State, AnAlteredByteIsRefusedByTheChecksum) {
  std::vector<std::uint8_t> saved = Small().Saved();
  saved[saved.size() / 2] ^= 0x10;
  EXPECT_EQ(RefusedField(saved), "header.checksum");
  saved[saved.size() / 2] ^= 0x10;
  saved.push_back(0);
  EXPECT_EQ(RefusedField(saved), "header.length");
}

// A NaN where the engine never leaves one, in a state whose checksum is right: refused by the
// field's name.
TEST(State, ANonFiniteVelocityIsRefused) {
  Small small;
  const RVec3 v(0.123456789012345, -2.5, 0.25);
  small.bodies[small.bodies.HandleAt(2)].SetVelocity_W(v);
  std::vector<std::uint8_t> saved = SaveState(small.integrator, small.bodies);
  const std::size_t at = Find(saved, v.x());
  ASSERT_NE(at, std::string::npos);
  state::StoreU64(saved.data() + at, 0x7ff8000000000000ULL);  // a quiet NaN
  state::Seal(saved);
  EXPECT_EQ(RefusedField(saved), "bodies[2].velocity");
}

TEST(State, AnotherWorldsStateIsRefused) {
  // Spheres where the loading world has boxes: their shape is nowhere in it.
  RBodies spheres;
  spheres.Add(GroundDef());
  spheres.Add(SphereDef(0.5).Mass(1).At(RVec3(0, 0.5, 0)).Named("box0"));
  RIntegrator integrator(EarthGravity());
  integrator.Update(spheres, kDt);
  EXPECT_EQ(RefusedField(SaveState(integrator, spheres)), "bodies[1].shape");
  // The same shapes under other names, at the handles the loading world holds.
  RBodies renamed;
  for (BodyDef d : BoxStackDefs(2)) renamed.Add(d.Named(d.name + "'"));
  EXPECT_EQ(RefusedField(SaveState(integrator, renamed)), "bodies[0]");
  // A world tag other than the one asked for.
  Small small;
  EXPECT_EQ(RefusedField(SaveState(small.integrator, small.bodies, 42)), "world_tag");
  RLoadOptions tagged;
  tagged.worldTag = 42;
  EXPECT_EQ(RefusedField(SaveState(small.integrator, small.bodies, 42), tagged), "(loaded)");
  // A plain vector's state.
  std::vector<RRigidBody> vector = MakeBodies(BoxStackDefs(2));
  EXPECT_EQ(RefusedField(SaveState(small.integrator, vector)), "container.kind");
}

// A body removed since the save comes back from a shape the game passes when no body of the
// container has it any more.
TEST(State, AShapeNoBodyHoldsComesFromTheOptions) {
  RBodies bodies;
  bodies.Add(GroundDef());
  const RBodyHandle ball = bodies.Add(SphereDef(0.5).Mass(1).At(RVec3(0, 3, 0)).Named("ball"));
  RIntegrator integrator(EarthGravity());
  for (int s = 0; s < 10; ++s) integrator.Update(bodies, kDt);
  const std::shared_ptr<const RPreparedShape> shape = bodies[ball].PreparedShape();
  const std::vector<std::uint8_t> saved = SaveState(integrator, bodies);
  bodies.Remove(ball);
  EXPECT_THROW(LoadState(integrator, bodies, saved), RStateError);
  RLoadOptions options;
  options.shapes.push_back(PrepareShape(shape->shape));  // prepared again: matched by its definition
  LoadState(integrator, bodies, saved, options);
  ASSERT_TRUE(bodies.Contains(ball));
  EXPECT_EQ(SaveState(integrator, bodies), saved);
}
