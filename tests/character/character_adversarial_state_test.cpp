// One-way bodies, determinism and copies, large floors, sills, steep ground.
// Adversarial cases of RCharacter's promises (RCharacter.h), against closed forms: each
// case is one a controller commonly gets wrong.
#include <gtest/gtest.h>

#include "character/CharacterAdversary.h"

#include <algorithm>
#include <cstring>
#include <random>

using namespace REngine;
using namespace REngine::test;

namespace {

// ---------- one-way ------------------------------------------------------------------------------

RBodyHandle OneWay(CharacterWorld& w, const RVec3& half, const RVec3& c, RBodyKind kind = RBodyKind::kStatic,
                   const RQuat& q = RQuat::Identity()) {
  RBodyDef d;
  d.shape = RShape::Box(half);
  d.kind = kind;
  d.position_W = c;
  d.q_WS = q;
  d.oneWay = true;
  return w.bodies.Add(d);
}

TEST(CharacterAdversarial, OneWayHoldsFastLandings) {
  for (RScalar v : {10.0, 1e3, 1e5}) {
    for (RScalar vx : {0.0, 5.0}) {
      for (const RCharacterDef& def0 : {Capsule(), BoxChar(), CylChar()}) {
        CharacterWorld w;
        Big(w, 200);
        const RBodyHandle p = OneWay(w, RVec3(40, 0.005, 40), RVec3(0, 2, 0));  // 1 cm thick, top 2.005
        RCharacterDef def = def0;
        def.position_W = RVec3(0, 30, 0);
        RCharacter c(def);
        c.SetVelocity(RVec3(0, -v, 0));
        c.SetDesiredVelocity(RVec3(vx, 0, 0));
        for (int k = 0; k < 200; ++k) w.Step({&c});
        EXPECT_TRUE(c.OnGround());
        EXPECT_EQ(c.Ground().contact.body, p) << "v " << v << " vx " << vx << " shape " << int(def.shape.type)
                                              << " y " << c.Position_W().y();
        EXPECT_NEAR(c.Position_W().y(), 2.005 + HalfHeight(def) + kOff, 1e-6) << "v " << v << " vx " << vx;
      }
    }
  }
}

TEST(CharacterAdversarial, OneWayJumpThroughThickAndLandBack) {
  for (RScalar jump : {4.0, 6.5, 9.0, 300.0}) {
    CharacterWorld w;
    Big(w, 900);
    const RBodyHandle p = OneWay(w, RVec3(3, 0.5, 3), RVec3(0, 2.5, 0));  // 1 m thick, y 2 .. 3
    RCharacter c(Capsule());
    w.Step({&c}, 20);
    c.Jump(jump);
    bool onTop = false;
    for (int k = 0; k < 60 * 70; ++k) {
      w.Step({&c});
      ASSERT_TRUE(Finite(c.Position_W()));
      if (c.OnGround() && k > 2) { onTop = c.Ground().contact.body == p; break; }
    }
    // The feet (y - 0.9) rise above 3 when v^2/2g > 3 - 0.001 + ... : then it lands on top.
    const bool clears = jump * jump / (2 * kG) > 3.0 + 0.01;
    EXPECT_EQ(onTop, clears) << "jump " << jump << " y " << c.Position_W().y();
    if (clears) EXPECT_NEAR(c.Position_W().y(), 3 + 0.9 + kOff, 1e-6) << jump;
    else EXPECT_NEAR(c.Position_W().y(), 0.9 + kOff, 1e-6) << jump;
  }
}

// Standing on a kinematic platform that descends at a constant 1 m/s (and turns): it is ground
// all the time (no acceleration at all), its place on it is kept, and a jump is honoured.
TEST(CharacterAdversarial, DescendingPlatformIsGround) {
  for (bool oneWay : {false, true}) {
    for (RScalar spin : {0.0, 0.5}) {
      CharacterWorld w;
      const RBodyHandle e = oneWay ? OneWay(w, RVec3(3, 0.1, 3), RVec3(0, 2, 0), RBodyKind::kKinematic)
                                   : w.Box(RVec3(3, 0.1, 3), RVec3(0, 2, 0), RBodyKind::kKinematic);
      RCharacterDef def = Capsule();
      def.position_W = RVec3(1.5, 2.1 + 0.9 + 0.01, 0.2);
      RCharacter c(def);
      w.Step({&c}, 20);
      ASSERT_TRUE(c.OnGround());
      w.bodies[e].SetVelocity_W(RVec3(0, -1, 0));
      w.bodies[e].SetAngularVelocity_W(RVec3(0, spin, 0));
      const auto local = [&] {
        const RRigidBody& d = w.bodies[e];
        return RVec3(d.Orientation_WB().conjugate() * (c.Position_W() - d.Position_W()));
      };
      const RVec3 place = local();
      RScalar drift = 0;
      int off = 0;
      for (int k = 0; k < 60; ++k) {
        w.Step({&c});
        off += !c.OnGround();
        drift = std::max(drift, (local() - place).norm());
      }
      EXPECT_EQ(off, 0) << "oneWay " << oneWay << " spin " << spin << ": updates not on ground of 60";
      EXPECT_LT(drift, 1e-6) << "oneWay " << oneWay << " spin " << spin;
      // Jumps: 4 asked, on consecutive updates' boundaries; each should launch.
      int launched = 0;
      for (int j = 0; j < 4; ++j) {
        for (int pad = 0; pad <= j; ++pad) w.Step({&c});  // 1..4 updates between tries
        const RScalar before = local().y();
        c.Jump(3);
        w.Step({&c});
        if (local().y() > before + 1e-3) ++launched;
        for (int k = 0; k < 60 && !(k > 2 && c.OnGround()); ++k) w.Step({&c});
      }
      EXPECT_EQ(launched, 4) << "oneWay " << oneWay << " spin " << spin;
    }
  }
}

// A one-way ramp (walkable) walked onto from its foot: held by its top face.
TEST(CharacterAdversarial, OneWaySideWalkThrough) {
  CharacterWorld w;
  Big(w, 20);
  OneWay(w, RVec3(0.5, 0.5, 3), RVec3(2, 0.5, 0));  // a 1 m one-way block on the floor
  RCharacter c(Capsule());
  w.Step({&c}, 20);
  c.SetDesiredVelocity(RVec3(2, 0, 0));
  RScalar se = 0;
  for (int k = 0; k < 120; ++k) {
    const RVec3 b = c.Position_W();
    w.Step({&c});
    se = std::max(se, std::abs((c.Position_W() - b).x() / kDt - 2));
  }
  EXPECT_LE(se, 1e-9);  // walks straight through it at the command
  EXPECT_NEAR(c.Position_W().y(), 0.9 + kOff, 1e-6);
}

// ---------- determinism and copies ------------------------------------------------------------

struct Scene {
  CharacterWorld w;
  RBodyHandle deck;
  explicit Scene(bool tree = true) {
    w.queries.SetSettings(RQueries::RSettings{tree});
    Big(w, 30);
    deck = w.Box(RVec3(2, 0.1, 2), RVec3(5, 0.1, 0), RBodyKind::kKinematic);
    w.bodies[deck].SetAngularVelocity_W(RVec3(0, 0.9, 0));
    w.bodies[deck].SetVelocity_W(RVec3(0, 0, 0.3));
    w.Box(RVec3(0.3, 0.125, 0.3), RVec3(2, 0.125, 1));
    w.Box(RVec3(0.005, 1, 3), RVec3(8, 1, 0));
    OneWay(w, RVec3(1, 0.05, 1), RVec3(3, 1.2, -1));
    for (int i = 0; i < 5; ++i) w.Box(RVec3(0.25, 0.25, 0.25), RVec3(1 + 0.6 * i, 0.26, -2), RBodyKind::kDynamic);
  }
};

void Command(RCharacter& c, int k) {
  c.SetDesiredVelocity(RVec3(2 * std::cos(0.02 * k), 0, 1.5 * std::sin(0.031 * k)));
  if (k % 53 == 7) c.Jump(4.5);
}

std::vector<RVec3> RunScene(bool tree, int threads, int steps, RCharacterDef def) {
  Scene s(tree);
  s.w.integrator.Settings().threads = threads;
  RCharacter c(def);
  std::vector<RVec3> out;
  for (int k = 0; k < steps; ++k) {
    Command(c, k);
    s.w.Step({&c});
    out.push_back(c.Position_W());
  }
  return out;
}

TEST(CharacterAdversarial, DeterministicAcrossRunsTreeAndThreads) {
  for (const RCharacterDef& def : {Capsule(), BoxChar(), CylChar()}) {
    const auto a = RunScene(true, 1, 400, def), b = RunScene(true, 1, 400, def), t = RunScene(false, 1, 400, def),
               m = RunScene(true, 2, 400, def);
    for (std::size_t k = 0; k < a.size(); ++k) {
      ASSERT_EQ(std::memcmp(a[k].data(), b[k].data(), sizeof(RVec3)), 0) << "run twice, update " << k;
      ASSERT_EQ(std::memcmp(a[k].data(), t[k].data(), sizeof(RVec3)), 0) << "tree vs loop, update " << k;
      ASSERT_EQ(std::memcmp(a[k].data(), m[k].data(), sizeof(RVec3)), 0) << "2 threads, update " << k;
    }
  }
}

TEST(CharacterAdversarial, CopiesContinueBitForBit) {
  for (const RCharacterDef& def : {Capsule(), BoxChar(), CylChar()}) {
    for (int at : {50, 140, 211}) {
      // Two identical worlds stepped in lockstep; the copy lives in the second.
      Scene s1, s2;
      RCharacter c(def);
      for (int k = 0; k < at; ++k) {
        Command(c, k);
        s1.w.Step({&c});
        s2.w.integrator.Update(s2.w.bodies, kDt);
      }
      RCharacter d = c;                  // copy-construct
      RCharacter e(SphereChar());        // copy-assign over a different character
      e = c;
      Scene s3;
      for (int k = 0; k < at; ++k) s3.w.integrator.Update(s3.w.bodies, kDt);
      // s3 lacks c's impulses on the crates: only compare c vs d (s1 vs s2 got the same? no: s2 lacks them too)
      for (int k = at; k < at + 200; ++k) {
        Command(c, k), Command(d, k), Command(e, k);
        s1.w.Step({&c});
        s2.w.Step({&d});
        s3.w.Step({&e});
        ASSERT_EQ(std::memcmp(d.Position_W().data(), e.Position_W().data(), sizeof(RVec3)), 0)
            << "copy-constructed vs copy-assigned, shape " << int(def.shape.type) << " at " << at << " update " << k;
      }
    }
  }
}

// Copies stepped in the same world, without dynamic bodies (so neither affects the other).
TEST(CharacterAdversarial, CopiesInTheSameWorld) {
  for (const RCharacterDef& def : {Capsule(), BoxChar(), CylChar()}) {
    CharacterWorld w;
    Big(w, 30);
    const RBodyHandle deck = w.Box(RVec3(2, 0.1, 2), RVec3(5, 0.1, 0), RBodyKind::kKinematic);
    w.bodies[deck].SetAngularVelocity_W(RVec3(0, 0.9, 0));
    w.Box(RVec3(0.3, 0.125, 0.3), RVec3(2, 0.125, 1));
    const RBodyHandle kw = w.Box(RVec3(0.1, 1, 1), RVec3(-2, 1, 0), RBodyKind::kKinematic);
    w.bodies[kw].SetVelocity_W(RVec3(0.4, 0, 0));
    RCharacter c(def);
    for (int k = 0; k < 120; ++k) { Command(c, k); w.Step({&c}); }
    RCharacter d = c;
    for (int k = 120; k < 400; ++k) {
      Command(c, k), Command(d, k);
      w.Step({&c, &d});
      ASSERT_EQ(std::memcmp(c.Position_W().data(), d.Position_W().data(), sizeof(RVec3)), 0) << int(def.shape.type) << " " << k;
    }
  }
}


// ---------- more -----------------------------------------------------------------------------

// Large floors (an ocean plane): the cast's touching band grows with the body's size.
TEST(CharacterAdversarial, LargeFloors) {
  for (auto [half, off0] : {std::pair{1e3, 1e-3}, {1e4, 1e-3}, {1e5, 1e-3}, {1e6, 1e-3}, {1e4, 1e-5}, {3e3, 1e-6}}) {
    for (RCharacterDef def : {Capsule(), BoxChar()}) {
      def.contactOffset = off0;
      const RScalar kOff = off0;
      CharacterWorld w;
      w.Box(RVec3(half, half * 1.5e-4, half), RVec3(0, -half * 1.5e-4, 0));
      RCharacter c(def);
      w.Step({&c}, 30);
      EXPECT_TRUE(c.OnGround()) << "half " << half << " shape " << int(def.shape.type) << " gap "
                                << c.Position_W().y() - HalfHeight(def);
      EXPECT_NEAR(c.Position_W().y() - HalfHeight(def), kOff, 1e-6) << "half " << half << " shape " << int(def.shape.type);
      c.SetDesiredVelocity(RVec3(3, 0, 1));
      RScalar se = 0;
      int off = 0;
      for (int k = 0; k < 60; ++k) {
        const RVec3 b = c.Position_W();
        w.Step({&c});
        se = std::max(se, ((c.Position_W() - b) / kDt - RVec3(3, 0, 1)).cwiseProduct(RVec3(1, 0, 1)).norm());
        off += !c.OnGround();
      }
      EXPECT_LE(se, 1e-9) << "half " << half << " offset " << off0 << " shape " << int(def.shape.type);
      EXPECT_EQ(off, 0) << "half " << half << " shape " << int(def.shape.type);
    }
  }
}

// A dynamic crate slides (frictionless) into the character standing against a 1 cm static wall.
TEST(CharacterAdversarial, CrateShovesItAgainstAThinWall) {
  for (RScalar v : {3.0, 15.0}) {
    CharacterWorld w;
    RBodyDef floor;
    floor.shape = RShape::Box(RVec3(20, 0.1, 20));
    floor.kind = RBodyKind::kStatic;
    floor.position_W = RVec3(0, -0.1, 0);
    floor.friction = 0;
    w.bodies.Add(floor);
    w.Box(RVec3(0.005, 2, 3), RVec3(1.005, 2, 0));  // face at x = 1
    RBodyDef crate;
    crate.shape = RShape::Box(RVec3(0.4, 0.4, 0.4));
    crate.mass = 500;
    crate.friction = 0;
    crate.position_W = RVec3(-3, 0.401, 0);
    crate.velocity_W = RVec3(v, 0, 0);
    w.bodies.Add(crate);
    RCharacterDef def = Capsule();
    def.position_W = RVec3(0.699, 0.91, 0);
    RCharacter c(def);
    RScalar worst = -1e9;
    for (int k = 0; k < 120; ++k) {
      w.Step({&c});
      ASSERT_TRUE(Finite(c.Position_W()));
      worst = std::max(worst, c.Position_W().x() - (1 - 0.3));
    }
    EXPECT_LE(worst, 1e-9) << "v " << v << " final x " << c.Position_W().x();
  }
}

// Walking into a wedge between the floor and a thin ceiling sloping down (under a staircase).
TEST(CharacterAdversarial, UnderASlopingThinCeiling) {
  for (RScalar speed : {2.0, 100.0, 1e5}) {
    for (RScalar deg : {10.0, 30.0}) {
      CharacterWorld w;
      Big(w, 30);
      const RScalar a = deg * M_PI / 180;
      // A slab whose lower face is the plane through (6, 0, 0) rising towards -x at angle a.
      const RVec3 n(-std::sin(a), -std::cos(a), 0);  // the lower face's normal (down, towards -x)
      const RVec3 along(-std::cos(a), std::sin(a), 0);
      const RQuat q(Eigen::AngleAxisd(-a, RVec3::UnitZ()));
      w.Box(RVec3(10, 0.005, 3), RVec3(6, 0, 0) + along * 10 - n * 0.005, RBodyKind::kStatic, q);
      RCharacter c(Capsule());
      w.Step({&c}, 20);
      c.SetDesiredVelocity(RVec3(speed, 0, 0));
      RScalar worst = 1e9;
      for (int k = 0; k < 120; ++k) {
        w.Step({&c});
        ASSERT_TRUE(Finite(c.Position_W()));
        // The capsule's top sphere centre (y + 0.3) must stay 0.3 below the ceiling plane; its axis above the floor.
        const RVec3 top = c.Position_W() + RVec3(0, 0.3, 0);
        worst = std::min(worst, (top - RVec3(6, 0, 0)).dot(n) - 0.3);
        worst = std::min(worst, c.Position_W().y() - 0.9);
      }
      EXPECT_GE(worst, -1e-9) << "speed " << speed << " deg " << deg << " pos " << c.Position_W().transpose();
    }
  }
}


// A door sill: 0.1 m high, 5 cm deep, across the way at x = 1 .. 1.05. Any speed should get over it.
TEST(CharacterAdversarial, DoorSillAtSpeed) {
  for (const RCharacterDef& def : {Capsule(), BoxChar(), CylChar()}) {
    for (RScalar speed : {1.0, 6.0, 20.0, 60.0}) for (RScalar x0 : {0.0, -0.25, -0.5, -0.75}) {
      CharacterWorld w;
      Big(w, 300);
      w.Box(RVec3(0.025, 0.05, 20), RVec3(1.025, 0.05, 0));
      RCharacterDef d2 = def;
      d2.position_W.x() = x0;
      RCharacter c(d2);
      w.Step({&c}, 20);
      c.SetDesiredVelocity(RVec3(speed, 0, 0));
      for (int k = 0; k < int(5 / speed / kDt); ++k) w.Step({&c});
      EXPECT_GT(c.Position_W().x(), 3) << "shape " << int(def.shape.type) << " speed " << speed << " x0 " << x0 << " stuck at x "
                                       << c.Position_W().x();
    }
  }
}






// On steep ground (OnGround() false: kOnSteepGround) a jump should be dropped, as in the air.
TEST(CharacterAdversarial, NoJumpFromSteepGround) {
  CharacterWorld w;
  Big(w, 30);
  const RScalar a = 60 * M_PI / 180;
  // A 60-degree slope rising towards +x, its surface through the origin.
  const RVec3 n(-std::sin(a), std::cos(a), 0);
  w.Box(RVec3(10, 0.5, 5), RVec3(0, 0, 0) - n * 0.5, RBodyKind::kStatic, RQuat(Eigen::AngleAxisd(a, RVec3::UnitZ())));
  RCharacterDef def = Capsule();
  def.position_W = RVec3(1, 0.6 / std::cos(a) + std::tan(a) * 1 + 0.3 + 0.01, 0);
  def.position_W = RVec3(0, 0, 0) + n * (0.3 + 0.002) + RVec3(0, 0.6, 0) + RVec3(std::cos(a), std::sin(a), 0) * 2.0;
  RCharacter c(def);
  int steepSeen = 0, launched = 0;
  for (int k = 0; k < 60; ++k) {
    if (c.Ground().state == RGroundState::kOnSteepGround) {
      ++steepSeen;
      const RScalar before = c.Velocity_W().y();
      c.Jump(6);
      w.Step({&c});
      if (c.Velocity_W().y() > before + 3) ++launched;
    } else {
      w.Step({&c});
    }
  }
  // Spam jumps while pressing up the slope: does it climb the (unwalkable) 60-degree slope?
  RCharacter d(def);
  d.SetDesiredVelocity(RVec3(3, 0, 0));
  RScalar top = -1e9;
  for (int k = 0; k < 600; ++k) {
    if (d.Ground().state == RGroundState::kOnSteepGround) d.Jump(6);
    w.Step({&d});
    top = std::max(top, d.Position_W().y());
  }
  EXPECT_LT(d.Position_W().y(), def.position_W.y()) << "climbed a 60-degree slope by jumping";
  EXPECT_GT(steepSeen, 0);
  EXPECT_EQ(launched, 0);
}

}  // namespace
