// Flush tiles share the friction under a body as one floor does (solver/RPatchGroups.cpp),
// while each tile's contact stays its own: what the contacts report is what the body got,
// and the sharing does not depend on which side of each pair the body is. The scenes are
// SeamScenes.h's.
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>

#include "collision/SeamScenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kAsked = 1e-9;  // m/s, m: as seams_test.cpp asks of every crossing
// As seams_test.cpp: enough tiles that the body ends on the last but one.
int TileCount(RScalar speed) { return static_cast<int>(std::ceil(std::max(4.0, 0.25 * speed))) + 3; }

}  // namespace

// The contacts stay the pairs' own: each reports its normal impulses and its part of the
// friction patch its tile shares with the others under the body, and what they report is
// what the body got. A box sliding with friction over the turned grid (mu 0.5: it slows at
// mu g) has manifolds on up to four tiles; each step, the impulses its contacts report
// (normal along each contact's normal, friction as reported) are its momentum change less
// gravity's, m (v1 - v0) - m g dt, to rounding (1e-12 of m g dt asked).
TEST(Seams, EachTileReportsItsPartOfTheFrictionUnderABody) {
  Crossing c;
  c.mover = Mover::kBox, c.speed = 5, c.grid = true, c.tileYaw = 0.4, c.tileCount = TileCount(5);
  c.moverFriction = 0.5;
  RScalar height = 0;
  RVec3 w0;
  std::vector<RRigidBody> bodies = SeamScene(c, 0.4, height, w0);
  RIntegrator integrator;
  SetGravity(integrator, c);
  integrator.Settings().shortcuts.sleeping = false;
  const std::uint32_t mover = static_cast<std::uint32_t>(bodies.size() - 1);
  const RVec3 g = integrator.Settings().gravity_W;
  RScalar worst = 0;
  int shared = 0;
  for (int k = 0; k < 30; ++k) {
    const RVec3 v0 = bodies.back().Velocity_W();
    integrator.Update(bodies, kDt);
    const RScalar m = bodies.back().Mass();
    RVec3 reported = RVec3::Zero();
    int rubbing = 0;
    for (const RContact& ct : integrator.Contacts()) {
      if (ct.a != mover && ct.b != mover) continue;
      RScalar normal = 0;
      for (int i = 0; i < ct.manifold.pointCount; ++i) normal += ct.normalImpulse[i];
      const RVec3 J = normal * ct.manifold.normal + ct.frictionImpulse_W;  // on b
      reported += ct.b == mover ? J : RVec3(-J);
      rubbing += ct.frictionImpulse_W.norm() > 0;
    }
    shared += rubbing > 1;
    const RVec3 got = m * (bodies.back().Velocity_W() - v0) - m * g * kDt;
    worst = std::max(worst, (reported - got).norm() / (m * g.norm() * kDt));
  }
  std::printf("box sliding with friction over a turned grid: %d steps on several tiles with friction, "
              "reports off the momentum change by %.1e of m g dt\n", shared, worst);
  EXPECT_GT(shared, 0);
  EXPECT_LT(worst, 1e-12);
}

// A pair's a is its lower body index. With the body between the tiles in the list, its
// contacts with the tiles before it have it as b and those after it as a: their normals
// are opposite, and the shared patch takes each one's part the other way round. A capsule
// and a cylinder rolling with friction over the turned grid, moved to index 30 of the 91
// bodies, keep the closed form (speed and height) as with the body last (1e-9 asked,
// 1.2e-12 measured), in steps on tiles of both sides.
TEST(Seams, ABodyBetweenItsTilesInTheListSharesItsFrictionAlike) {
  for (const Mover mover : {Mover::kCapsuleRolling, Mover::kCylinderRolling}) {
    for (const RScalar speed : {1.0, 5.0}) {
      Crossing c;
      c.mover = mover, c.speed = speed, c.grid = true, c.tileYaw = 0.4, c.tileCount = TileCount(speed);
      RScalar height = 0;
      RVec3 w0;
      std::vector<RRigidBody> bodies = SeamScene(c, 0.4, height, w0);
      const std::uint32_t at = 30;
      std::rotate(bodies.begin() + at, bodies.end() - 1, bodies.end());  // the body to index 30
      RIntegrator integrator;
      SetGravity(integrator, c);
      integrator.Settings().shortcuts.sleeping = false;
      RScalar speedError = 0, heightError = 0;
      int bothSides = 0;
      const int steps = static_cast<int>(std::ceil(std::max(4.0, 0.25 * speed) / speed / kDt));
      for (int k = 0; k < steps; ++k) {
        integrator.Update(bodies, kDt);
        const RVec3 v = bodies[at].Velocity_W();
        speedError = std::max(speedError, std::hypot(v.x() - speed, v.z()));
        heightError = std::max(heightError, std::abs(bodies[at].Position_W().y() - height));
        bool asA = false, asB = false;
        for (const RContact& ct : integrator.Contacts()) asA = asA || ct.a == at, asB = asB || ct.b == at;
        bothSides += asA && asB;
      }
      std::printf("%-16s at %g m/s, index 30 of %zu: %d steps on tiles of both sides, |dv| %.1e m/s, |dy| %.1e m\n",
                  Name(mover), speed, bodies.size(), bothSides, speedError, heightError);
      EXPECT_GT(bothSides, 0) << Name(mover) << " " << speed;
      EXPECT_LT(speedError, kAsked) << Name(mover) << " " << speed;
      EXPECT_LT(heightError, kAsked) << Name(mover) << " " << speed;
    }
  }
}
