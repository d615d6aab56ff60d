// Thin walls at any speed and angle, carried and pushed, meshes.
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

// ---------- thin walls -----------------------------------------------------------------------

// Capsule walking in direction angle a (from +x toward +z) at `speed` into a thin wall at x in [2, 2.01].
TEST(CharacterAdversarial, ThinWallAnySpeedAnyAngle) {
  for (RScalar dt : {1.0 / 60, 1.0}) {
    for (RScalar speed : {1.0, 37.0, 1e3, 1e5, 1e6}) {
      for (RScalar adeg : {0.0, 10.0, 45.0, 80.0, 89.0, 89.99}) {
        CharacterWorld w;
        Big(w);
        w.Box(RVec3(0.005, 1, 20), RVec3(2.005, 1, 0));
        RCharacter c(Capsule());
        for (int k = 0; k < 30; ++k) c.Update(w.bodies, w.queries, 1.0 / 60, w.gravity);
        const RScalar a = adeg * M_PI / 180;
        c.SetDesiredVelocity(RVec3(std::cos(a), 0, std::sin(a)) * speed);
        RScalar worst = -1e9;
        for (int k = 0; k < 10; ++k) {
          const RVec3 b = c.Position_W();
          c.Update(w.bodies, w.queries, dt, w.gravity);
          const RVec3 e = c.Position_W();
          ASSERT_TRUE(Finite(e));
          if (e.x() > 1.7) {  // crossed the wall's plane: where?
            const RScalar t = (1.7 - b.x()) / (e.x() - b.x());
            const RScalar zc = b.z() + t * (e.z() - b.z());
            if (std::abs(zc) < 20.3) worst = std::max(worst, e.x() - 1.7);
          }
          if (std::abs(e.z()) > 15) break;
        }
        EXPECT_LE(worst, 1e-9) << "dt " << dt << " speed " << speed << " angle " << adeg;
      }
    }
  }
}

// Diagonal into a corner of two thin walls (x = 2 and z = 2 faces), many speeds.
TEST(CharacterAdversarial, ThinCornerDiagonal) {
  for (const RCharacterDef& def : {Capsule(), BoxChar(), CylChar()}) {
    for (RScalar speed : {1.0, 50.0, 1e4, 1e6}) {
      for (RScalar adeg : {45.0, 30.0, 60.0, 44.9}) {
        CharacterWorld w;
        Big(w);
        w.Box(RVec3(0.005, 1, 3), RVec3(2.005, 1, 0));
        w.Box(RVec3(3, 1, 0.005), RVec3(0, 1, 2.005));
        RCharacter c(def);
        w.Step({&c}, 30);
        const RScalar a = adeg * M_PI / 180;
        c.SetDesiredVelocity(RVec3(std::cos(a), 0, std::sin(a)) * speed);
        RScalar worstX = -1e9, worstZ = -1e9;
        for (int k = 0; k < 240; ++k) {
          w.Step({&c});
          ASSERT_TRUE(Finite(c.Position_W()));
          worstX = std::max(worstX, c.Position_W().x() - (2 - 0.3));
          worstZ = std::max(worstZ, c.Position_W().z() - (2 - 0.3));
        }
        EXPECT_LE(worstX, 1e-9) << int(def.shape.type) << " speed " << speed << " a " << adeg;
        EXPECT_LE(worstZ, 1e-9) << int(def.shape.type) << " speed " << speed << " a " << adeg;
        // Should reach the corner (within a few offsets).
        EXPECT_GT(c.Position_W().x(), 2 - 0.3 - 0.01) << int(def.shape.type) << " speed " << speed << " a " << adeg;
        EXPECT_GT(c.Position_W().z(), 2 - 0.3 - 0.01) << int(def.shape.type) << " speed " << speed << " a " << adeg;
      }
    }
  }
}

// A wedge: two thin walls meeting at the apex (3, *, 0) at +-half angle, opening towards -x.
TEST(CharacterAdversarial, ThinWedge) {
  for (RScalar half : {5.0, 15.0, 30.0}) {
    for (RScalar speed : {2.0, 100.0, 1e5}) {
      for (RScalar zdir : {0.0, 0.1, -0.3}) {
        CharacterWorld w;
        Big(w);
        const RScalar h = half * M_PI / 180;
        // wall i: a thin slab whose inner face passes through the apex, at angle +-h from -x axis.
        RVec3 normals[2];
        for (int s = -1; s <= 1; s += 2) {
          const RScalar ang = s * h;
          const RVec3 along(-std::cos(ang), 0, std::sin(ang));  // from apex outward
          RVec3 inner = RVec3(0, 1, 0).cross(along).normalized();
          if (inner.z() * s > 0) inner = -inner;  // points inside the wedge (toward z=0)
          normals[(s + 1) / 2] = inner;
          const RVec3 centre = RVec3(8, 1, 0) + along * 4.2 - inner * 0.005;
          const RQuat q(Eigen::AngleAxisd(std::atan2(-along.z(), along.x()), RVec3::UnitY()));
          w.Box(RVec3(4.2, 1, 0.005), centre, RBodyKind::kStatic, q);
        }
        RCharacter c(Capsule());
        w.Step({&c}, 30);
        c.SetDesiredVelocity(RVec3(1, 0, zdir).normalized() * speed);
        RScalar worst = 1e9;
        for (int k = 0; k < 300; ++k) {
          w.Step({&c});
          ASSERT_TRUE(Finite(c.Position_W()));
          for (const RVec3& n : normals) {
            // signed distance of the capsule axis from the inner face plane through apex
            const RScalar sd = (c.Position_W() - RVec3(8, 1, 0)).dot(n);
            worst = std::min(worst, sd - 0.3);
          }
        }
        EXPECT_GE(worst, -1e-9) << "half " << half << " speed " << speed << " zdir " << zdir
                                << " pos " << c.Position_W().transpose();
      }
    }
  }
}

// A corridor barely wider than the character, walked diagonally fast.
TEST(CharacterAdversarial, NarrowCorridorDiagonal) {
  for (RScalar width : {0.603, 0.61, 0.7}) {
    for (RScalar speed : {3.0, 300.0, 1e5}) {
      CharacterWorld w;
      Big(w, 60);
      w.Box(RVec3(50, 1, 0.005), RVec3(0, 1, width / 2 + 0.005));
      w.Box(RVec3(50, 1, 0.005), RVec3(0, 1, -width / 2 - 0.005));
      RCharacter c(Capsule());
      w.Step({&c}, 30);
      RScalar worst = -1e9;
      for (int k = 0; k < 120; ++k) {
        const RScalar a = 0.3 + 1.2 * std::sin(0.37 * k);  // keeps hitting both walls
        c.SetDesiredVelocity(RVec3(std::cos(a), 0, (k % 2 ? 1 : -1) * std::sin(a)) * speed);
        w.Step({&c});
        ASSERT_TRUE(Finite(c.Position_W()));
        worst = std::max(worst, std::abs(c.Position_W().z()) + 0.3 - width / 2);
        if (std::abs(c.Position_W().x()) > 45) c.SetPosition(RVec3(0, c.Position_W().y(), c.Position_W().z()));
      }
      EXPECT_LE(worst, 1e-9) << "width " << width << " speed " << speed;
    }
  }
}


// ---------- carried / pushed ------------------------------------------------------------------

// A deck moving at v with its own (separate kinematic) rear wall, the character `gap` in front
// of it: carried, its place on the deck must not change and it never gets behind the wall.
TEST(CharacterAdversarial, CarriedWithAWallOfTheShip) {
  for (RScalar v : {2.0, 20.0, 60.0}) {
    for (RScalar gap : {0.0011, 0.05, 0.5}) {
      CharacterWorld w;
      const RBodyHandle deck = w.Box(RVec3(10, 0.1, 3), RVec3(0, -0.1, 0), RBodyKind::kKinematic);
      const RBodyHandle wall = w.Box(RVec3(0.05, 1, 3), RVec3(-0.3 - gap - 0.05, 1.1, 0), RBodyKind::kKinematic);
      RCharacter c(Capsule(0.3, 0.6, 0, 0, 0.001));
      w.Step({&c}, 5);
      ASSERT_TRUE(c.OnGround());
      w.bodies[deck].SetVelocity_W(RVec3(v, 0, 0));
      w.bodies[wall].SetVelocity_W(RVec3(v, 0, 0));
      RScalar worstBehind = -1e9, drift = 0;
      const RScalar rel0 = c.Position_W().x() - w.bodies[deck].Position_W().x();
      for (int k = 0; k < 60; ++k) {
        w.Step({&c});
        const RScalar face = w.bodies[wall].Position_W().x() + 0.05;
        worstBehind = std::max(worstBehind, face - (c.Position_W().x() - 0.3));
        drift = std::max(drift, std::abs(c.Position_W().x() - w.bodies[deck].Position_W().x() - rel0));
      }
      EXPECT_LE(worstBehind, 0) << "v " << v << " gap " << gap << " (character behind the wall's face by this)";
      EXPECT_LE(drift, 1e-6) << "v " << v << " gap " << gap << " (place on the deck drifted)";
    }
  }
}

// A deck carries the character into a static thin wall that spans above the deck.
TEST(CharacterAdversarial, CarriedIntoAStaticThinWall) {
  for (RScalar v : {2.0, 30.0, 200.0, 3000.0}) {
    CharacterWorld w;
    const RBodyHandle deck = w.Box(RVec3(5000, 1, 3), RVec3(1000, -1, 0), RBodyKind::kKinematic);
    w.Box(RVec3(0.005, 2, 3), RVec3(2.005, 2.2, 0));  // spans y 0.2 .. 4.2: above the deck, blocks the capsule
    RCharacter c(Capsule(0.3, 0.6, 0, 0, 0.001));
    w.Step({&c}, 5);
    w.bodies[deck].SetVelocity_W(RVec3(v, 0, 0));
    RScalar worst = -1e9;
    for (int k = 0; k < 60; ++k) {
      w.Step({&c});
      ASSERT_TRUE(Finite(c.Position_W()));
      worst = std::max(worst, c.Position_W().x() - (2 - 0.3));
    }
    EXPECT_LE(worst, 1e-9) << "v " << v << " final " << c.Position_W().transpose();
  }
}

// A kinematic wall pushes the character against a static 1 cm wall.
TEST(CharacterAdversarial, SqueezedBetweenKinematicAndStaticWall) {
  for (RScalar v : {0.5, 1.5, 10.0, 40.0}) {
    for (RScalar start : {-0.5, -3.0}) {
      CharacterWorld w;
      Big(w);
      w.Box(RVec3(0.005, 2, 3), RVec3(1.005, 2, 0));  // static, face at x = 1
      const RBodyHandle kin = w.Box(RVec3(0.1, 1, 3), RVec3(start, 1.05, 0), RBodyKind::kKinematic);
      w.bodies[kin].SetVelocity_W(RVec3(v, 0, 0));
      RCharacter c(Capsule());
      RScalar worst = -1e9;
      int steps = int((1.2 - start) / v / kDt) + 30;
      for (int k = 0; k < steps && w.bodies[kin].Position_W().x() < 0.8; ++k) {
        w.Step({&c});
        ASSERT_TRUE(Finite(c.Position_W()));
        worst = std::max(worst, c.Position_W().x() - (1 - 0.3));
      }
      EXPECT_LE(worst, 1e-9) << "v " << v << " start " << start << " final " << c.Position_W().transpose()
                             << " kin " << w.bodies[kin].Position_W().x();
    }
  }
}

// ---------- meshes ------------------------------------------------------------------------------


// A zero-thickness mesh wall (two triangles, plane x = 2), walked into fast at angles.
TEST(CharacterAdversarial, MeshWallZeroThickness) {
  for (RScalar speed : {1.0, 100.0, 1e4, 1e6}) {
    for (RScalar adeg : {0.0, 30.0, 60.0}) {
      CharacterWorld w;
      Big(w);
      RBodyDef wall;
      wall.shape = RShape::Mesh({{2, 0, -5}, {2, 3, -5}, {2, 3, 5}, {2, 0, 5}}, {{0, 1, 2}, {0, 2, 3}});
      wall.kind = RBodyKind::kStatic;
      w.bodies.Add(wall);
      for (const RCharacterDef& def : {Capsule(), BoxChar(), CylChar()}) {
        RCharacter c(def);
        w.Step({&c}, 20);
        const RScalar a = adeg * M_PI / 180;
        c.SetDesiredVelocity(RVec3(std::cos(a), 0, std::sin(a)) * speed);
        RScalar worst = -1e9;
        for (int k = 0; k < 30; ++k) {
          const RVec3 b = c.Position_W();
          w.Step({&c});
          const RVec3 e = c.Position_W();
          ASSERT_TRUE(Finite(e));
          if (e.x() > 1.7) {
            const RScalar t = (1.7 - b.x()) / (e.x() - b.x());
            if (std::abs(b.z() + t * (e.z() - b.z())) < 5) worst = std::max(worst, e.x() - 1.7);
          }
          if (std::abs(e.z()) > 4.5) break;
        }
        EXPECT_LE(worst, 1e-9) << "shape " << int(def.shape.type) << " speed " << speed << " a " << adeg;
      }
    }
  }
}

// Falling very fast onto a one-layer mesh floor, and onto a mesh floor with bumps.
TEST(CharacterAdversarial, FallOntoMeshFloor) {
  for (RScalar vfall : {10.0, 1e3}) {
    for (RScalar bump : {0.0, 0.02}) {
      CharacterWorld w;
      RBodyDef f = MeshGrid(0.1, 200, 200, RVec3(-10, 0, -10), bump, 3);
      w.bodies.Add(f);
      for (const RCharacterDef& def0 : {Capsule(), BoxChar(), CylChar()}) {
        RCharacterDef def = def0;
        def.position_W = RVec3(0.0123, 20, 0.0456);
        RCharacter c(def);
        c.SetVelocity(RVec3(0, -vfall, 0));
        for (int k = 0; k < 150 && !(k > 5 && c.OnGround()); ++k) c.Update(w.bodies, w.queries, 1.0 / 60, w.gravity);
        for (int k = 0; k < 3; ++k) c.Update(w.bodies, w.queries, 1.0 / 60, w.gravity);
        ASSERT_TRUE(Finite(c.Position_W()));
        const RScalar bottom = c.Position_W().y() - HalfHeight(def);
        EXPECT_GE(bottom, -bump - 1e-9) << "v " << vfall << " bump " << bump << " shape " << int(def.shape.type);
        // Landing on walkable ground: it should not be thrown sideways.
        EXPECT_LT((c.Position_W() - def.position_W).cwiseProduct(RVec3(1, 0, 1)).norm(), 0.05)
            << "v " << vfall << " bump " << bump << " shape " << int(def.shape.type) << " landed at " << c.Position_W().transpose();
        if (bump == 0) {
          EXPECT_TRUE(c.OnGround()) << "v " << vfall << " shape " << int(def.shape.type);
          EXPECT_NEAR(bottom, kOff, 1e-7) << "v " << vfall << " shape " << int(def.shape.type);
        }
      }
    }
  }
}


// Falling onto a walkable 20-degree static ramp: where it lands, horizontally.
TEST(CharacterAdversarial, LandingOnWalkableRampDoesNotSlideSideways) {
  for (RScalar vfall : {5.0, 50.0, 500.0}) {
    CharacterWorld w;
    const RScalar ang = 20 * M_PI / 180;
    w.Box(RVec3(50, 0.1, 50), RVec3(0, -0.1, 0), RBodyKind::kStatic, RQuat(Eigen::AngleAxisd(ang, RVec3::UnitZ())));
    RCharacterDef def = Capsule();
    def.position_W = RVec3(0, 3, 0);
    RCharacter c(def);
    c.SetVelocity(RVec3(0, -vfall, 0));
    for (int k = 0; k < 120; ++k) c.Update(w.bodies, w.queries, kDt, w.gravity);
    EXPECT_TRUE(c.OnGround());
    // Where a vertical fall meets the ramp: x stays 0 (the ramp is walkable, nothing pushes it along).
    EXPECT_NEAR(c.Position_W().x(), 0, 1e-6) << "v " << vfall;
  }
}


}  // namespace
