// Joint islands of every size, 1 to 2000 joints: stars (a hub carrying n satellites on ball
// joints), hanging chains and meshes of joints (loops), spinning in zero g and swinging under
// gravity. No contacts (the satellites' filters pass nothing), so what the joints do is all
// there is, and physics says what must hold:
//  - momentum, in zero g, to rounding: every joint impulse acts on both bodies, equal and
//    opposite;
//  - angular momentum, in zero g about any point, under gravity about the vertical through
//    the pivot: the impulses act at the same point of both bodies, so to rounding (1e-16 of
//    each of up to 2000 bodies' share, over 120 steps) and to the Newton tolerance of the
//    step's end (1e-10 m, which the position projection may move a body on arms of metres):
//    1e-8 of the sum of the shares' sizes;
//  - energy, to RATTLE's error: a second-order symplectic method keeps it within a bounded
//    oscillation of relative size about (w dt)^2, w the fastest rate of the motion (the spin,
//    a pendulum's sqrt(g / l)); no drift, no run-away.
// Islands past the block solver's size (86 ball joints, 258 rows) are solved as one sparse
// system; these cross that size.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;

// A body no contact ever touches: joints only.
BodyDef Ghost(RScalar radius, RScalar mass, const RVec3& x) {
  BodyDef d = SphereDef(radius).Mass(mass).At(x);
  d.mask = 0;
  return d;
}

struct Totals {
  RVec3 p = RVec3::Zero(), l = RVec3::Zero();
  RScalar e = 0;          // kinetic plus potential (height along +y times g), J
  RScalar scaleP = 0;     // sum of m |v|
  RScalar scaleL = 0;     // sum of |x x m v| + |I w|
  RScalar vMax = 0;
};

Totals Measure(const RBodies& bodies, RScalar g, const RVec3& about) {
  Totals t;
  for (std::size_t i = 0; i < bodies.EnabledCount(); ++i) {
    const RRigidBody& b = bodies.At(i);
    if (b.Mass() == 0) continue;
    const RVec3 mv = b.Mass() * b.Velocity_W();
    const RVec3 orbital = (b.Position_W() - about).cross(mv);
    t.p += mv, t.l += orbital + b.AngularMomentum_W();
    t.e += b.LinearKineticEnergy() + b.RotationalKineticEnergy() + b.Mass() * g * b.Position_W().y();
    t.scaleP += mv.norm(), t.scaleL += orbital.norm() + b.AngularMomentum_W().norm();
    t.vMax = std::max(t.vMax, b.Velocity_W().norm());
  }
  return t;
}

// What a run kept: the worst relative drift of each conserved quantity over the steps
// after `settle` (the steps in which the joints first pull the bodies into line, an
// inelastic event, are not conservative).
struct Kept {
  RScalar p = 0, l = 0, e = 0, vMax = 0;
};

// The run: steps of the world, measured after each one. Angular momentum about `about`: all
// of it conserved in zero g (g = 0), its vertical component under gravity.
Kept RunAndMeasure(RBodies& bodies, RIntegrator& integrator, int steps, int settle, RScalar g, const RVec3& about) {
  for (int s = 0; s < settle; ++s) integrator.Update(bodies, kDt);
  const Totals t0 = Measure(bodies, g, about);
  Kept k;
  const RScalar e0 = std::abs(t0.e) > 0 ? std::abs(t0.e) : 1;
  for (int s = 0; s < steps; ++s) {
    integrator.Update(bodies, kDt);
    EXPECT_TRUE(integrator.NonFiniteInLastStep().empty());
    const Totals t = Measure(bodies, g, about);
    k.p = std::max(k.p, (t.p - t0.p).norm() / std::max(t0.scaleP, RScalar(1e-300)));
    const RScalar dl = g == 0 ? (t.l - t0.l).norm() : std::abs(t.l.y() - t0.l.y());
    k.l = std::max(k.l, dl / std::max(t0.scaleL, RScalar(1e-300)));
    k.e = std::max(k.e, std::abs(t.e - t0.e) / e0);
    k.vMax = std::max(k.vMax, t.vMax);
  }
  return k;
}

// n satellites (1 kg, radius 0.2 m) on a Fibonacci sphere of radius R around a hub (radius
// 1 m), each on a ball joint halfway out. spin: the satellites move with the hub's spin
// (2 rad/s about y) from the start; else only the hub spins, and the joints' first pull
// spins the satellites up.
struct Star {
  std::vector<RBodyHandle> bodies;
  RBodyHandle hub;
};
Star MakeStar(RBodies& bodies, int n, RScalar hubMass, bool spin, bool pinned) {
  const RScalar R = std::max(RScalar(3), RScalar(0.6) * std::sqrt(RScalar(n)));
  const RVec3 w(0, 2, 0);
  Star s;
  s.hub = bodies.Add(Ghost(1, hubMass, RVec3::Zero()).Spinning(w));
  for (int i = 0; i < n; ++i) {
    const RScalar y = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - y * y);
    const RScalar phi = kPi * (3 - std::sqrt(RScalar(5))) * i;
    const RVec3 d(r * std::cos(phi), y, r * std::sin(phi));
    BodyDef def = Ghost(0.2, 1, R * d);
    if (spin) def.Moving(w.cross(R * d)).Spinning(w);
    const RBodyHandle h = bodies.Add(def);
    bodies.AddJoint(Joint(RJointType::kBall, s.hub, h, (1 + R) / 2 * d));
  }
  if (pinned) bodies.AddJoint(Joint(RJointType::kBall, s.hub, RBodyHandle{}, RVec3::Zero()));
  return s;
}

// A square mesh of k x k spheres (1 kg, 0.5 m apart in the z = 0 plane, centred on the
// origin), each joined to its right and upper neighbours by ball joints halfway between: 2 k
// (k - 1) joints, loops everywhere (redundant rows). Spinning rigidly at w. Returns the joints.
int MakeMesh(RBodies& bodies, int k, const RVec3& w) {
  const RScalar spacing = 0.5;
  std::vector<RBodyHandle> grid;
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) {
      const RVec3 x((i - (k - 1) / 2.0) * spacing, (j - (k - 1) / 2.0) * spacing, 0);
      grid.push_back(bodies.Add(Ghost(0.1, 1, x).Moving(w.cross(x)).Spinning(w)));
    }
  }
  int joints = 0;
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) {
      const RVec3 x = bodies[grid[i * k + j]].Position_W();
      if (i + 1 < k) {
        bodies.AddJoint(Joint(RJointType::kBall, grid[i * k + j], grid[(i + 1) * k + j], x + RVec3(spacing / 2, 0, 0)));
        ++joints;
      }
      if (j + 1 < k) {
        bodies.AddJoint(Joint(RJointType::kBall, grid[i * k + j], grid[i * k + j + 1], x + RVec3(0, spacing / 2, 0)));
        ++joints;
      }
    }
  }
  return joints;
}

RWorldSettings Space() { return RWorldSettings{}; }

void Report(const char* what, int joints, const Kept& k, RScalar bound) {
  std::printf("%s, %d joints: momentum %.2e, angular momentum %.2e, energy %.2e (bound %.2e), top speed %.3g m/s\n",
              what, joints, k.p, k.l, k.e, bound, k.vMax);
}

void SpinningStar(int n) {
  RBodies bodies;
  MakeStar(bodies, n, std::max(10, n), true, false);
  RIntegrator integrator(Space());
  const Kept k = RunAndMeasure(bodies, integrator, 120, 0, 0, RVec3::Zero());
  // w dt = 2/60: (w dt)^2 = 1.1e-3 bounds the oscillation of the energy.
  const RScalar bound = (2 * kDt) * (2 * kDt);
  Report("spinning star", n, k, bound);
  EXPECT_LT(k.p, 1e-12);
  EXPECT_LT(k.l, 1e-8);
  EXPECT_LT(k.e, bound);
  const RScalar R = std::max(RScalar(3), RScalar(0.6) * std::sqrt(RScalar(n)));
  EXPECT_LT(k.vMax, 2 * 2 * R);  // the rim's speed, with room for the satellites' swing
}

}  // namespace

// The star spinning in zero g, from one joint to 2000, across the block solver's size.
TEST(JointIslands, SpinningStarOf1) { SpinningStar(1); }
TEST(JointIslands, SpinningStarOf85) { SpinningStar(85); }
TEST(JointIslands, SpinningStarOf86) { SpinningStar(86); }
TEST(JointIslands, SpinningStarOf300) { SpinningStar(300); }
TEST(JointIslands, SpinningStarOf2000) { SpinningStar(2000); }

// A 10 kg hub spun at 2 rad/s with 86 (then 200) 1 kg satellites at rest on ball joints: the
// first step's pull spins the satellites up (inelastic, as a collision: energy goes, both
// momenta stay), then the star turns on with both momenta and its energy kept. (The step
// spreads the spin-up's last 0.5% of the energy over its first second: measured from then.)
TEST(JointIslands, HubSpinsUpItsSatellitesAndKeepsWhatItHas) {
  for (int n : {86, 200}) {
    RBodies bodies;
    MakeStar(bodies, n, 10, false, false);
    RIntegrator integrator(Space());
    const Totals before = Measure(bodies, 0, RVec3::Zero());
    integrator.Update(bodies, kDt);
    const Totals after = Measure(bodies, 0, RVec3::Zero());
    EXPECT_LT((after.l - before.l).norm(), 1e-12 * before.scaleL) << n;
    EXPECT_LT((after.p - before.p).norm(), 1e-12 * std::max(before.scaleP, after.scaleP)) << n;
    EXPECT_LT(after.e, 0.9 * before.e) << n;
    const Kept k = RunAndMeasure(bodies, integrator, 120, 60, 0, RVec3::Zero());
    const RScalar bound = (2 * kDt) * (2 * kDt);
    Report("hub spinning up its satellites", n, k, bound);
    EXPECT_LT(k.p, 1e-12) << n;
    EXPECT_LT(k.l, 1e-8) << n;
    EXPECT_LT(k.e, bound) << n;
    EXPECT_LT(k.vMax, 2 * 2 * 3.0) << n;  // no faster than the rim would move
  }
}

// The star pinned at its centre, under gravity: the satellites swing and tumble about the
// pin. Conserved: energy, and angular momentum about the vertical through the pin.
TEST(JointIslands, PinnedStarsUnderGravityOf100And2000) {
  for (int n : {100, 2000}) {
    RBodies bodies;
    MakeStar(bodies, n, n, true, true);
    RIntegrator integrator(GravityAlongMinusY(9.81));
    const Kept k = RunAndMeasure(bodies, integrator, 120, 0, 9.81, RVec3::Zero());
    const RScalar bound = (2 * kDt) * (2 * kDt);
    Report("pinned star under gravity", n + 1, k, bound);
    EXPECT_LT(k.l, 1e-8) << n;
    EXPECT_LT(k.e, bound) << n;
  }
}

// A chain of 10 links 10 cm long (spheres of 1 kg on ball joints) hanging from the world,
// swung from vertical at half its rate as a rigid pendulum (w = sqrt(g / (2 L / 3))), about
// z and about x: energy kept to the swing's (w dt)^2 (at least 1e-3: the links' own modes are
// faster than the swing), and the vertical component of angular momentum about the pivot.
TEST(JointIslands, SwingingChainOf10Links) {
  for (int n : {10}) {
    RBodies bodies;
    const RScalar link = 0.1, L = n * link;
    const RVec3 pivot(0, 0, 0);
    const RScalar w = std::sqrt(9.81 / (2 * L / 3));
    const RVec3 spin = 0.5 * w * RVec3(0.6, 0, 0.8);
    RBodyHandle previous{};
    for (int i = 1; i <= n; ++i) {
      const RVec3 x = pivot + RVec3(0, -i * link, 0);
      const RBodyHandle h = bodies.Add(Ghost(link / 2, 1, x).Moving(spin.cross(x - pivot)).Spinning(spin));
      bodies.AddJoint(Joint(RJointType::kBall, h, previous, x + RVec3(0, link, 0)));
      previous = h;
    }
    RIntegrator integrator(GravityAlongMinusY(9.81));
    const Kept k = RunAndMeasure(bodies, integrator, 120, 0, 9.81, pivot);
    // Relative to the swing's energy, not to the potential's arbitrary zero.
    const RScalar swing = 0.5 * n * (L * L / 3) * spin.squaredNorm();
    const RScalar bound = std::max(RScalar(1e-3), (w * kDt) * (w * kDt));
    const RScalar e = k.e * std::abs(Measure(bodies, 9.81, pivot).e) / swing;
    Report("swinging chain", n, Kept{k.p, k.l, e, k.vMax}, bound);
    EXPECT_LT(k.l, 1e-8) << n;
    EXPECT_LT(e, bound) << n;
  }
}

// Meshes (MakeMesh) spinning in zero g about their normal.
TEST(JointIslands, SpinningMeshesOf12And180Joints) {
  for (int k : {3, 10}) {
    RBodies bodies;
    const RVec3 w(0, 0, 1.0);
    const int joints = MakeMesh(bodies, k, w);
    RIntegrator integrator(Space());
    const Kept kept = RunAndMeasure(bodies, integrator, 120, 0, 0, RVec3::Zero());
    const RScalar bound = (w.norm() * kDt) * (w.norm() * kDt);
    Report("spinning mesh", joints, kept, bound);
    EXPECT_LT(kept.p, 1e-12) << k;
    EXPECT_LT(kept.l, 1e-8) << k;
    EXPECT_LT(kept.e, bound) << k;
  }
}

// The same meshes tumbling about an axis off their normal (36 and 64 spheres, 60 and 112
// joints: the skyline block and the sparse system). A nearly flat mesh is nearly singular
// across its plane (its tension grows without bound as it flattens): the Newton rounds,
// which hold the rows of the step's start, stop converging, and the island is solved
// stiffened (RJointStiffness.cpp) from nothing, whose rounds do converge. (Joint by joint
// with warm starts carried from diverged rounds, these reached thousands of metres a second
// in 30 steps; with the plain velocity constraint and the position projection after the
// diverged rounds they lost 2 % of their energy in 2 s.) Angular momentum to 1e-7: the
// stiffened steps of the sparse system keep it to about 1e-10 a step, not to rounding (the
// 64-sphere mesh: 1.0e-8 in 120 steps); where that is lost is not yet found.
TEST(JointIslands, TumblingMeshesOf60And112Joints) {
  for (int k : {6, 8}) {
    RBodies bodies;
    const RVec3 w(0.3, 0.2, 1.0);
    const int joints = MakeMesh(bodies, k, w);
    RIntegrator integrator(Space());
    const Kept kept = RunAndMeasure(bodies, integrator, 120, 0, 0, RVec3::Zero());
    const RScalar bound = (w.norm() * kDt) * (w.norm() * kDt);
    Report("tumbling mesh", joints, kept, bound);
    EXPECT_LT(kept.p, 1e-12) << k;
    EXPECT_LT(kept.l, 1e-7) << k;
    EXPECT_LT(kept.e, bound) << k;
  }
}

// The largest mesh, 32 x 32 spheres (1984 joints, loops everywhere: the sparse system with
// its self-stresses taken out), tumbling as above for 12 steps (each about a second's work):
// momentum to rounding, angular momentum to the Newton tolerance as the stars, energy within
// the method's (w dt)^2.
TEST(JointIslands, TumblingMeshOf1984Joints) {
  RBodies bodies;
  const RVec3 w(0.3, 0.2, 1.0);
  const int joints = MakeMesh(bodies, 32, w);
  RIntegrator integrator(Space());
  const Kept k = RunAndMeasure(bodies, integrator, 12, 0, 0, RVec3::Zero());
  const RScalar bound = (w.norm() * kDt) * (w.norm() * kDt);
  Report("tumbling mesh", joints, k, bound);
  EXPECT_LT(k.p, 1e-12);
  EXPECT_LT(k.l, 1e-8);
  EXPECT_LT(k.e, bound);
}
