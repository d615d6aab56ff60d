// A ball bouncing under gravity, against the closed form. Dropped from h onto a static box
// (restitution e, no friction), it lands at t1 = sqrt(2h/g) at v1 = g t1, and the n-th bounce
// comes at t_n = t1 + 2 t1 (e + ... + e^(n-1)) at speed e^(n-1) v1. Between bounces its
// energy height y - r + v^2/(2g) is h e^(2n) after the n-th, and it comes to rest at the
// Zeno time t1 (1 + e)/(1 - e). Each bounce's impulse is m (1 + e) times the speed at the
// moment of contact.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kG = 9.81;

struct Drop {
  RScalar t1, v1, zeno;
  // The closed form's bounces up to time t: their count and the last one's time.
  int BouncesBy(RScalar t, RScalar e) const {
    int n = 0;
    RScalar tn = t1, flight = 2 * t1 * e;
    while (tn <= t && n < 10000) ++n, tn += flight, flight *= e;
    return n;
  }
};

}  // namespace

// Flight heights, bounce steps and impulses, and the rest at the Zeno time, for e = 0.8 and
// 0.6. The motion between impacts is exact for constant gravity (kick-drift-kick), and the
// impact is found at its time on the parabola: every flight's energy height is h e^(2n) to
// rounding (1e-9 of h asked, over some 200 steps of a few roundings of 5 m each). The
// restitution threshold is set below the last bounces' speeds that last a step: 1 mm/s
// leaves the ball bouncing until 2 e (1 mm/s)/(g (1 - e)) before the Zeno time, under a
// step.
TEST(BounceUnderGravity, FlightHeightsBounceImpulsesAndRestFollowTheClosedForm) {
  for (const RScalar e : {0.8, 0.6}) {
    const RScalar h = 5, r = 0.5, m = 2;
    RBodies bodies;
    bodies.Add(BoxDef(RVec3(5, 0.5, 5)).Static().Restitution(1).Friction(0).At(RVec3(0, -0.5, 0)).Named("ground"));
    const RBodyHandle ball = bodies.Add(
        SphereDef(r).Mass(m).Restitution(e).Friction(0).At(RVec3(0, r + h, 0)).Named("ball"));
    RWorldSettings settings;
    settings.gravity_W = RVec3(0, -kG, 0);
    settings.restitutionThreshold = 1e-3;
    RIntegrator integrator(settings);
    Drop d;
    d.t1 = std::sqrt(2 * h / kG), d.v1 = kG * d.t1, d.zeno = d.t1 * (1 + e) / (1 - e);
    RScalar worstH = 0, worstJ = 0;
    int bounceEvents = 0;
    const int steps = static_cast<int>(std::ceil(d.zeno / kDt)) + 60;
    for (int s = 1; s <= steps; ++s) {
      integrator.Update(bodies, kDt);
      const RScalar t = s * kDt;
      const RRigidBody& b = bodies[ball];
      const RScalar y = b.Position_W().y(), v = b.Velocity_W().y();
      const RScalar energyHeight = y - r + v * v / (2 * kG);
      // The bounces in this step: a begin, its impulse theirs at their closed-form speeds
      // (two bounces may fall in one step late in the fall).
      for (const RContactEvent& ev : integrator.Events()) {
        if (ev.type != RContactEventType::kBegin || t >= d.zeno - kDt) continue;
        const int first = d.BouncesBy(t - kDt, e) + 1, last = d.BouncesBy(t, e);
        EXPECT_GE(last, first) << "e " << e << ": a bounce begins in step " << s;
        RScalar impulse = 0;
        for (int n = first; n <= last; ++n) impulse += m * (1 + e) * d.v1 * std::pow(e, n - 1);
        worstJ = std::max(worstJ, std::abs(ev.normalImpulse - impulse) / impulse);
        ++bounceEvents;
      }
      if (t < d.zeno - kDt) {
        const RScalar want = h * std::pow(e, 2 * d.BouncesBy(t, e));
        worstH = std::max(worstH, std::abs(energyHeight - want) / h);
      } else if (t >= d.zeno + kDt) {
        // At rest on the ground from a step after the Zeno time on, sunk no deeper than the slop.
        EXPECT_NEAR(v, 0, 1e-9) << "e " << e << " step " << s;
        EXPECT_NEAR(y - r, 0, settings.penetrationSlop) << "e " << e << " step " << s;
      }
    }
    std::printf("ball under gravity, e %.1f: flight energy heights off h e^(2n) by %.2g of h, bounce impulses "
                "off m (1 + e) v by %.2g, %d bounce events\n",
                e, worstH, worstJ, bounceEvents);
    EXPECT_LT(worstH, 1e-9) << "e " << e;
    EXPECT_LT(worstJ, 1e-9) << "e " << e;
    EXPECT_GE(bounceEvents, 5) << "e " << e;
  }
}
