// Long chains of joints, 35 to 2000 links of one 2 m length: hanging from a pin and swung
// under gravity, and bent and spinning free in zero g. However many links, a link's turn
// under the chain's tension is faster than the step can follow: its mode has (omega dt)^2 =
// F r dt^2 / (I + m r^2) of 2 at 35 links and 1e3 at 2000, where RATTLE's rounds (rows of
// the step's start) amplify it; those islands are solved stiffened (RJointStiffness.cpp),
// which damps the modes the step cannot follow. What must hold, from physics:
//  - every joint, to 1e-9 m: the projection ends within its tolerance (1e-10 m) at the poses
//    it predicts, which the motion reaches again to the rounding of sums over 2 m;
//  - energy, to RATTLE's bounded oscillation, (w dt)^2 of the motion's energy, w the fastest
//    rate the motion has (a swung chain's second mode, a spin): a stiffened step takes
//    energy, it does not give it. What it takes is the price of the modes it cannot follow:
//    within that bound for a swing, and 10 % in 2 s once a free chain's end whips (its links
//    turning at 150 rad/s);
//  - free in zero g, momentum to rounding (1e-16 of each body's share over 120 steps, 2000
//    bodies) and angular momentum to 1e-8 of the sum of the shares' sizes (the Newton
//    tolerance, 1e-10 m, on arms of metres): the joints' impulses are equal and opposite at
//    one point, and what the stiffened solve and the position projection would take from it
//    is given back as a turn of the whole island.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kLength = 2;  // m, every chain's

// A chain's links: spheres of 1 kg, a link long across, at the points x (each a link from
// the one before), each on a ball joint at the centre of the one before (the first, when
// pinned, at the world point a link before it). No contacts: the joints are all there is.
struct Chain {
  RBodies bodies;
  std::vector<RJointHandle> joints;
};
void BuildChain(Chain& c, const std::vector<RVec3>& x, RScalar link, const RVec3& spin, const RVec3& about,
                const RVec3* pin) {
  RBodyHandle previous{};
  for (std::size_t i = 0; i < x.size(); ++i) {
    BodyDef d = SphereDef(link / 2).Mass(1).At(x[i]).Moving(spin.cross(x[i] - about)).Spinning(spin);
    d.mask = 0;
    const RBodyHandle h = c.bodies.Add(d);
    if (i > 0) c.joints.push_back(c.bodies.AddJoint(Joint(RJointType::kBall, h, previous, x[i - 1])));
    if (i == 0 && pin) c.joints.push_back(c.bodies.AddJoint(Joint(RJointType::kBall, h, RBodyHandle{}, *pin)));
    previous = h;
  }
}

struct Totals {
  RVec3 p = RVec3::Zero(), l = RVec3::Zero();
  RScalar e = 0, scaleP = 0, scaleL = 0;
};
Totals Measure(const RBodies& bodies, RScalar g) {
  Totals t;
  for (std::size_t i = 0; i < bodies.EnabledCount(); ++i) {
    const RRigidBody& b = bodies.At(i);
    const RVec3 mv = b.Mass() * b.Velocity_W();
    t.p += mv, t.l += b.Position_W().cross(mv) + b.AngularMomentum_W();
    t.e += 0.5 * b.Velocity_W().dot(mv) + 0.5 * b.AngularVelocity_W().dot(b.AngularMomentum_W()) +
           b.Mass() * g * b.Position_W().y();
    t.scaleP += mv.norm(), t.scaleL += b.Position_W().cross(mv).norm() + b.AngularMomentum_W().norm();
  }
  return t;
}

struct Run {
  RScalar gap = 0, gain = 0, loss = 0, p = 0, l = 0;
};
Run Step(Chain& c, RScalar g, int steps) {
  RWorldSettings s = GravityAlongMinusY(g);
  s.shortcuts.sleeping = false;
  RIntegrator integrator(s);
  const Totals t0 = Measure(c.bodies, g);
  Run r;
  for (int k = 0; k < steps; ++k) {
    integrator.Update(c.bodies, kDt);
    EXPECT_TRUE(integrator.NonFiniteInLastStep().empty());
    const Totals t = Measure(c.bodies, g);
    for (RJointHandle h : c.joints) r.gap = std::max(r.gap, Gap(c.bodies, h));
    r.gain = std::max(r.gain, t.e - t0.e), r.loss = std::max(r.loss, t0.e - t.e);
    r.p = std::max(r.p, (t.p - t0.p).norm() / t0.scaleP), r.l = std::max(r.l, (t.l - t0.l).norm() / t0.scaleL);
  }
  return r;
}

}  // namespace

// Hanging from a pin at the origin, straight down, swung as a rigid pendulum at half its rate
// (sqrt(g / (2 L / 3))) about a tilted horizontal axis: mostly the chain's first two modes,
// the second at w = (j_2 / 2) sqrt(g / L), j_2 = 5.5201 the second zero of J0.
void HangingChain(int n) {
  const RScalar link = kLength / n, g = 9.81;
  const RVec3 spin = 0.5 * std::sqrt(g / (2 * kLength / 3)) * RVec3(0.6, 0, 0.8), pin = RVec3::Zero();
  std::vector<RVec3> x;
  for (int i = 1; i <= n; ++i) x.push_back(RVec3(0, -i * link, 0));
  Chain c;
  BuildChain(c, x, link, spin, pin, &pin);
  const Run r = Step(c, g, 120);
  // The swing's energy: the rigid rod's (n equal masses) at that rate.
  const RScalar swing = 0.5 * n * (kLength * kLength / 3) * spin.squaredNorm();
  const RScalar w = 5.5201 / 2 * std::sqrt(g / kLength), bound = (w * kDt) * (w * kDt);
  std::printf("hanging chain of %d links: gap %.2e m, energy gained %.2e, lost %.2e of the swing's (bound %.2e)\n", n,
              r.gap, r.gain / swing, r.loss / swing, bound);
  EXPECT_LT(r.gap, 1e-9) << n;
  EXPECT_LT(r.gain, bound * swing) << n;
  EXPECT_LT(r.loss, bound * swing) << n;
}

TEST(JointChains, HangingChainOf35) { HangingChain(35); }
TEST(JointChains, HangingChainOf100) { HangingChain(100); }
TEST(JointChains, HangingChainOf2000) { HangingChain(2000); }

// Free in zero g: bent along an arc of radius 1 m with a wave across it, spinning at 2 rad/s
// about an axis tilted from its plane's normal: under its own tension it straightens, swings
// through and whips its end.
void SpinningBentChain(int n) {
  const RScalar link = kLength / n, radius = 1;
  std::vector<RVec3> x{RVec3::Zero()};
  auto bent = [&](int i) {
    const RScalar a = i * link / radius;
    return RVec3(radius * std::sin(a), radius * std::cos(a) - radius, 0.3 * std::sin(3 * a));
  };
  for (int i = 1; i < n; ++i) x.push_back(x.back() + (bent(i) - bent(i - 1)).normalized() * link);
  RVec3 centre = RVec3::Zero();
  for (const RVec3& p : x) centre += p / n;
  for (RVec3& p : x) p -= centre;
  const RVec3 spin = 2 * RVec3(0.3, 0.2, 1);
  Chain c;
  BuildChain(c, x, link, spin, RVec3::Zero(), nullptr);
  RScalar kinetic = 0;
  for (const RVec3& p : x) kinetic += 0.5 * spin.cross(p).squaredNorm();
  const Run r = Step(c, 0, 120);
  const RScalar bound = (spin.norm() * kDt) * (spin.norm() * kDt);
  std::printf("spinning bent chain of %d links: gap %.2e m, momentum %.2e, angular momentum %.2e, energy gained %.2e, "
              "lost %.2e (bound %.2e)\n", n, r.gap, r.p, r.l, r.gain / kinetic, r.loss / kinetic, bound);
  EXPECT_LT(r.gap, 1e-9) << n;
  EXPECT_LT(r.p, 1e-12) << n;
  EXPECT_LT(r.l, 1e-8) << n;
  EXPECT_LT(r.gain, bound * kinetic) << n;
  EXPECT_LT(r.loss, 0.1 * kinetic) << n;
}

TEST(JointChains, SpinningBentChainOf100) { SpinningBentChain(100); }
TEST(JointChains, SpinningBentChainOf2000) { SpinningBentChain(2000); }
