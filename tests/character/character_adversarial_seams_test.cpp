// Seams, steps, and robustness (no NaN, no hang, far from the origin, other ups).
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

// ---------- seams ------------------------------------------------------------------------------

RQuat Rot0(int kind, std::mt19937& rng) {
  std::normal_distribution<RScalar> n(0, 1);
  // One statement each: the order a constructor's arguments are evaluated in is the
  // compiler's (gcc right to left, clang left to right), and the cases must be the same.
  const RScalar ax = n(rng);
  const RScalar ay = n(rng);
  const RScalar az = n(rng);
  const RVec3 axis = RVec3(ax, ay, az).normalized();
  switch (kind) {
    case 0: return RQuat::Identity();
    case 1: return RQuat(-1, 0, 0, 0);                                 // the same rotation
    case 2: return RQuat(Eigen::AngleAxisd(2 * M_PI, axis));           // a full turn
    case 3: return RQuat(Eigen::AngleAxisd(1e-12 * n(rng), axis));     // rounding-size
    case 4: return RQuat(Eigen::AngleAxisd(M_PI / 2 * static_cast<double>(rng() % 4), RVec3::UnitY()));  // quarter turns about up
    default: return RQuat::Identity();
  }
}

struct SeamResult { RScalar speedErr = 0, heightErr = 0, gapErr = 0; int offGround = 0; };

SeamResult WalkSeams(const RCharacterDef& def0, RScalar tile, int rotKind, unsigned seed, bool mesh, RScalar speed = 3,
                     int steps = 200, RScalar dt = kDt) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<RScalar> u(0, 2 * M_PI);
  const RScalar a = u(rng);
  const RVec3 dir(std::cos(a), 0, std::sin(a));
  const RScalar len = speed * steps * dt + 1;
  CharacterWorld w;
  if (mesh) {
    const RVec3 lo = (dir * len).cwiseMin(RVec3::Zero()) - RVec3(2, 0, 2);
    const RVec3 hi = (dir * len).cwiseMax(RVec3::Zero()) + RVec3(2, 0, 2);
    const int n = int(std::ceil((hi - lo).maxCoeff() / tile));
    RBodyDef f = MeshGrid(tile, n, n, RVec3(lo.x(), 0, lo.z()), 0, seed);
    w.bodies.Add(f);
  } else {
    const int n = int(std::ceil((len + 2) / tile));
    for (int i = -n; i <= n; ++i)
      for (int j = -n; j <= n; ++j) {
        const RVec3 c((i + 0.5) * tile, -0.1, (j + 0.5) * tile);
        const RVec3 rel(c.x(), 0, c.z());
        const RScalar along = std::clamp(rel.dot(dir), RScalar(-1), len);
        if ((rel - dir * along).norm() > 1.5 + tile) continue;
        w.Box(RVec3(tile / 2, 0.1, tile / 2), c, RBodyKind::kStatic, Rot0(rotKind, rng));
      }
  }
  RCharacterDef def = def0;
  def.position_W += RVec3(std::uniform_real_distribution<RScalar>(-0.5, 0.5)(rng) * tile, 0, 0.37 * tile);
  RCharacter c(def);
  w.Step({&c}, 20);
  SeamResult r;
  if (!c.OnGround()) { r.offGround = 1000; return r; }
  const RScalar h = c.Position_W().y();
  r.gapErr = std::abs(h - HalfHeight(def) - kOff);
  c.SetDesiredVelocity(dir * speed);
  for (int k = 0; k < steps; ++k) {
    const RVec3 b = c.Position_W();
    c.Update(w.bodies, w.queries, dt, w.gravity);
    const RVec3 m = (c.Position_W() - b) / dt;
    r.speedErr = std::max(r.speedErr, (RVec3(m.x(), 0, m.z()) - dir * speed).norm());
    r.heightErr = std::max(r.heightErr, std::abs(c.Position_W().y() - h));
    if (!c.OnGround()) ++r.offGround;
  }
  return r;
}


TEST(CharacterAdversarial, SeamsOfBoxTiles) {
  const std::vector<std::pair<const char*, RCharacterDef>> chars = {
      {"capsule", Capsule()}, {"box", BoxChar()}, {"yawed box", YawedBox(0.3)}, {"cylinder", CylChar()},
      {"sphere", [] { RCharacterDef d; d.shape = RShape::Sphere(0.4); d.position_W = RVec3(0, 0.41, 0); return d; }()}};
  int fails = 0;
  for (RScalar tile : {0.1, 0.37, 1.0, 3.3}) {
    for (int rot : {0, 1, 2, 3, 4}) {
      for (const auto& [name, def] : chars) {
        for (unsigned seed : {1u}) {
          const SeamResult r = WalkSeams(def, tile, rot, seed * 7 + rot + unsigned(tile * 100), false, 3, 100);
          const bool bad = r.speedErr > 1e-9 || r.heightErr > 1e-6 || r.offGround > 0 || r.gapErr > 1e-7;
          if (bad && ++fails < 40)
            ADD_FAILURE() << name << " tile " << tile << " rot " << rot << " seed " << seed << ": speed err " << r.speedErr
                          << " height err " << r.heightErr << " gap err " << r.gapErr << " off-ground updates " << r.offGround;
        }
      }
    }
  }
  EXPECT_EQ(fails, 0);
}

TEST(CharacterAdversarial, SeamsOfMeshTriangles) {
  const std::vector<std::pair<const char*, RCharacterDef>> chars = {
      {"capsule", Capsule()}, {"box", BoxChar()}, {"yawed box", YawedBox(0.7)}, {"cylinder", CylChar()}};
  int fails = 0;
  for (RScalar tile : {0.07, 0.5}) {
    for (const auto& [name, def] : chars) {
      for (unsigned seed : {1u}) {
        const SeamResult r = WalkSeams(def, tile, 0, seed, true, 3, 60);
        const bool bad = r.speedErr > 1e-9 || r.heightErr > 1e-6 || r.offGround > 0 || r.gapErr > 1e-7;
        if (bad && ++fails < 40)
          ADD_FAILURE() << name << " mesh cell " << tile << " seed " << seed << ": speed err " << r.speedErr
                        << " height err " << r.heightErr << " gap err " << r.gapErr << " off-ground updates " << r.offGround;
      }
    }
  }
  EXPECT_EQ(fails, 0);
}


// Sliver triangles: a strip 6 m wide along x made of triangles 6 m long and ~5 mm wide.
TEST(CharacterAdversarial, SeamsOfSliverTriangles) {
  std::vector<RVec3> v;
  std::vector<std::array<std::uint32_t, 3>> t;
  const int n = 2000;
  for (int i = 0; i <= n; ++i) {
    v.emplace_back(-2 + 0.005 * i, 0, -3);
    v.emplace_back(-2 + 0.005 * i + 0.0025, 0, 3);
  }
  for (int i = 0; i < n; ++i) {
    const std::uint32_t a = 2 * i;
    t.push_back({a, a + 1, a + 2});
    t.push_back({a + 1, a + 3, a + 2});
  }
  for (const RCharacterDef& def : {Capsule(), BoxChar(), YawedBox(0.5), CylChar()}) {
    for (RVec3 dir : {RVec3(1, 0, 0.3).normalized(), RVec3(0.2, 0, -1).normalized()}) {
      CharacterWorld w;
      RBodyDef f;
      f.shape = RShape::Mesh(v, t);
      f.kind = RBodyKind::kStatic;
      w.bodies.Add(f);
      RCharacter c(def);
      w.Step({&c}, 20);
      ASSERT_TRUE(c.OnGround());
      const RScalar h = c.Position_W().y();
      EXPECT_NEAR(h - HalfHeight(def), kOff, 1e-7);
      c.SetDesiredVelocity(dir * 3);
      RScalar se = 0, he = 0;
      int off = 0;
      for (int k = 0; k < 50; ++k) {
        const RVec3 b = c.Position_W();
        w.Step({&c});
        const RVec3 m = (c.Position_W() - b) / kDt;
        se = std::max(se, (RVec3(m.x(), 0, m.z()) - dir * 3).norm());
        he = std::max(he, std::abs(c.Position_W().y() - h));
        off += !c.OnGround();
      }
      EXPECT_LE(se, 1e-9) << int(def.shape.type) << " dir " << dir.transpose();
      EXPECT_LE(he, 1e-6) << int(def.shape.type) << " dir " << dir.transpose();
      EXPECT_EQ(off, 0) << int(def.shape.type) << " dir " << dir.transpose();
    }
  }
}


// ---------- steps ------------------------------------------------------------------------------


struct StepOut { RScalar x, y, maxY; bool onGround; };
// A step of height h, its face the plane x = 1 (rotated by yaw about the foot of the character's path).
StepOut WalkAtStep(const RCharacterDef& def, RScalar h, RScalar adeg, RScalar speed, int steps = 120) {
  CharacterWorld w;
  Big(w, 30);
  w.Box(RVec3(2, h / 2, 20), RVec3(3, h / 2, 0));  // face at x = 1
  RCharacter c(def);
  w.Step({&c}, 20);
  const RScalar a = adeg * M_PI / 180;
  c.SetDesiredVelocity(RVec3(std::cos(a), 0, std::sin(a)) * speed);
  StepOut o{0, 0, -1e9, false};
  for (int k = 0; k < steps; ++k) {
    w.Step({&c});
    o.maxY = std::max(o.maxY, c.Position_W().y());
    if (c.Position_W().x() > 2.5 || std::abs(c.Position_W().z()) > 17) break;
  }
  o.x = c.Position_W().x(), o.y = c.Position_W().y(), o.onGround = c.OnGround();
  return o;
}

TEST(CharacterAdversarial, StepsUpToStepHeightAndNoHigher) {
  const std::vector<std::pair<const char*, RCharacterDef>> chars = {
      {"capsule", Capsule()}, {"box", BoxChar()}, {"cylinder", CylChar()}, {"sphere", SphereChar()}, {"yawed box", YawedBox(0.4)}};
  for (const auto& [name, def] : chars) {
    const RScalar hh = HalfHeight(def), sh = def.stepHeight;
    for (RScalar adeg : {0.0, 40.0, 70.0}) {
      for (RScalar speed : {1.0, 6.0, 40.0}) {
        // Below stepHeight: climbs onto it, at the offset above its top.
        const StepOut up = WalkAtStep(def, sh - 0.005, adeg, speed, int(4 / speed / kDt) + 30);
        EXPECT_GT(up.x, 1.3) << name << " didn't climb " << sh - 0.005 << " at " << adeg << " deg, " << speed << " m/s";
        if (up.x > 1.3) {
          EXPECT_NEAR(up.y, sh - 0.005 + hh + kOff, 1e-6) << name << " a " << adeg << " v " << speed;
        }
        // Above: stays on the floor.
        for (RScalar over : {0.002, 0.05}) {
          const StepOut no = WalkAtStep(def, sh + over, adeg, speed, int(4 / speed / kDt) + 30);
          EXPECT_LT(no.maxY, hh + kOff + 1e-6) << name << " climbed (rose) " << sh + over << " at " << adeg << " deg, " << speed
                                               << " m/s: y " << no.maxY << " x " << no.x;
          EXPECT_LT(no.x, 1.0) << name << " got onto " << sh + over << " at " << adeg << " deg, " << speed << " m/s";
        }
      }
    }
  }
}

// A sphere pressing into a step a bit higher than stepHeight for a long time (levering up?).
TEST(CharacterAdversarial, NoLeveringUpAHighStep) {
  for (RScalar h : {0.31, 0.35, 0.39}) {
    const StepOut o = WalkAtStep(SphereChar(0.4), h, 0, 3, 600);
    EXPECT_LT(o.x, 1.0) << h;
    EXPECT_NEAR(o.y, 0.4 + kOff, 1e-6) << h;
  }
}

// ---------- robustness: NaN, hangs ------------------------------------------------------------

TEST(CharacterAdversarial, StartsInsideABody) {
  for (const RCharacterDef& def0 : {Capsule(), BoxChar(), CylChar(), SphereChar()}) {
    for (RVec3 p : {RVec3(0, 0, 0), RVec3(0, 1, 0), RVec3(2.003, 1, 0), RVec3(0, -0.1, 0)}) {
      CharacterWorld w;
      Big(w);
      w.Box(RVec3(0.005, 1, 3), RVec3(2.005, 1, 0));  // thin wall, centre at 2.005
      w.Box(RVec3(1, 1, 1), RVec3(0, 1, 0));          // a crate around the origin
      RCharacterDef def = def0;
      def.position_W = p;
      RCharacter c(def);
      c.SetDesiredVelocity(RVec3(1, 0, 0.5));
      {
        for (int k = 0; k < 120; ++k) {
          w.Step({&c});
          ASSERT_TRUE(Finite(c.Position_W())) << k;
        }
      }
      for (const RCharacterContact& k : c.Contacts())
        EXPECT_GT(k.distance, 0) << "still overlapping after 2 s; shape " << int(def.shape.type) << " start " << p.transpose();
    }
  }
}

TEST(CharacterAdversarial, ExtremeSpeedsAndDt) {
  for (RScalar dt : {1e-9, 1.0 / 60, 1.0}) {
    for (RScalar speed : {0.0, 1e-12, 1e6, 1e14}) {
      CharacterWorld w;
      w.Box(RVec3(1e5, 10, 1e5), RVec3(0, -10, 0));
      w.Box(RVec3(0.005, 1, 40), RVec3(2.005, 1, 0));
      RCharacter c(Capsule());
      c.SetDesiredVelocity(RVec3(speed, 0, 0));
      {
        for (int k = 0; k < 30; ++k) {
          c.Update(w.bodies, w.queries, dt, w.gravity);
          ASSERT_TRUE(Finite(c.Position_W())) << k;
          ASSERT_TRUE(Finite(c.MovedVelocity_W())) << k;
          ASSERT_TRUE(Finite(c.Velocity_W())) << k;
        }
      }
      EXPECT_LE(c.Position_W().x(), 2 - 0.3 + 1e-9) << "dt " << dt << " speed " << speed;
      EXPECT_GE(c.Position_W().y(), 0.9) << "dt " << dt << " speed " << speed;
    }
  }
  // Jump/fall with dt = 1: exact parabola: jump 5 m/s, g 9.81: after 1 s height 5 - 4.905.
  CharacterWorld w;
  Big(w);
  RCharacter c(Capsule());
  w.Step({&c}, 20);
  const RScalar y0 = c.Position_W().y();
  c.Jump(10);
  c.Update(w.bodies, w.queries, 1.0, w.gravity);
  EXPECT_NEAR(c.Position_W().y() - y0, 10 - 0.5 * kG, 1e-9);
}

TEST(CharacterAdversarial, FarFromTheOrigin) {
  for (RScalar far : {1e7, 1e9}) {
    for (const RCharacterDef& def0 : {Capsule(), BoxChar(), CylChar()}) {
      CharacterWorld w;
      const RVec3 o(far, far * 0.5, -far);
      w.Box(RVec3(40, 0.1, 40), o + RVec3(0, -0.1, 0));
      w.Box(RVec3(0.005, 1, 40), o + RVec3(5.005, 1, 0));
      RCharacterDef def = def0;
      def.position_W += o;
      RCharacter c(def);
      w.Step({&c}, 20);
      EXPECT_TRUE(c.OnGround()) << far;
      const RScalar y = c.Position_W().y();
      c.SetDesiredVelocity(RVec3(3, 0, 1));
      RScalar se = 0;
      for (int k = 0; k < 120; ++k) {
        const RVec3 b = c.Position_W();
        w.Step({&c});
        ASSERT_TRUE(Finite(c.Position_W()));
        if (c.Position_W().x() - o.x() < 4) se = std::max(se, std::abs((c.Position_W() - b).x() / kDt - 3));
      }
      // Rounding of positions ~1e-16 * far per update, over dt.
      const RScalar tol = 8 * 2.2e-16 * far / kDt;
      EXPECT_LE(se, tol) << "far " << far << " shape " << int(def.shape.type);
      EXPECT_TRUE(c.OnGround()) << far;
      EXPECT_NEAR(c.Position_W().y(), y, 1e-6 + 1e-15 * far) << far;
      EXPECT_LE(c.Position_W().x() - o.x(), 5 - 0.3 + 1e-6) << far;
    }
  }
}

// Up along x (and z), gravity along -up; walking, a jump's apex v^2/2g, and a thin wall.
TEST(CharacterAdversarial, UpAlongOtherAxes) {
  for (int axis : {0, 2}) {
    for (bool explicitUp : {true, false}) {
      RVec3 up = RVec3::Zero();
      up[axis] = 1;
      CharacterWorld w;
      w.SetGravity(-kG * up);
      RVec3 half(20, 20, 20);
      half[axis] = 0.1;
      w.Box(half, -0.1 * up);
      RCharacterDef def = Capsule();
      def.q_WS = RQuat::FromTwoVectors(RVec3::UnitY(), up);
      def.position_W = up * (0.9 + 0.01);
      if (explicitUp) def.up_W = up;
      RCharacter c(def);
      w.Step({&c}, 30);
      ASSERT_TRUE(c.OnGround()) << axis;
      EXPECT_NEAR(c.Position_W().dot(up), 0.9 + kOff, 1e-9);
      const RVec3 t1 = RVec3::UnitY().cross(up).norm() > 0.5 ? RVec3(RVec3::UnitY()) : RVec3(RVec3::UnitX());
      const RVec3 t2 = up.cross(t1);
      const RVec3 v = t1 * 2 + t2 * 1.5;
      c.SetDesiredVelocity(v + up * 7);  // its part along up is ignored
      RScalar se = 0;
      for (int k = 0; k < 60; ++k) {
        const RVec3 b = c.Position_W();
        w.Step({&c});
        se = std::max(se, ((c.Position_W() - b) / kDt - v).norm());
      }
      EXPECT_LE(se, 1e-9) << "axis " << axis << " explicit " << explicitUp;
      c.SetDesiredVelocity(RVec3::Zero());
      const RScalar h0 = c.Position_W().dot(up);
      c.Jump(5);
      RScalar top = h0;
      for (int k = 0; k < 120; ++k) { w.Step({&c}); top = std::max(top, c.Position_W().dot(up)); }
      EXPECT_LE(top - h0, 25 / (2 * kG) + 1e-12) << axis;
      EXPECT_GE(top - h0, 25 / (2 * kG) - kG * kDt * kDt / 8 - 1e-12) << axis;
      EXPECT_TRUE(c.OnGround());
    }
  }
}

// Zero gravity with an explicit up: standing stays, walking moves at the command, a jump rises linearly.
TEST(CharacterAdversarial, ZeroGravityExplicitUp) {
  CharacterWorld w;
  w.SetGravity(RVec3::Zero());
  Big(w);
  RCharacterDef def = Capsule(0.3, 0.6, 0, 0, 0.0);  // touching the floor
  def.up_W = RVec3::UnitY();
  RCharacter c(def);
  w.Step({&c}, 5);
  EXPECT_TRUE(Finite(c.Position_W()));
  c.SetDesiredVelocity(RVec3(1, 0, 0));
  for (int k = 0; k < 60; ++k) w.Step({&c});
  EXPECT_NEAR(c.Position_W().x(), 1.0, 1e-9);
  c.Jump(2);
  w.Step({&c});
  const RScalar y1 = c.Position_W().y();
  w.Step({&c}, 59);
  EXPECT_NEAR(c.Position_W().y() - y1, 2 * 59 * kDt, 1e-9);
  EXPECT_NEAR(c.Position_W().x(), 2.0, 1e-9);
}

// Gravity along a slanted direction, up defaulting to -g: the floor tilted to match.
TEST(CharacterAdversarial, SlantedGravity) {
  const RVec3 up = RVec3(1, 2, -3).normalized();
  CharacterWorld w;
  w.SetGravity(-kG * up);
  const RQuat q = RQuat::FromTwoVectors(RVec3::UnitY(), up);
  w.Box(RVec3(30, 0.1, 30), -0.1 * up, RBodyKind::kStatic, q);
  RCharacterDef def = Capsule();
  def.q_WS = q;
  def.position_W = up * 0.91;
  RCharacter c(def);
  w.Step({&c}, 30);
  ASSERT_TRUE(c.OnGround());
  EXPECT_NEAR(c.Position_W().dot(up), 0.9 + kOff, 1e-9);
  const RVec3 v = (q * RVec3(2, 0, 1));
  c.SetDesiredVelocity(v);
  RScalar se = 0, he = 0;
  for (int k = 0; k < 60; ++k) {
    const RVec3 b = c.Position_W();
    w.Step({&c});
    se = std::max(se, ((c.Position_W() - b) / kDt - v).norm());
    he = std::max(he, std::abs(c.Position_W().dot(up) - 0.9 - kOff));
    ASSERT_TRUE(c.OnGround()) << k;
  }
  EXPECT_LE(se, 1e-9);
  EXPECT_LE(he, 1e-9);
}


// The largest accepted command (1e15 m/s) and dt (1 s) take it to 1e15 m in one Update, in free
// space; the next Update should not throw a query error / produce non-finite values.
TEST(CharacterAdversarial, LargestAcceptedCommandThenUpdate) {
  CharacterWorld w;
  RCharacter c(Capsule());
  c.SetDesiredVelocity(RVec3(1e15, 0, 0));
  try {
    for (int k = 0; k < 3; ++k) {
      c.Update(w.bodies, w.queries, 1.0, w.gravity);
      ASSERT_TRUE(Finite(c.Position_W()));
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw: " << e.what() << " at x = " << c.Position_W().x();
  }
  // The same with a floor body under it (queries touch the tree).
  CharacterWorld w2;
  Big(w2);
  RCharacter d(Capsule());
  w2.Step({&d}, 5);
  d.SetDesiredVelocity(RVec3(1e15, 0, 0));
  try {
    for (int k = 0; k < 3; ++k) {
      d.Update(w2.bodies, w2.queries, 1.0, w2.gravity);
      ASSERT_TRUE(Finite(d.Position_W()));
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "with a floor: threw: " << e.what() << " at x = " << d.Position_W().x();
  }
}


TEST(CharacterAdversarial, SeamsAtLargeDtAndSpeed) {
  const std::vector<std::pair<const char*, RCharacterDef>> chars = {
      {"capsule", Capsule()}, {"box", BoxChar()}, {"yawed box", YawedBox(0.3)}, {"cylinder", CylChar()}};
  int fails = 0;
  for (auto [speed, dt, steps] : {std::tuple{3.0, 1.0, 6}, {3.0, 0.25, 20}, {30.0, 1.0 / 60, 60}, {300.0, 1.0 / 60, 6}}) {
    for (RScalar tile : {0.37, 1.0}) {
      for (const auto& [name, def] : chars) {
        for (unsigned seed : {5u, 6u}) {
          const SeamResult r = WalkSeams(def, tile, 3, seed, false, speed, steps, dt);
          const bool bad = r.speedErr > 1e-9 * std::max(1.0, speed / 3) || r.heightErr > 1e-6 || r.offGround > 0;
          if (bad && ++fails < 30)
            ADD_FAILURE() << name << " tile " << tile << " speed " << speed << " dt " << dt << " seed " << seed
                          << ": speed err " << r.speedErr << " height err " << r.heightErr << " off-ground " << r.offGround;
        }
      }
    }
  }
  EXPECT_EQ(fails, 0);
}

}  // namespace
