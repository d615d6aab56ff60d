// LoadState (RWorldState.h) on edited states whose checksum is right: every value a saved
// world cannot hold is refused by the field's name, with the world left as it was. A body
// asleep with no island, or with an island beyond the slots (the next step would mark a slot
// out of bounds); a position beyond 1e15 m; NaN in the exact rotation's cache, in a joint's
// frames or gravity; impulses of 1e300; limits and motors a joint cannot have; 2^31 solver
// iterations; remembered pairs naming bodies the container never held.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RWorldState.h>

#include "state/RStateFormat.h"  // the header's layout and checksum: to reseal edited states
#include "support/TestBodies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;

// A world with a body of each kind, each at an x of its own (to find its record by its
// position), a box tumbling about its intermediate axis (the exact rotation's cache), a
// hinge with limits and a motor and a ball joint (each anchor's x its own too).
constexpr RScalar kGroundX = 0.0625, kBoxX = 0.09375, kPlatformX = 5.03125, kTumblerX = -7.15625, kHingeX = 0.34375,
                  kBallX = 9.40625;
enum : std::size_t { kGround, kBox, kPlatform, kTumbler, kBob, kBall };

void Build(RBodies& bodies) {
  bodies.Add(BoxDef(RVec3(20, 0.5, 20)).Static().At(RVec3(kGroundX, -0.5, 0)).Named("ground"));
  bodies.Add(BoxDef(RVec3::Constant(0.5)).Mass(1).At(RVec3(kBoxX, 0.5, 0)).Named("box"));
  bodies.Add(BoxDef(RVec3(1, 0.1, 1)).Kinematic().At(RVec3(kPlatformX, 0.1, 0)).Spinning(RVec3(0, 1, 0))
                 .Named("platform"));
  bodies.Add(BoxDef(RVec3(0.2, 0.5, 0.9)).Mass(2).GravityScale(0).At(RVec3(kTumblerX, 20, 0)).Spinning(RVec3(0.01, 3, 0.02))
                 .Named("tumbler"));
  const RBodyHandle bob = bodies.Add(SphereDef(0.2).Mass(1).At(RVec3(kHingeX + 1, 3.5, 0)).Named("bob"));
  const RBodyHandle ball = bodies.Add(SphereDef(0.2).Mass(1).At(RVec3(kBallX + 0.5, 6, 0)).Named("ball"));
  RJointDef hinge;
  hinge.type = RJointType::kHinge;
  hinge.a = bob;
  hinge.anchor_W = RVec3(kHingeX, 3.5, 0), hinge.axis_W = RVec3(0, 0, 1);
  hinge.hasLimits = true, hinge.lower = -1, hinge.upper = 1;
  hinge.motor = {true, 0.5, 20};
  bodies.AddJoint(hinge);
  RJointDef ballJoint;
  ballJoint.type = RJointType::kBall;
  ballJoint.a = ball;
  ballJoint.anchor_W = RVec3(kBallX, 6, 0);
  bodies.AddJoint(ballJoint);
}

struct World {
  RBodies bodies;
  RIntegrator integrator{EarthGravity()};
  World() { Build(bodies); }
  std::vector<std::uint8_t> SavedAfter(int steps) {
    for (int s = 0; s < steps; ++s) integrator.Update(bodies, kDt);
    return SaveState(integrator, bodies);
  }
};

// The field a refused load names, after checking that it left the world as it was;
// "(loaded)" if it loaded.
std::string RefusedField(std::vector<std::uint8_t> state) {
  state::Seal(state);
  World target;
  target.SavedAfter(3);
  const std::vector<std::uint8_t> before = SaveState(target.integrator, target.bodies);
  try {
    LoadState(target.integrator, target.bodies, state);
  } catch (const RStateError& e) {
    EXPECT_FALSE(e.Problem().empty());
    EXPECT_EQ(SaveState(target.integrator, target.bodies), before) << "a refused load changed the world (" << e.what() << ")";
    return e.Field();
  }
  return "(loaded)";
}

// The offset of the first (or last) occurrence of a double's bits in the state.
std::size_t Find(const std::vector<std::uint8_t>& bytes, double value, bool last = false) {
  std::uint8_t pattern[8];
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  state::StoreU64(pattern, bits);
  const auto it = last ? std::find_end(bytes.begin(), bytes.end(), pattern, pattern + 8)
                       : std::search(bytes.begin(), bytes.end(), pattern, pattern + 8);
  return it == bytes.end() ? std::string::npos : static_cast<std::size_t>(it - bytes.begin());
}

void PutF64(std::vector<std::uint8_t>& bytes, std::size_t at, double v) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &v, sizeof bits);
  state::StoreU64(bytes.data() + at, bits);
}
void PutU32(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) bytes[at + k] = static_cast<std::uint8_t>(v >> (8 * k));
}
std::uint64_t GetU64(const std::vector<std::uint8_t>& bytes, std::size_t at) { return state::LoadU64(bytes.data() + at); }

// A body's record from its position on (src/state/RStateRecords.cpp, WriteBody): the offsets of
// its fields after the position's first byte.
enum : std::size_t { kSleeping = 224, kIsland = 283, kGeneral = 292, kCacheValid = 293, kCacheStep = 294, kAxes = 326 };
// A joint's record from its anchor on (src/state/RStateJoints.cpp).
enum : std::size_t { kUpper = 82, kMotor = 106, kAxisA = 172, kImpulses = 316 };
// The payload's fixed start (src/state/RStateStep.cpp): the world tag, the settings, the
// integrator's counts, then the warm starts.
constexpr std::size_t kPayload = state::kHeaderBytes;
constexpr std::size_t kGravity = kPayload + 8, kIterations = kPayload + 34, kWarmCount = kPayload + 143;
constexpr std::size_t kFirstWarm = kWarmCount + 8, kWarmNormalImpulse = 44, kWarmBytes = 124;

}  // namespace

TEST(StateRefusal, TheOffsetsTheseTestsEditAreTheFieldsTheyName) {
  World world;
  const std::vector<std::uint8_t> saved = world.SavedAfter(0);
  ASSERT_EQ(RefusedField(saved), "(loaded)");
  const std::size_t box = Find(saved, kBoxX);
  ASSERT_NE(box, std::string::npos);
  EXPECT_EQ(saved[box + kSleeping], 0);
  EXPECT_EQ(saved[box + kIsland] & saved[box + kIsland + 3], 0xff) << "an island of kNoIsland";
  EXPECT_EQ(Find(saved, -9.81), kGravity + 8) << "gravity's y";
  EXPECT_EQ(saved[kIterations], 10);
}

// A body asleep with no island, or one beyond the slots, is refused: the step would mark
// m_wakeMark[island] out of bounds when anything touched it. Static and kinematic bodies
// never sleep and have no island.
TEST(StateRefusal, ASleepingBodyNeedsAnIslandWithinTheSlots) {
  World world;
  const std::vector<std::uint8_t> saved = world.SavedAfter(0);
  struct Case {
    RScalar x;
    std::size_t body;
    const char* field;
  };
  for (const Case& c : {Case{kBoxX, kBox, ".island"}, Case{kGroundX, kGround, ".sleeping"},
                        Case{kPlatformX, kPlatform, ".sleeping"}}) {
    std::vector<std::uint8_t> forged = saved;
    const std::size_t at = Find(forged, c.x);
    ASSERT_NE(at, std::string::npos);
    forged[at + kSleeping] = 1;
    EXPECT_EQ(RefusedField(forged), "bodies[" + std::to_string(c.body) + "]" + c.field);
    forged[at + kSleeping] = 0;
    PutU32(forged, at + kIsland, 1);
    EXPECT_EQ(RefusedField(forged), c.body == kBox ? "(loaded)" : "bodies[" + std::to_string(c.body) + "].island")
        << "an awake dynamic body may still name the island the game woke it from";
  }
  std::vector<std::uint8_t> forged = saved;
  const std::size_t box = Find(forged, kBoxX);
  forged[box + kSleeping] = 1;
  PutU32(forged, box + kIsland, 6);  // six slots: 0 to 5
  EXPECT_EQ(RefusedField(forged), "bodies[1].island");
  PutU32(forged, box + kIsland, 5);
  EXPECT_EQ(RefusedField(forged), "(loaded)");
}

TEST(StateRefusal, APositionBeyondTheApisRangeIsRefused) {
  World world;
  std::vector<std::uint8_t> forged = world.SavedAfter(0);
  PutF64(forged, Find(forged, kBoxX), 2e15);
  EXPECT_EQ(RefusedField(forged), "bodies[1].position");
}

// The exact rotation's cache, valid after a step, is reused bit for bit by the next: a NaN
// or a repeated axis in it is refused.
TEST(StateRefusal, ABrokenRotationCacheIsRefused) {
  World world;
  const std::vector<std::uint8_t> saved = world.SavedAfter(10);
  ASSERT_EQ(world.bodies.At(kTumbler).Position_W().x(), kTumblerX);
  const std::size_t at = Find(saved, kTumblerX);
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(saved[at + kGeneral], 1);
  ASSERT_EQ(saved[at + kCacheValid], 1);
  std::vector<std::uint8_t> forged = saved;
  PutF64(forged, at + kCacheStep, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(RefusedField(forged), "bodies[3].rotation.step");
  forged = saved;
  forged[at + kAxes + 2] = forged[at + kAxes];
  EXPECT_EQ(RefusedField(forged), "bodies[3].rotation.axes");
}

TEST(StateRefusal, AJointNoAddJointMakesIsRefused) {
  World world;
  const std::vector<std::uint8_t> saved = world.SavedAfter(5);
  const std::size_t hinge = Find(saved, kHingeX), ball = Find(saved, kBallX);
  ASSERT_NE(hinge, std::string::npos);
  ASSERT_NE(ball, std::string::npos);
  std::vector<std::uint8_t> forged = saved;
  PutF64(forged, hinge + kAxisA, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(RefusedField(forged), "joints[0].frames");
  forged = saved;
  PutF64(forged, hinge + kImpulses, 1e300);
  EXPECT_EQ(RefusedField(forged), "joints[0].impulses");
  forged = saved;
  PutF64(forged, hinge + kUpper, 4);
  EXPECT_EQ(RefusedField(forged), "joints[0].upper") << "a hinge's limits lie within [-pi, pi]";
  forged = saved;
  forged[ball + kMotor] = 1;
  EXPECT_EQ(RefusedField(forged), "joints[1].motor") << "a ball joint has no motor";
}

TEST(StateRefusal, SettingsBeyondTheirRangesAreRefused) {
  World world;
  const std::vector<std::uint8_t> saved = world.SavedAfter(5);
  std::vector<std::uint8_t> forged = saved;
  PutF64(forged, kGravity + 8, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(RefusedField(forged), "settings.gravity");
  for (std::uint32_t iterations : {0u, 1001u, 0x80000000u}) {
    forged = saved;
    PutU32(forged, kIterations, iterations);
    EXPECT_EQ(RefusedField(forged), "settings.iterations") << iterations;
  }
  forged = saved;
  PutU32(forged, kIterations, 1000);
  EXPECT_EQ(RefusedField(forged), "(loaded)");
}

// A warm start of 1e300 would throw the pair's bodies out of the doubles in the next step; a
// warm start of a slot the container never had names no pair (the last one edited: the
// warm starts stay in order).
TEST(StateRefusal, AWarmStartBeyondItsRangeIsRefused) {
  World world;
  const std::vector<std::uint8_t> saved = world.SavedAfter(30);
  ASSERT_EQ(saved[kWarmCount - 1], 0) << "a body became non-finite";
  ASSERT_GT(GetU64(saved, kWarmCount), 0u) << "no warm starts to edit";
  std::vector<std::uint8_t> forged = saved;
  PutF64(forged, kFirstWarm + kWarmNormalImpulse, 1e300);
  EXPECT_EQ(RefusedField(forged), "warm_starts[0].normal_impulse");
  const std::size_t last = GetU64(saved, kWarmCount) - 1;
  forged = saved;
  PutU32(forged, kFirstWarm + last * kWarmBytes, 1000);  // the pair's second slot (the key's low half)
  EXPECT_EQ(RefusedField(forged), "warm_starts[" + std::to_string(last) + "].pair");
}

// A touching pair naming a body the container never held would end in a phantom event (the
// last pair edited: the pairs stay in order).
TEST(StateRefusal, ATouchingPairOfABodyNeverHeldIsRefused) {
  World world;
  const std::vector<std::uint8_t> saved = world.SavedAfter(20);
  const auto touching = std::find_if(world.integrator.Events().rbegin(), world.integrator.Events().rend(),
                                     [](const RContactEvent& e) { return e.type != RContactEventType::kEnd; });
  ASSERT_NE(touching, world.integrator.Events().rend()) << "nothing touches";
  const std::size_t point = Find(saved, touching->point_W.x(), true);
  ASSERT_NE(point, std::string::npos);
  for (const std::uint32_t generation : {0u, 1u}) {
    std::vector<std::uint8_t> forged = saved;
    if (generation == 0) {
      PutU32(forged, point - 8, 1000);  // handle_b's slot
    } else {
      PutU32(forged, point - 4, touching->handleB.generation + 1);  // a generation not yet issued
    }
    const std::string field = RefusedField(forged);
    EXPECT_EQ(field.rfind("touching[", 0), 0u) << field;
    EXPECT_NE(field.find("].handle_b"), std::string::npos) << field;
  }
}
