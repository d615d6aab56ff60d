// Walking (RCharacter.h) against closed forms: the commanded speed across the seams of tiles
// and mesh triangles, steps up to stepHeight and not above, slopes up to maxSlope and not
// steeper, and staying on the ground walking down.
//
// Tolerances. Walking on level ground moves the character by exactly v dt across the plane
// of up each Update (a cast that meets nothing moves it all the way): its speed is the
// command to the rounding of positions (1e-16 of ~20 m over dt = 1/60 s: ~1e-13 m/s), far
// inside the 1e-9 asked. Its height changes only where it meets something: on a seam there
// is nothing to meet, so it stays the same to rounding.
#include <gtest/gtest.h>

#include "character/CharacterWorld.h"

using namespace REngine;
using namespace REngine::test;

namespace {

// Walks `c` at v along x for `steps` updates after it has landed, checking each update's
// horizontal speed and its height.
void WalkLevel(CharacterWorld& w, RCharacter& c, const RVec3& v, int steps, RScalar floorTop) {
  w.Step({&c}, 30);  // lands from 1 cm up
  ASSERT_TRUE(c.OnGround());
  const RScalar height = c.Position_W().y();
  c.SetDesiredVelocity(v);
  for (int k = 0; k < steps; ++k) {
    const RVec3 before = c.Position_W();
    w.Step({&c});
    const RVec3 moved = (c.Position_W() - before) / kDt;
    ASSERT_NEAR(moved.x(), v.x(), 1e-9) << "update " << k;
    ASSERT_NEAR(moved.z(), v.z(), 1e-9) << "update " << k;
    ASSERT_NEAR(c.Position_W().y(), height, 1e-6) << "update " << k;
    ASSERT_TRUE(c.OnGround()) << "update " << k;
  }
  // It hovers contactOffset above the floor.
  const RScalar bottom = c.Position_W().y() - (c.Def().shape.type == RShapeType::kBox
                                                   ? c.Def().shape.halfExtents.y()
                                                   : c.Def().shape.halfHeight + c.Def().shape.radius);
  EXPECT_NEAR(bottom - floorTop, c.Def().contactOffset, 1e-9);
}

TEST(CharacterWalk, CrossesTwentyTilesAtTheCommandedSpeedAndHeight) {
  CharacterWorld w;
  w.Tiles(22);
  RCharacter c(Capsule());
  WalkLevel(w, c, RVec3(3, 0, 0), 20 * 20, 0);  // 20 m at 3 m/s
  EXPECT_GT(c.Position_W().x(), 19.9);
}

TEST(CharacterWalk, ABoxCrossesTheTilesCornersFirst) {
  // A box's edges meet the seams edge to edge: the case where a rigid box snags.
  CharacterWorld w;
  w.Tiles(22);
  RCharacterDef def;
  def.shape = RShape::Box(RVec3(0.3, 0.9, 0.3));
  def.position_W = RVec3(0, 0.91, 0);
  RCharacter c(def);
  WalkLevel(w, c, RVec3(3, 0, 0.2), 20 * 20, 0);
}

TEST(CharacterWalk, CrossesAMeshFloorsTriangles) {
  CharacterWorld w;
  // A 24 x 6 m floor of 0.5 m squares, each two triangles, top at y = 0.
  std::vector<RVec3> v;
  std::vector<std::array<std::uint32_t, 3>> t;
  const int nx = 48, nz = 12;
  for (int i = 0; i <= nx; ++i)
    for (int j = 0; j <= nz; ++j) v.emplace_back(-2 + 0.5 * i, 0, -3 + 0.5 * j);
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < nz; ++j) {
      const std::uint32_t a = i * (nz + 1) + j, b = a + nz + 1;
      t.push_back({a, a + 1, b});
      t.push_back({b, a + 1, b + 1});
    }
  RBodyDef floor;
  floor.shape = RShape::Mesh(v, t);
  floor.kind = RBodyKind::kStatic;
  w.bodies.Add(floor);
  RCharacter c(Capsule());
  WalkLevel(w, c, RVec3(3, 0, 0.3), 20 * 20, 0);
}

// A step of height h at x = 1 (its face), 2 m deep.
RScalar ClimbStep(RScalar h, RScalar stepHeight) {
  CharacterWorld w;
  w.Tiles(8);
  w.Box(RVec3(1, h / 2, 2), RVec3(2, h / 2, 0));
  RCharacterDef def = Capsule(0.3, 0.6);
  def.stepHeight = stepHeight;
  RCharacter c(def);
  w.Step({&c}, 30);
  c.SetDesiredVelocity(RVec3(2, 0, 0));
  w.Step({&c}, 90);  // 3 m of walking
  return c.Position_W().x();
}

TEST(CharacterWalk, ClimbsAStepBelowStepHeightAndStopsAtAHigherOne) {
  {
    CharacterWorld w;
    w.Tiles(8);
    w.Box(RVec3(1, 0.15, 2), RVec3(2, 0.15, 0));  // 0.30 m high, face at x = 1
    RCharacterDef def = Capsule(0.3, 0.6);
    def.stepHeight = 0.35;
    RCharacter c(def);
    w.Step({&c}, 30);
    c.SetDesiredVelocity(RVec3(2, 0, 0));
    w.Step({&c}, 60);  // 2 m
    EXPECT_TRUE(c.OnGround());
    EXPECT_NEAR(c.Position_W().y(), 0.30 + 0.9 + def.contactOffset, 1e-6);  // on top of it
    EXPECT_GT(c.Position_W().x(), 1.5);
  }
  // 0.45 m: it stops against the face, one radius and the offset before it.
  const RScalar x = ClimbStep(0.45, 0.35);
  EXPECT_NEAR(x, 1 - 0.3 - 1e-3, 1e-6);
}

// A ramp rising along +x at `angle` from the floor, its foot at x = 1.
void Ramp(CharacterWorld& w, RScalar angle) {
  const RScalar len = 6, thick = 0.2;
  const RQuat q(Eigen::AngleAxisd(angle, RVec3::UnitZ()));
  // The top face's foot edge at (1, 0): centre half a length up the slope, half a thickness in.
  const RVec3 along(std::cos(angle), std::sin(angle), 0), normal(-std::sin(angle), std::cos(angle), 0);
  w.Box(RVec3(len / 2, thick / 2, 2), RVec3(1, 0, 0) + along * (len / 2) - normal * (thick / 2), RBodyKind::kStatic, q);
}

TEST(CharacterWalk, WalksUpAThirtyDegreeRampAtTheCommandedHorizontalSpeed) {
  CharacterWorld w;
  w.Tiles(10);
  const RScalar angle = 30 * M_PI / 180;
  Ramp(w, angle);
  RCharacter c(Capsule());
  w.Step({&c}, 30);
  c.SetDesiredVelocity(RVec3(2, 0, 0));
  int onRamp = 0;
  for (int k = 0; k < 120; ++k) {
    const RVec3 before = c.Position_W();
    w.Step({&c});
    ASSERT_TRUE(c.OnGround()) << k;
    const RScalar rise = c.Ground().contact.normal_W.y();
    // Fully on the ramp (before and after): horizontal speed 2, vertical 2 tan 30.
    if (std::abs(rise - std::cos(angle)) < 1e-9 && before.x() > 2) {
      const RVec3 v = (c.Position_W() - before) / kDt;
      EXPECT_NEAR(v.x(), 2, 1e-9) << k;
      EXPECT_NEAR(v.y(), 2 * std::tan(angle), 1e-6) << k;
      ++onRamp;
    }
  }
  EXPECT_GT(onRamp, 50);
  EXPECT_GT(c.Position_W().y(), 0.9 + 2 * std::tan(angle));
}

TEST(CharacterWalk, DoesNotClimbAFiftyDegreeRamp) {
  CharacterWorld w;
  w.Tiles(10);
  Ramp(w, 50 * M_PI / 180);
  RCharacter c(Capsule());
  w.Step({&c}, 30);
  c.SetDesiredVelocity(RVec3(2, 0, 0));
  w.Step({&c}, 120);
  // Against the ramp's foot, no higher than a step (stepHeight 0.3) lets it get on the slope.
  EXPECT_LT(c.Position_W().x(), 1.0);
  EXPECT_LT(c.Position_W().y(), 0.9 + 0.3 + 0.01);
  w.Step({&c}, 60);
  EXPECT_LT(c.Position_W().x(), 1.0);
}

TEST(CharacterWalk, StaysOnTheGroundWalkingDownStairs) {
  CharacterWorld w;
  w.Tiles(4, -4);  // top at 0 for x < 0
  // Stairs down from x = 0: five 0.2 m steps 0.4 m deep, then a floor at -1.
  for (int i = 0; i < 5; ++i) w.Box(RVec3(0.2, 0.1, 2), RVec3(0.2 + 0.4 * i, -0.2 * (i + 1) - 0.1, 0));
  w.Box(RVec3(3, 0.1, 2), RVec3(5, -1.1, 0));
  RCharacter c(Capsule(0.3, 0.6, 0, -1));
  w.Step({&c}, 30);
  c.SetDesiredVelocity(RVec3(1.5, 0, 0));
  for (int k = 0; k < 150; ++k) {
    w.Step({&c});
    ASSERT_TRUE(c.OnGround()) << "left the stairs at update " << k << ", x " << c.Position_W().x();
  }
  EXPECT_NEAR(c.Position_W().y(), -1 + 0.9 + 1e-3, 1e-6);
}

}  // namespace
