// A crate resting on the deck of a spinning station: a kinematic ring turning at w about its
// axis in zero gravity, the crate carried on the inside of its rim. The deck holds the crate
// on a circle with the centripetal force m w^2 R alone: the crate stays at the deck's
// surface (sunk no deeper than the contact slop, at any spin), turns with the station, and
// its velocity relative to the deck under it has no normal part.
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;

}  // namespace

// The station: two plates 1 m thick whose inner faces are R from the axis (z), the crate on
// the lower one at the plate's middle (the deck's lowest point as the spin sees it, where it
// rests without friction's help). Spins of 0.5 and 1 rad/s at R = 39.24 m: 1 g and 4 g.
TEST(SpinningDeck, CrateRestsOnTheDeckAtAnySpin) {
  const RScalar R = 39.24, half = 0.5;
  for (const RScalar w : {0.5, 1.0}) {
    RShape ring = RShape::Compound({{RShape::Box(RVec3(4, 0.5, 4)), RVec3(0, -R - 0.5, 0)},
                                    {RShape::Box(RVec3(4, 0.5, 4)), RVec3(0, R + 0.5, 0)}});
    BodyDef station;
    station.shape = ring;
    station.Kinematic().Spinning(RVec3(0, 0, w)).Friction(0.5).Named("station");
    const RVec3 x0(0, -R + half, 0);
    BodyDef crate = BoxDef(RVec3::Constant(half)).Mass(2).Friction(0.5).At(x0).Named("crate");
    crate.Moving(RVec3(0, 0, w).cross(x0)).Spinning(RVec3(0, 0, w));
    std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{station, crate});
    RIntegrator integrator;  // zero gravity
    RScalar worstSink = 0, worstNormal = 0, worstLag = 0;
    for (int s = 1; s <= 600; ++s) {
      integrator.Update(bodies, kDt);
      const RVec3 x = bodies[1].Position_W();
      // How far the crate's bottom face is beyond the deck (its centre's distance from the
      // axis, plus half its size, against R).
      const RScalar r = std::hypot(x.x(), x.y());
      worstSink = std::max(worstSink, r + half - R);
      // Its velocity relative to the deck's surface under it, along the deck's normal (the
      // radius): zero at rest, to the friction and end solves' residuals (1e-10 of w^2 R dt).
      const RVec3 radial = RVec3(x.x(), x.y(), 0) / r;
      const RVec3 deck = RVec3(0, 0, w).cross(RVec3(x.x(), x.y(), 0));
      // (After the first second: the first steps, without warm starts, settle the friction
      // that keeps the crate turning to some 1e-5 of its spin.)
      if (s > 60) worstNormal = std::max(worstNormal, std::abs((bodies[1].Velocity_W() - deck).dot(radial)));
      // Turning with the station: its angle, from the axis, the station's.
      const RScalar angle = std::atan2(x.x(), -x.y());
      worstLag = std::max(worstLag, std::abs(std::remainder(angle - w * s * kDt, 2 * M_PI)));
    }
    std::printf("deck at %.1f rad/s (%.1f g): sunk up to %.3g m, normal velocity up to %.3g m/s, angle off the "
                "station's by %.3g rad\n",
                w, w * w * R / 9.81, worstSink, worstNormal, worstLag);
    EXPECT_LE(worstSink, integrator.Settings().penetrationSlop * (1 + 1e-9)) << "w " << w;
    EXPECT_LT(worstNormal, 1e-9) << "w " << w;
    EXPECT_LT(worstLag, 1e-6) << "w " << w;
  }
}
