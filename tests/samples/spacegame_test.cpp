// rengine-spacegame's logic, without a display: what the game does, asserted against
// the physics. A missile leaves through its own launcher's hull without touching it, and
// goes off on its first contact with anything else; a laser gives the rock it names exactly
// the beam's impulse (linear and angular); the dock's weld holds the ship on the spinning
// station; debris comes to rest in the cargo bay and sleeps; the autoplay repeats to the bit;
// and all of it 1e6 m from the origin.
#include <REnginePhysics/RContactEvents.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include "Autoplay.h"
#include "Game.h"
#include "StateHash.h"

#include "support/CountingNew.h"  // this binary's operator new counts allocations

using namespace spacegame;
using namespace REngine;

namespace {

bool Touches(const RContactEvent& e, RBodyHandle a, RBodyHandle b) {
  return (e.handleA == a && e.handleB == b) || (e.handleA == b && e.handleB == a);
}

// A rock of a size class placed `ahead` m along the ship's nose line, `side` m off it
// (along the ship's x), at rest.
RBodyHandle RockAhead(SpaceWorld& world, int size, double ahead, double side = 0) {
  const RRigidBody& ship = world.Bodies()[world.Ship()];
  const RQuat q = ship.ShapeOrientation_WS();
  const RVec3 p = ShipNose_W(world) + ahead * (q * RVec3::UnitZ()) + side * (q * RVec3::UnitX());
  return world.AddAsteroid(size, 0, p, RQuat::Identity(), RVec3::Zero(), RVec3::Zero());
}

}  // namespace

TEST(SpaceGame, TheWorldLivesNearAMillionMetres) {
  SpaceWorld world;
  for (const RRigidBody& b : world.Bodies()) EXPECT_GT(b.Position_W().norm(), 1e6);
  EXPECT_GT(world.Bodies().EnabledCount(), std::size_t(40));
}

// The missile starts at the ship's centre, deep inside its hull, and drifts out at 1 m/s:
// for 2 s no event and no contact names the pair, and the missile does not go off. The same
// capsule put there without the ignore (the control) reports a begin in the first step.
TEST(SpaceGame, AMissileSpawnedInsideItsLauncherNeverTouchesIt) {
  SpaceWorld world;
  MissileTuning slow;
  slow.launchSpeed = 1, slow.motorForce = 0;
  Missiles missiles(world, 2, 8, slow);
  const RBodyHandle ship = world.Ship();
  const RVec3 centre = world.Bodies()[ship].Position_W();
  const RBodyHandle missile = missiles.Fire(ship, centre, ShipForward_W(world));
  ASSERT_TRUE(missile.IsValid());

  RBodyDef control;
  control.restitution = 0.5;
  control.prepared = world.Shapes().missile;
  control.mass = 200;
  control.responds = false;
  control.gravityScale = 0;
  control.position_W = centre + RVec3(0, 0.2, 0);
  const RBodyHandle unguarded = world.Bodies().Add(control);
  world.Bodies().IgnoreCollisions(unguarded, missile);  // it is there to touch the ship alone

  int missileEvents = 0, controlEvents = 0, missileContacts = 0;
  for (int s = 0; s < 120; ++s) {
    missiles.BeforeStep();
    world.Step();
    for (const RContactEvent& e : world.Integrator().Events()) {
      missileEvents += Touches(e, missile, ship);
      controlEvents += Touches(e, unguarded, ship);
    }
    for (const RContact& c : world.Integrator().Contacts())
      missileContacts += (c.handleA == missile && c.handleB == ship) ||
                         (c.handleA == ship && c.handleB == missile);
    missiles.AfterStep();
    if (s == 0) world.Bodies().Remove(unguarded);  // the control has made its point
  }
  EXPECT_GT(controlEvents, 0) << "the control capsule inside the hull must report a contact";
  EXPECT_EQ(missileEvents, 0);
  EXPECT_EQ(missileContacts, 0);
  EXPECT_EQ(missiles.ExplosionCount(), 0u);
  EXPECT_TRUE(world.Bodies().IsEnabled(missile));
  // It did leave the hull: 2 s at 1 m/s, beyond the hull's nose from the centre.
  EXPECT_GT((world.Bodies()[missile].Position_W() - centre).norm(), 1.9);
}

// Fired from inside the ship at a rock 60 m ahead: it goes off in the very step whose events
// hold its first begin with the rock, and with nothing before; it is parked, the rock is
// pushed away from the blast, and debris flies out from it.
TEST(SpaceGame, AMissileExplodesOnItsFirstContactWithSomethingElse) {
  SpaceWorld world;
  Missiles missiles(world);
  const RBodyHandle rock = RockAhead(world, 1, 60);
  const RVec3 fwd = ShipForward_W(world);
  const RBodyHandle missile = missiles.Fire(world.Ship(), ShipNose_W(world) - 2 * fwd, fwd);
  ASSERT_TRUE(missile.IsValid());
  const RVec3 rockV0 = world.Bodies()[rock].Velocity_W();

  std::uint64_t firstBegin = 0;
  for (int s = 0; s < 300 && missiles.ExplosionCount() == 0; ++s) {
    missiles.BeforeStep();
    world.Step();
    for (const RContactEvent& e : world.Integrator().Events()) {
      const bool withMissile = e.handleA == missile || e.handleB == missile;
      if (withMissile && e.type == RContactEventType::kBegin && firstBegin == 0) {
        firstBegin = world.Integrator().StepCount();
        EXPECT_TRUE(Touches(e, missile, rock)) << "its first contact is the rock";
      }
    }
    missiles.AfterStep();
  }
  ASSERT_EQ(missiles.ExplosionCount(), 1u);
  const Explosion& x = missiles.LastExplosions().at(0);
  EXPECT_EQ(x.step, firstBegin);
  EXPECT_EQ(x.hit, rock);
  EXPECT_FALSE(world.Bodies().IsEnabled(missile));
  // The blast reaches the rock in the next step: away from the point it went off at.
  world.Step();
  const RRigidBody& r = world.Bodies()[rock];
  const RVec3 away = (r.Position_W() - x.point_W).normalized();
  EXPECT_GT((r.Velocity_W() - rockV0).dot(away), 0.1);
  int debris = 0;
  for (const RRigidBody& b : world.Bodies())
    debris += RoleOf(b) == Role::kDebris && (b.Position_W() - x.point_W).norm() < 30;
  EXPECT_EQ(debris, missiles.Tuning().debrisPerBlast);
}

// The beam plays on a small rock 100 m ahead, 1.5 m off its centre: after the step the rock's
// velocity has changed by J/m and its angular momentum about its centre by (p - x) x J, to
// rounding (nothing else touches it, and free motion keeps both).
TEST(SpaceGame, ALaserHitGivesTheRockItNamesTheBeamsImpulse) {
  SpaceWorld world;
  Lasers lasers(world);
  const RBodyHandle rock = RockAhead(world, 0, 100, 1.5);
  const RRigidBody& r = world.Bodies()[rock];
  const RVec3 x0 = r.Position_W(), v0 = r.Velocity_W(), L0 = r.AngularMomentum_W();

  const std::optional<LaserHit> hit = lasers.FireFromShip();
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->body, rock);
  const RVec3 J = hit->impulse_W;
  EXPECT_NEAR(J.norm(), lasers.Tuning().force * world.StepDt(), 1e-9);
  world.Step();

  const RVec3 dv = r.Velocity_W() - v0, dvWant = J / r.Mass();
  const RVec3 dL = r.AngularMomentum_W() - L0, dLWant = (hit->point_W - x0).cross(J);
  std::printf("laser: |dv| %.6e m/s, error %.2e; |dL| %.6e kg m^2/s, error %.2e\n", dv.norm(),
              (dv - dvWant).norm(), dL.norm(), (dL - dLWant).norm());
  EXPECT_LT((dv - dvWant).norm(), 1e-12 * dvWant.norm());
  EXPECT_GT(dLWant.norm(), 0.5 * J.norm());  // a real lever arm
  EXPECT_LT((dL - dLWant).norm(), 1e-9 * dLWant.norm());
}

// A big rock under the beam long enough splits into two of the next size down.
TEST(SpaceGame, ALaserSplitsABigRock) {
  SpaceWorld world;
  Lasers lasers(world);
  const RBodyHandle rock = RockAhead(world, 2, 120);
  const std::size_t before = world.Bodies().EnabledCount();
  bool split = false;
  for (int s = 0; s < 240 && !split; ++s) {
    const std::optional<LaserHit> hit = lasers.FireFromShip();
    ASSERT_TRUE(hit.has_value());
    split = hit->split;
    world.Step();
  }
  EXPECT_TRUE(split);
  EXPECT_FALSE(world.Bodies().Contains(rock));
  EXPECT_EQ(world.Bodies().EnabledCount(), before + 1);
  EXPECT_EQ(lasers.Splits(), 1u);
}

// Welded at a port on the ring (45 m out, carried at 4.5 m/s round the axis) for 20 s, two
// radians of the station's turn: the ship stays on the port's pose.
TEST(SpaceGame, DockingHoldsTheShipOnTheSpinningStation) {
  SpaceWorld world;
  Docking dock(world);
  EXPECT_FALSE(dock.TryDock()) << "the ship starts beyond the capture distance";
  dock.DockAt(1);
  ASSERT_TRUE(dock.IsDocked());
  const RRigidBody& ship = world.Bodies()[world.Ship()];
  double worstPosition = 0, worstAngle = 0;
  for (int s = 0; s < 1200; ++s) {
    world.Step();
    worstPosition =
        std::max(worstPosition, (ship.ShapePosition_W() - dock.PortPosition_W(1)).norm());
    worstAngle =
        std::max(worstAngle, ship.ShapeOrientation_WS().angularDistance(dock.PortOrientation_W(1)));
  }
  const RRigidBody& station = world.Bodies()[world.Station()];
  const double turned =
      2 * std::atan2(station.ShapeOrientation_WS().vec().norm(), station.ShapeOrientation_WS().w());
  std::printf(
      "docked 20 s: station turned %.4f rad; ship off its port by at most %.2e m, %.2e rad\n",
      turned, worstPosition, worstAngle);
  EXPECT_NEAR(turned, 2.0, 1e-9);
  EXPECT_LT(worstPosition, 1e-3);
  EXPECT_LT(worstAngle, 1e-4);
  // Undocked, it leaves the port.
  dock.Undock();
  for (int s = 0; s < 60; ++s) world.Step();
  EXPECT_GT((ship.ShapePosition_W() - dock.PortPosition_W(1)).norm(), 1.0);
}

// Close to the hub's port and slow, the clamp takes the ship; far, it does not.
TEST(SpaceGame, TheClampTakesAShipOnlyWithinReach) {
  SpaceWorld world;
  Docking dock(world);
  RRigidBody& ship = world.Bodies()[world.Ship()];
  ship.SetShapePose(dock.PortPosition_W(0) + RVec3(0, 10, 3), RQuat::Identity());
  ship.SetVelocity_W(RVec3(0, -8, 0));
  EXPECT_FALSE(dock.TryDock()) << "too fast";
  ship.SetVelocity_W(RVec3(0, -2, 0));
  EXPECT_TRUE(dock.TryDock());
  EXPECT_EQ(dock.DockedPort(), 0);
}

// A missile fired down into the cargo bay goes off on a crate; the debris that stays in the
// bay falls to its floor (the bay's gravity) and sleeps there.
TEST(SpaceGame, DebrisComesToRestInTheBayAndSleeps) {
  SpaceWorld world;
  Missiles missiles(world);
  const RVec3 O = world.Config().origin_W;
  const RVec3 above = O + RVec3(-6, GameShapes::kBayY + 12, -4);  // over the first crate
  ASSERT_TRUE(missiles.Fire(world.Station(), above, RVec3(0, -1, 0)).IsValid());
  for (int s = 0; s < 600; ++s) {
    missiles.BeforeStep();
    world.Step();
    missiles.AfterStep();
    world.UpdateBayGravity();
  }
  EXPECT_EQ(missiles.ExplosionCount(), 1u);
  int inBay = 0, asleep = 0;
  for (const RRigidBody& b : world.Bodies()) {
    if (RoleOf(b) != Role::kDebris || !world.InBay(b.Position_W())) continue;
    ++inBay;
    asleep += b.IsSleeping();
  }
  std::printf("bay: %d pieces of debris in the bay, %d asleep\n", inBay, asleep);
  EXPECT_GE(inBay, 3);
  EXPECT_EQ(asleep, inBay);
}

// The yaw thrusters are a couple, forces at the nose and the tail: one step of them leaves
// the ship's momentum as it was and adds the couple's angular impulse, 2 arm F dt about the
// ship's up axis (free motion keeps the world angular momentum between the half kicks).
TEST(SpaceGame, TheAttitudeThrustersTurnTheShipWithoutPushingIt) {
  SpaceWorld world;
  const RRigidBody& ship = world.Bodies()[world.Ship()];
  const RVec3 p0 = ship.Mass() * ship.Velocity_W(), L0 = ship.AngularMomentum_W();
  const RVec3 up = ship.ShapeOrientation_WS() * RVec3::UnitY();
  ShipInput yaw;
  yaw.yaw = 1;
  const ShipTuning t;
  ApplyShipControl(world, yaw, t);
  world.Step();
  const RVec3 dp = ship.Mass() * ship.Velocity_W() - p0, dL = ship.AngularMomentum_W() - L0;
  const RVec3 want = 2 * t.rcsArm * t.rcsThrust * world.StepDt() * up;
  std::printf("yaw couple: |dp| %.2e kg m/s, |dL - 2 a F dt| %.2e of %.4e kg m^2/s\n", dp.norm(),
              (dL - want).norm(), want.norm());
  EXPECT_LT(dp.norm(), 1e-9 * ship.Mass());
  EXPECT_LT((dL - want).norm(), 1e-9 * want.norm());
}

// The loop: frames of 1/144 s for one second take 60 fixed steps, and between steps the
// ship is drawn part-way from its pose before the last step to its pose after it.
TEST(SpaceGame, TheLoopStepsAtTheFixedDtAndDrawsBetweenSteps) {
  Game game;
  ShipInput in;
  in.thrust = 1;
  std::size_t shipDense = 0;
  const RBodies& bodies = game.World().Bodies();
  while (bodies.HandleAt(shipDense) != game.World().Ship()) ++shipDense;
  RVec3 before = bodies[game.World().Ship()].ShapePosition_W();
  int checked = 0;
  for (int f = 0; f < 144; ++f) {
    const std::uint64_t steps = game.Timing().steps;
    const RVec3 last = bodies[game.World().Ship()].ShapePosition_W();
    game.Frame(1.0 / 144, in);
    if (game.Timing().steps != steps) before = last;
    RVec3 drawn;
    RQuat q;
    game.DrawPose(shipDense, drawn, q);
    const RVec3 now = bodies[game.World().Ship()].ShapePosition_W();
    const RVec3 between = before + game.Alpha() * (now - before);
    EXPECT_LT((drawn - between).norm(), 1e-6);
    checked += game.Alpha() > 0.1 && (now - before).norm() > 1e-3;
  }
  EXPECT_EQ(game.Timing().steps, 60u);
  EXPECT_GT(checked, 50);
}

// The autoplay twice in one process: the same hash, and the state did change; and the hash
// gcc and clang both give (the world is drawn in a fixed order and the game's angles go
// through the engine's own functions), pinned as the scenes' are in cli_test.cpp.
TEST(SpaceGame, TheAutoplayRepeatsToTheBit) {
  std::uint64_t hashes[2];
  std::uint64_t start = 0;
  for (std::uint64_t& h : hashes) {
    Game game;
    start = HashState(game.World().Bodies());
    Autoplay script(game);
    for (int f = 0; f < 240; ++f) game.Frame(Autoplay::kFrameSeconds, script.Input(f, game));
    h = HashState(game.World().Bodies());
    std::printf("autoplay 240 frames: steps %llu, explosions %llu, splits %llu, hash=%s\n",
                static_cast<unsigned long long>(game.Timing().steps),
                static_cast<unsigned long long>(game.MissileSystem().ExplosionCount()),
                static_cast<unsigned long long>(game.LaserSystem().Splits()), HashHex(h).c_str());
    EXPECT_EQ(game.Timing().steps, 240u);
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_NE(hashes[0], start);
  EXPECT_EQ(HashHex(hashes[0]), "a63da13c75e9d7c8");
}

// The engine's promise through the game: the same autoplay on two threads ends on the same
// hash as on one (the step is bit-identical for any thread count).
TEST(SpaceGame, TheAutoplayIsTheSameOnTwoThreads) {
  std::uint64_t hashes[2];
  for (int threads = 1; threads <= 2; ++threads) {
    WorldConfig config;
    config.threads = threads;
    Game game(config);
    Autoplay script(game);
    for (int f = 0; f < 240; ++f) game.Frame(Autoplay::kFrameSeconds, script.Input(f, game));
    hashes[threads - 1] = HashState(game.World().Bodies());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

// Space games live far out: the autoplay played 1e6 m from the origin ends where it ends at
// the origin, relative to its station, every body within a small distance (what rounding
// 1e6 m out, ~1e-10 m a step, grows to through a laser, a missile and its debris).
TEST(SpaceGame, TheGameFarOutPlaysAsAtTheOrigin) {
  std::vector<RVec3> ends[2];
  const RVec3 origins[2] = {RVec3::Zero(), RVec3(1e6, 1e6, 1e6)};
  for (int k = 0; k < 2; ++k) {
    WorldConfig config;
    config.origin_W = origins[k];
    Game game(config);
    Autoplay script(game);
    for (int f = 0; f < 240; ++f) game.Frame(Autoplay::kFrameSeconds, script.Input(f, game));
    const RBodies& bodies = game.World().Bodies();
    for (std::size_t i = 0; i < bodies.EnabledCount(); ++i)
      ends[k].push_back(bodies.At(i).Position_W() - origins[k]);
  }
  ASSERT_EQ(ends[0].size(), ends[1].size());
  double worst = 0;
  for (std::size_t i = 0; i < ends[0].size(); ++i)
    worst = std::max(worst, (ends[0][i] - ends[1][i]).norm());
  std::printf("autoplay at 0 and at 1e6 m: %zu bodies, largest difference %.2e m\n", ends[0].size(),
              worst);
  EXPECT_LT(worst, 1e-3);
}

// No heap churn in the loop: after the first second, the autoplay's frames (thrusters, the
// laser on every step, a missile homing in and going off, debris thrown out) allocate nothing,
// but for the few where something first happens and a container grows (the step's contacts
// and events when the debris first touches, the queries' tree rebuilt for the bodies the
// blast enabled).
TEST(SpaceGame, TheLoopAllocatesOnlyWhileItsContainersGrow) {
  Game game;
  Autoplay script(game);
  for (int f = 0; f < 60; ++f) game.Frame(Autoplay::kFrameSeconds, script.Input(f, game));
  int allocatingFrames = 0;
  long total = 0;
  std::string which;  // frame:allocations
  for (int f = 60; f < 240; ++f) {
    const ShipInput in = script.Input(f, game);
    g_allocations = 0;
    g_countAllocations = true;
    game.Frame(Autoplay::kFrameSeconds, in);
    g_countAllocations = false;
    allocatingFrames += g_allocations > 0;
    if (g_allocations > 0) which += " " + std::to_string(f) + ":" + std::to_string(g_allocations);
    total += g_allocations;
  }
  std::printf("frames 60 to 240: %d of 180 allocated, %ld allocations in all (%s)\n",
              allocatingFrames, total, which.c_str());
  // Measured: 15 frames, most about the missile going off (frames 106 to 114: the blast, the
  // debris enabled, their first contacts), the second launch (150) and debris reaching rocks
  // (201 to 222).
  EXPECT_LE(allocatingFrames, 20);
}


// The walkable interior: through the autoplay the crew member walks round the turning ring
// with the spin as its gravity. Measured in the station's frame, where the ring stands still:
// each step moves it by exactly the commanded 1.5 m/s times dt across its up (carrying by the
// ring is its exact pose change, so nothing else moves it), and it stands on the floor of
// segment 0 (the plane x_S = 42.5, facing -x_S) at the capsule's height along up: its centre
// 0.3 + 0.001 + 0.6 cos(tilt) from the plane, tilt the angle between up and the floor's normal
// (the spin's up points at the axis, not square to a flat segment off its middle).
TEST(SpaceGame, TheAutoplayWalksTheCrewRoundTheTurningRing) {
  Game game;
  Autoplay script(game);
  const SpaceWorld& world = game.World();
  int onGround = 0, measured = 0;
  RVec3 last = game.CrewMember().InStation();
  for (int f = 0; f < 240; ++f) {
    game.Frame(Autoplay::kFrameSeconds, script.Input(f, game));
    const REngine::RCharacter& crew = game.CrewMember().Character();
    const RVec3 now = game.CrewMember().InStation();
    const RRigidBody& station = world.Bodies()[world.Station()];
    const RVec3 up_S = station.ShapeOrientation_WS().conjugate() * crew.Up_W();
    if (crew.OnGround()) {
      ++onGround;
      if (f > 30) {
        const RVec3 step = now - last;
        const RVec3 across = step - up_S * step.dot(up_S);
        // Rounding: positions 1e6 m from the origin carry 1e-10 m, a step's difference twice.
        EXPECT_NEAR(across.norm(), Autoplay::kCrewWalk * world.StepDt(), 1e-8) << f;
        const double tilt = std::acos(std::min(1.0, -up_S.x()));
        EXPECT_NEAR(42.5 - now.x(), 0.301 + 0.6 * std::cos(tilt), 1e-6) << f;
        ++measured;
      }
    }
    last = now;
  }
  EXPECT_GT(onGround, 200);
  EXPECT_GT(measured, 200);
  // Round the ring the way it turns (-z in the station's frame at +x): about 1.5 m/s for 4 s.
  EXPECT_LT(game.CrewMember().InStation().z(), -5.0);
}
