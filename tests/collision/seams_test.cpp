// Flush tiles behave as one floor: a body that slides or rolls across separate immovable
// tiles laid edge to edge (boxes, hulls, mesh pieces, kinematic boxes, and the box children
// of one compound body) keeps its velocity along the floor, its spin and its height, as the
// closed form of motion on a plane says (constant), while a real step stops it or lifts it
// as its geometry says, a gap is a gap and a wall of stacked boxes stops it. The scenes are
// SeamScenes.h's.
//
// Tolerances. The closed form is kept to rounding on one floor: the contact solver leaves a
// body sliding or rolling on a plane at its velocity and height to 1e-12 or better, so the
// tiles are asked 1e-9 (m/s, m; spin 1e-9 m/s at the rim). Each crossing also runs on one
// floor (Tiles::kOneFloor), the method's own error for that case, and where that error is
// larger the tiles are asked it again within a factor 4 (other rounding seeds the same
// growth). One family needs this, and more: a capsule rolling 1e5 m from the origin on a
// floor laid along a diagonal. On one floor its tilt, seeded by the rounding of its contact
// points there (1e-11 m), grows by about 1.8 a step at 50 m/s (333 rad/s, 5.6 rad a step):
// 2.8e-6 m/s after 15 steps. On the tiles the seed is larger: their tops, at poses rounded
// to 1e-11 m, are level only to that (the rule takes them as flush), and the capsule's line
// of contact passing from one top to the next leaves up to 2.4e-9 m/s at 5 m/s. That
// family is asked 1e-8. So is the same capsule rolling across a compound's children (a deck
// of boxes in one body): at 50 m/s it crosses a seam nearly every step, and its tilt, 2e-13
// rad/s after the first step as on one floor, grows by about 1.8 a step from the second
// on, to 7e-9 rad/s (1.1e-9 m/s at its rim) after 15, where on one floor it stays at 3e-11.
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>

#include "collision/SeamScenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kSpeeds[] = {1, 5, 20, 50};
constexpr RScalar kAsked = 1e-9;       // m/s, m; the spin's at a rim of 0.15 m and up
constexpr RScalar kSpinRadius = 0.15;  // m, the smallest roller's
constexpr RScalar kNoise = 4;          // see the tolerances above
constexpr RScalar kAskedFarRoller = 1e-8;

// What a crossing is asked (see the tolerances above).
RScalar Asked(const Crossing& c) {
  const bool far = c.frame.origin.norm() > 0 && !c.frame.R.isIdentity();
  return c.mover == Mover::kCapsuleRolling && (far || c.tiles == Tiles::kCompound) ? kAskedFarRoller : kAsked;
}

// How far a crossing runs: 4 m or a quarter second, whichever is longer, on enough tiles
// (from x = 0.4, on the first tile) that the body ends on the last but one.
int Steps(RScalar speed) { return static_cast<int>(std::ceil(std::max(4.0, 0.25 * speed) / speed / kDt)); }
int TileCount(RScalar speed) { return static_cast<int>(std::ceil(std::max(4.0, 0.25 * speed))) + 3; }

std::string Describe(const Crossing& c) {
  char s[200];
  std::snprintf(s, sizeof s, "%s on %s%s, %g m/s, %s, %s", Name(c.mover), Name(c.tiles), c.grid ? " (grid)" : "",
                c.speed, c.gravity ? "gravity" : "no gravity", c.frame.name);
  return s;
}

// The worst departures from the closed form over a set of crossings, each against its bound
// (Asked, or the same crossing's error on one floor times kNoise when that is larger).
struct Worst {
  CrossingResult r;
  RScalar ratio[3] = {0, 0, 0};
  std::string at[3];
  void Add(const Crossing& c, const CrossingResult& x, const CrossingResult& oneFloor) {
    const RScalar errors[3] = {x.speedError, x.spinError * kSpinRadius, x.heightError};
    const RScalar floors[3] = {oneFloor.speedError, oneFloor.spinError * kSpinRadius, oneFloor.heightError};
    for (int k = 0; k < 3; ++k) {
      const RScalar q = errors[k] / std::max(Asked(c), kNoise * floors[k]);
      if (q > ratio[k]) ratio[k] = q, at[k] = Describe(c);
    }
    r.speedError = std::max(r.speedError, x.speedError);
    r.spinError = std::max(r.spinError, x.spinError);
    r.heightError = std::max(r.heightError, x.heightError);
  }
  void Expect() const {
    EXPECT_LE(ratio[0], 1) << "velocity, worst " << at[0];
    EXPECT_LE(ratio[1], 1) << "spin, worst " << at[1];
    EXPECT_LE(ratio[2], 1) << "height, worst " << at[2];
  }
};

// The crossing, on its tiles and on one floor.
void Cross(const Crossing& c, Worst& worst, CrossingResult* tiles = nullptr) {
  Crossing one = c;
  one.tiles = Tiles::kOneFloor, one.grid = false;
  const CrossingResult r = RunCrossing(c, 0.4, Steps(c.speed), kDt);
  worst.Add(c, r, RunCrossing(one, 0.4, Steps(c.speed), kDt));
  if (tiles) *tiles = r;
}

}  // namespace

// Every shape across boxes, hulls, mesh pieces and a compound's box children, at 1 to 50
// m/s, with and without gravity, on a floor along x, along a diagonal, 1e5 m out, and as a wall (gravity towards it). The
// issue's case (5 m/s, gravity, box tiles) is printed per shape with its exit velocity and
// hop, and the worst of each shape and kind of tile.
TEST(Seams, EveryShapeCrossesFlushTilesAsOneFloor) {
  for (const Mover mover : kMovers) {
    for (const Tiles tiles : {Tiles::kBoxes, Tiles::kHulls, Tiles::kMeshes, Tiles::kCompound}) {
      Worst worst;
      for (const SceneFrame& frame : Frames()) {
        for (const RScalar speed : kSpeeds) {
          for (const bool gravity : {true, false}) {
            Crossing c;
            c.mover = mover, c.tiles = tiles, c.speed = speed, c.gravity = gravity, c.frame = frame;
            c.tileCount = TileCount(speed);
            CrossingResult r;
            Cross(c, worst, &r);
            if (speed == 5 && gravity && frame.name == Frames()[0].name) {
              std::printf("%-16s on %-7s at 5 m/s: exit v (%.9f, %.2e) m/s, hop %.2e m\n", Name(mover), Name(tiles),
                          r.exitV.x(), r.exitV.y(), r.hop);
            }
          }
        }
      }
      std::printf("%-16s on %-7s worst: |dv| %.1e m/s, |dw| %.1e rad/s, |dy| %.1e m (of the bound: %.2f %.2f %.2f)\n",
                  Name(mover), Name(tiles), worst.r.speedError, worst.r.spinError, worst.r.heightError, worst.ratio[0],
                  worst.ratio[1], worst.ratio[2]);
      worst.Expect();
    }
  }
}

// Kinematic tiles (still) are immovable as static ones are.
TEST(Seams, KinematicTilesAreOneFloorToo) {
  Worst worst;
  for (const Mover mover : kMovers) {
    for (const RScalar speed : kSpeeds) {
      Crossing c;
      c.mover = mover, c.tiles = Tiles::kKinematic, c.speed = speed, c.tileCount = TileCount(speed);
      Cross(c, worst);
    }
  }
  worst.Expect();
}

// Tiles laid with their seams alternately 1e-5 m open and 1e-5 m closed (overlapping): a
// level's placement error, within the slop of flush, is one floor too. (A ball over a gap
// g sinks g^2 / (8 r) into it: 5e-11 m here.)
TEST(Seams, NearlyFlushTilesAreOneFloor) {
  Worst worst;
  for (const Mover mover : kMovers) {
    for (const RScalar speed : {1.0, 20.0}) {
      for (const bool gravity : {true, false}) {
        Crossing c;
        c.mover = mover, c.speed = speed, c.gravity = gravity, c.tileCount = TileCount(speed), c.jitter = 1e-5;
        Cross(c, worst);
      }
    }
  }
  worst.Expect();
}

// A grid of 1 m box tiles turned 0.4 rad to the motion: the body crosses seams of both
// directions and the corners where four tiles meet, and lies across seams along its length.
// Frictionless, every shape keeps the closed form (a roller rolls on without friction). With
// friction (the rollers' own, 0.5), a capsule or cylinder rolling with its line of contact
// split between two tiles keeps it too: its manifolds on the flush tiles share one friction
// patch, at the middle of the whole line with the line's twist limit, as on one floor
// (solver/RPatchGroups.cpp). With a patch per manifold, each at its own point with no twist
// limit and solved one after the other, it drifted (0.36 m/s at 50 m/s, 1e-2 at 1 m/s).
TEST(Seams, AGridOfTilesCrossedObliquelyIsOneFloor) {
  for (const Mover mover : kMovers) {
    Worst worst;
    for (const RScalar speed : kSpeeds) {
      for (const bool gravity : {true, false}) {
        Crossing c;
        c.mover = mover, c.speed = speed, c.gravity = gravity, c.grid = true, c.tileYaw = 0.4;
        c.tileCount = TileCount(speed), c.moverFriction = 0;
        Cross(c, worst);
      }
    }
    std::printf("%-16s over a turned grid, frictionless: |dv| %.1e m/s, |dw| %.1e rad/s, |dy| %.1e m\n", Name(mover),
                worst.r.speedError, worst.r.spinError, worst.r.heightError);
    worst.Expect();
  }
  for (const Mover mover : {Mover::kCapsuleRolling, Mover::kCylinderRolling}) {
    Worst worst;
    for (const RScalar speed : kSpeeds) {
      for (const bool gravity : {true, false}) {
        Crossing c;
        c.mover = mover, c.speed = speed, c.gravity = gravity, c.grid = true, c.tileYaw = 0.4;
        c.tileCount = TileCount(speed);
        CrossingResult r;
        Cross(c, worst, &r);
        EXPECT_LT(r.hop, kAsked) << Describe(c);
      }
    }
    std::printf("%-16s over a turned grid, with friction: |dv| %.1e m/s, |dw| %.1e rad/s, |dy| %.1e m\n",
                Name(mover), worst.r.speedError, worst.r.spinError, worst.r.heightError);
    worst.Expect();
  }
}

namespace {

// A box of half height hh (scene frame) sliding at 5 m/s from x = 2.2 towards tile 3 raised
// by `rise`: the tiles, and the same geometry with no seam (one floor, a separate step box
// on it from x = 3: nothing covers that box's face), run side by side; the tile scene's
// contacts with the raised tile checked by `check` after each step.
template <class Check>
void StepAgainstOneFloor(const SceneFrame& frame, RScalar rise, RScalar hh, RScalar& apart, RVec3& x, RVec3& v,
                         const Check& check) {
  Crossing c;
  c.mover = Mover::kBox, c.speed = 5, c.frame = frame, c.raised = 3, c.rise = rise;
  RScalar height = 0;
  RVec3 w0;
  std::vector<RRigidBody> tiles = SeamScene(c, 2.2, height, w0);
  Crossing one = c;
  one.tiles = Tiles::kOneFloor, one.raised = -1;
  std::vector<RRigidBody> reference = SeamScene(one, 2.2, height, w0);
  RBodyDef box = MoverDef(c, 2.2, height, w0);
  box.shape = RShape::Box(RVec3(0.3, hh, 0.25));
  box.position_W = frame.R * RVec3(2.2, hh, 0) + frame.origin;
  tiles.back() = RRigidBody(box), reference.back() = RRigidBody(box);
  RBodyDef step;
  step.shape = RShape::Box(RVec3(0.5 * (c.tileCount - 3), rise / 2, 2));
  step.position_W = frame.R * RVec3(3 + 0.5 * (c.tileCount - 3), rise / 2, 0) + frame.origin;
  step.q_WS = RQuat(frame.R);
  reference.insert(reference.begin() + 1, RRigidBody(Immovable(step, c)));
  RIntegrator a, b;
  SetGravity(a, c), SetGravity(b, c);
  a.Settings().shortcuts.sleeping = b.Settings().shortcuts.sleeping = false;
  apart = 0;
  for (int k = 0; k < 60; ++k) {
    a.Update(tiles, kDt), b.Update(reference, kDt);
    apart = std::max(apart, (tiles.back().Position_W() - reference.back().Position_W()).norm());
    check(a.Contacts());
  }
  x = frame.R.transpose() * (tiles.back().Position_W() - frame.origin);
  v = frame.R.transpose() * tiles.back().Velocity_W();
}

}  // namespace

// A real step acts. A box as tall as the step (restitution 0) meets the step's face with its
// whole front face, through its centre of mass: it stops dead at x = 3 (velocity 0), as it
// does against the same step made of a separate box on one floor (to 1e-9 m over the run).
// A box 0.4 m tall tips: back off a 10 cm step, and over a 1 cm one onto it (a frictionless
// box at 5 m/s carries its centre over the edge), on the tiles as on the one floor with a
// step box. Not to rounding: the two decompositions give the tipping box's corners to
// different bodies (over the seam the lower tile's edge, within its clipping tolerance; on
// one floor the step box, the floor's face under it being covered), so from the first step
// a corner is clipped on one and kept on the other their manifolds differ, and the tipping
// that follows is statically indeterminate (10 solver iterations) and goes its own way on
// each. What must agree is what the geometry does: the box backs off the 10 cm step (behind
// it, moving back) and goes over the 1 cm one (above it), and the two runs stay within
// 0.1 m of each other on the 10 cm step (1.8e-2 measured), a sixth of the box's length, and
// 1e-5 m on the 1 cm one (1.2e-6 measured: there the tipping does not part them).
// Throughout, the raised tile's contacts on its side lie above its neighbour's top: the
// side's covered part is no surface (a tipping box dips its edge below the neighbour's top,
// where the contact is clipped).
TEST(Seams, ARealStepActsAsTheSameStepOnOneFloor) {
  for (const SceneFrame& frame : Frames()) {
    for (const RScalar rise : {0.01, 0.1}) {
      for (const RScalar hh : {rise / 2, 0.2}) {
        RScalar lowest = std::numeric_limits<RScalar>::infinity();
        auto check = [&](const std::vector<RContact>& contacts) {
          for (const RContact& ct : contacts) {
            if (ct.a != 3 && ct.b != 3) continue;
            const RVec3 n = frame.R.transpose() * ct.manifold.normal;
            if (std::abs(n.x()) < 0.9) continue;  // the tile's side
            // Each point on the tile's surface: half its separation back along the normal.
            const RVec3 n_W = ct.a == 3 ? ct.manifold.normal : RVec3(-ct.manifold.normal);
            for (int k = 0; k < ct.manifold.pointCount; ++k) {
              const RContactPoint& p = ct.manifold.points[k];
              const RVec3 q = frame.R.transpose() * (p.position - 0.5 * p.separation * n_W - frame.origin);
              lowest = std::min(lowest, q.y());
            }
          }
        };
        RScalar apart;
        RVec3 x, v;
        StepAgainstOneFloor(frame, rise, hh, apart, x, v, check);
        std::printf("box %g m tall at 5 m/s against a %g m step (%s): ends at x %.6f y %.6f, v (%.2e, %.2e) m/s; "
                    "from one floor's step %.1e m; lowest point on the step's side %.1e m\n",
                    2 * hh, rise, frame.name, x.x(), x.y(), v.x(), v.y(), apart, lowest);
        EXPECT_GE(lowest, -1e-9) << rise << " " << hh << " " << frame.name;
        if (hh == rise / 2) {
          EXPECT_LT(apart, 1e-9) << rise << " " << frame.name;
          EXPECT_LT(v.norm(), 1e-9) << rise << " " << frame.name;
          EXPECT_NEAR(x.x() + 0.3, 3, 5e-4) << rise << " " << frame.name;
        } else if (rise == 0.1) {
          EXPECT_LT(apart, 0.1) << frame.name;
          EXPECT_LT(x.x(), 3) << frame.name;
          EXPECT_LT(v.x(), 0) << frame.name;
        } else {
          EXPECT_LT(apart, 1e-5) << frame.name;
          EXPECT_GT(x.y(), rise) << frame.name;
        }
      }
    }
  }
}

// A real step lifts a fast ball as the geometry says. A frictionless ball of radius r (no
// gravity, restitution 0) meets the edge of a step h high when its centre is d =
// sqrt(2 r h - h^2) before it; the edge's normal there is n = (-d, r - h) / r, and the
// impact takes the approach along n away: v' = v - (v . n) n = v0 (1 - d^2/r^2, d (r - h)/r^2).
// The impact is found at its time within the step to the touching band (1e-9 of the pair's
// size), which bounds the normal's error: 1e-6 of v0 asked. (Faster, where the edge is more
// than a step's travel away at the step's start, the contact phase's speculative row, at the
// start's normal, lifts the ball further after the impact: 7.80 m/s at 20 m/s for 5.38. That
// is the contact solver's, with or without tiles.)
TEST(Seams, ARealStepLiftsAFastBallAsTheGeometrySays) {
  const RScalar r = 0.25, h = 0.01, d = std::sqrt(2 * r * h - h * h);
  for (const RScalar v0 : {2.0, 5.0}) {
    for (const SceneFrame& frame : Frames()) {
      Crossing c;
      c.mover = Mover::kSphere, c.speed = v0, c.gravity = false, c.frame = frame, c.raised = 3, c.rise = h;
      c.moverFriction = 0;
      RScalar height = 0;
      RVec3 w0;
      std::vector<RRigidBody> bodies = SeamScene(c, 2.2, height, w0);
      bodies.back().SetAngularVelocity_W(RVec3::Zero());
      RIntegrator integrator;
      integrator.Settings().shortcuts.sleeping = false;
      RVec3 after = RVec3::Zero();
      for (int k = 0; k < 60 && after.y() <= 1e-3 * v0; ++k) {
        integrator.Update(bodies, kDt);
        after = c.frame.R.transpose() * bodies.back().Velocity_W();
      }
      const RVec3 expected(v0 * (1 - d * d / (r * r)), v0 * d * (r - h) / (r * r), 0);
      std::printf("ball at %g m/s on a 1 cm step (%s): v after (%.9f, %.9f), geometry (%.9f, %.9f)\n", v0, frame.name,
                  after.x(), after.y(), expected.x(), expected.y());
      EXPECT_LT((after - expected).norm(), 1e-6 * v0) << v0 << " " << frame.name;
    }
  }
}

// A gap wider than the slop is a gap: a ball of radius 1 cm rolling at 0.5 m/s falls into a
// 3 cm gap between two tiles (and through it: the tiles stand on nothing); a ball of 0.25 m
// crossing a 1 cm gap at 5 cm/s sinks into it, held by its two edges, by up to
// r - sqrt(r^2 - (g/2)^2) = 50 um at the gap's middle (42 um at least at the steps nearest
// it, 0.83 mm apart).
TEST(Seams, AGapBetweenTilesIsAGap) {
  for (const SceneFrame& frame : Frames()) {
    Crossing small;
    small.mover = Mover::kSphere, small.speed = 0.5, small.frame = frame, small.gapAt = 2, small.gap = 0.03;
    RScalar height = 0;
    RVec3 w0;
    std::vector<RRigidBody> bodies = SeamScene(small, 1.7, height, w0);
    RBodyDef ball = MoverDef(small, 1.7, height, w0);
    ball.shape = RShape::Sphere(0.01);
    ball.position_W = frame.R * RVec3(1.7, 0.01, 0) + frame.origin;
    ball.angularVelocity_W = frame.R * RVec3(0, 0, -0.5 / 0.01);
    bodies.back() = RRigidBody(ball);
    RIntegrator integrator;
    SetGravity(integrator, small);
    for (int k = 0; k < 90; ++k) integrator.Update(bodies, kDt);
    const RVec3 x = frame.R.transpose() * (bodies.back().Position_W() - frame.origin);
    std::printf("1 cm ball over a 3 cm gap (%s): ends at (%.4f, %.4f) m\n", frame.name, x.x(), x.y());
    EXPECT_LT(x.y(), -0.5) << frame.name;
    EXPECT_GT(x.x(), 2.0) << frame.name;
    EXPECT_LT(x.x(), 2.03) << frame.name;

    Crossing big;
    big.mover = Mover::kSphere, big.speed = 0.05, big.frame = frame, big.gapAt = 2, big.gap = 0.01;
    const CrossingResult r = RunCrossing(big, 1.9, 240, kDt);
    const RScalar sink = 0.25 - std::sqrt(0.25 * 0.25 - 0.005 * 0.005);
    std::printf("0.25 m ball over a 1 cm gap (%s): lowest %.3e m, geometry %.3e m\n", frame.name, r.minY - 0.25, -sink);
    EXPECT_LT(r.minY - 0.25, -0.8 * sink) << frame.name;
    EXPECT_GT(r.minY - 0.25, -sink - 5e-4) << frame.name;
  }
}

// A wall of boxes stacked flush (its seams horizontal, across the box's face) stops a box
// sliding into it over flush tiles, exactly as the same wall does on one floor (to 1e-9 m):
// the tiles change nothing of it. Restitution 0; the box never passes the wall (its back
// face is at x = 3.2) and leaves it, if at all, slower than it came. (Three manifolds share
// the impact instead of one: their rows' order turns the box, which then bounces off at
// 0.8 m/s and presses 1.2 cm into the wall for a step, on one floor too: the impact phase's.)
TEST(Seams, AWallOfStackedBoxesStopsABody) {
  for (const SceneFrame& frame : Frames()) {
    RVec3 end[2], velocity[2];
    RScalar front = 0;
    for (const Tiles tiles : {Tiles::kBoxes, Tiles::kOneFloor}) {
      Crossing c;
      c.mover = Mover::kBox, c.speed = 5, c.frame = frame, c.tiles = tiles;
      RScalar height = 0;
      RVec3 w0;
      std::vector<RRigidBody> bodies = SeamScene(c, 1.5, height, w0);
      RBodyDef box = MoverDef(c, 1.5, height, w0);
      box.shape = RShape::Box(RVec3(0.3, 0.4, 0.25));
      box.position_W = frame.R * RVec3(1.5, 0.4, 0) + frame.origin;
      bodies.pop_back();
      for (int k = 0; k < 3; ++k) {  // three bricks 0.3 m high at x in [3, 3.2]
        RBodyDef brick;
        brick.shape = RShape::Box(RVec3(0.1, 0.15, 1));
        brick.position_W = frame.R * RVec3(3.1, 0.15 + 0.3 * k, 0) + frame.origin;
        brick.q_WS = RQuat(frame.R);
        bodies.emplace_back(Immovable(brick, c));
      }
      bodies.emplace_back(box);
      RIntegrator integrator;
      SetGravity(integrator, c);
      integrator.Settings().shortcuts.sleeping = false;
      for (int k = 0; k < 60; ++k) {
        integrator.Update(bodies, kDt);
        front = std::max(front, (frame.R.transpose() * (bodies.back().Position_W() - frame.origin)).x() + 0.3);
      }
      const int which = tiles == Tiles::kBoxes ? 0 : 1;
      end[which] = bodies.back().Position_W(), velocity[which] = frame.R.transpose() * bodies.back().Velocity_W();
    }
    std::printf("box into a wall of three bricks (%s): front at most at x = %.4f m, v (%.2e, %.2e) m/s, "
                "from the one floor's %.1e m\n",
                frame.name, front, velocity[0].x(), velocity[0].y(), (end[0] - end[1]).norm());
    EXPECT_LT((end[0] - end[1]).norm(), 1e-9) << frame.name;
    EXPECT_LT(front, 3.2) << frame.name;
    EXPECT_LT(velocity[0].x(), 0) << frame.name;
    EXPECT_LT(velocity[0].norm(), 5) << frame.name;
  }
}

// The rule runs after the sweep's tasks are joined, in the contacts' order: forty bodies of
// every shape crossing a grid of 144 tiles in all directions move bit for bit the same on
// 1, 2 and 4 threads (the sweep then cuts its pairs into several tasks).
TEST(Seams, TheSameOnAnyNumberOfThreads) {
  auto world = [] {
    Crossing c;
    c.grid = true, c.tileYaw = 0.3, c.tileCount = 10;
    RScalar height = 0;
    RVec3 w0;
    std::vector<RRigidBody> bodies = SeamScene(c, 0, height, w0);
    bodies.pop_back();
    for (int k = 0; k < 40; ++k) {
      c.mover = kMovers[k % kMovers.size()];
      const RScalar a = 0.7 * k;
      c.speed = 2 + k % 5;
      c.frame.R = Eigen::AngleAxisd(a, RVec3::UnitY()).toRotationMatrix();
      c.frame.origin = RVec3(1 + 0.9 * (k % 7), 0, -3 + 0.9 * (k / 7));
      bodies.emplace_back(MoverDef(c, 0, height, w0));
    }
    return bodies;
  };
  std::vector<RRigidBody> one = world(), two = world(), four = world();
  RIntegrator a, b, c;
  for (RIntegrator* in : {&a, &b, &c}) in->Settings().gravity_W = RVec3(0, -9.81, 0);
  a.Settings().threads = 1, b.Settings().threads = 2, c.Settings().threads = 4;
  for (int step = 0; step < 60; ++step) {
    a.Update(one, kDt), b.Update(two, kDt), c.Update(four, kDt);
    for (std::size_t k = 0; k < one.size(); ++k) {
      ASSERT_EQ(one[k].Position_W(), two[k].Position_W()) << "step " << step << " body " << k;
      ASSERT_EQ(one[k].Position_W(), four[k].Position_W()) << "step " << step << " body " << k;
      ASSERT_EQ(one[k].Velocity_W(), four[k].Velocity_W()) << "step " << step << " body " << k;
    }
  }
}
