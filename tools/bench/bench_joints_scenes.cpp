// bench_joints' six scenes (JointScenes.h), the closed-form scenes of
// tests/joints/joints_test.cpp at 60 Hz: a pendulum on a ball joint, a hinge motor spinning a
// wheel up, a 10-link chain holding a 100 kg weight, a rope stopping a falling weight, a
// slider's limit stopping a falling car, a welded pair tumbling in zero g; what each
// measures, against its closed form.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include "JointScenes.h"
#include "support/Joints.h"
#include "support/TestBodies.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

using namespace REngine;
using namespace REngine::bench;
using namespace REngine::test;

namespace {

Anchor AnchorOf(const RBodies& bodies, RJointHandle h) {
  const RJoint& j = bodies.Joint(h);
  Anchor an;
  an.a = DenseOf(bodies, j.def.a);
  an.world = !j.def.b.IsValid();
  if (!an.world) an.b = DenseOf(bodies, j.def.b);
  an.anchorA_B = j.anchorA_B, an.anchorB_B = j.anchorB_B;
  return an;
}

// A ball of radius 5 cm hung 1 m below a ball joint to the world, released from 30 degrees:
// a physical pendulum, period 4 sqrt(I / (m g L)) K(sin(theta0/2)), over 20 periods.
class Pendulum : public Scene {
  static constexpr RScalar L = 1, theta0 = kPi / 6, m = 1, radius = 0.05;
  const RVec3 pivot = RVec3(0, 2, 0);
  RScalar period = 0, swing = 0;
  std::vector<RScalar> crossings;
  RScalar xPrev = 0, worstEnergy = 0, worstLength = 0;

 public:
  Pendulum() {
    name = "pendulum";
    title = "pendulum, ball joint, 30 deg, 20 periods";
    const RScalar I = 0.4 * m * radius * radius + m * L * L;
    period = 4 * std::sqrt(I / (m * kG * L)) * CompleteEllipticK(std::sin(theta0 / 2));
    swing = m * kG * L * (1 - std::cos(theta0));
    steps = static_cast<int>(std::ceil(20.5 * period / kDt));
  }
  void Build(RBodies& bodies) override {
    const RBodyHandle bob = bodies.Add(
        SphereDef(radius).Mass(m).At(pivot + L * RVec3(std::sin(theta0), -std::cos(theta0), 0)));
    bodies.AddJoint(Joint(RJointType::kBall, bob, RBodyHandle{}, pivot));
  }
  void Begin(const std::vector<State>& s) override {
    crossings.clear();
    xPrev = s[0].x.x(), worstEnergy = 0, worstLength = 0;
  }
  void Observe(int step, const std::vector<State>& s) override {
    const RScalar x = s[0].x.x();
    if (xPrev > 0 && x <= 0) crossings.push_back((step - 1 + xPrev / (xPrev - x)) * kDt);
    xPrev = x;
    const RScalar energy = s[0].Kinetic() + m * kG * (s[0].x.y() - (pivot.y() - L));
    worstEnergy = std::max(worstEnergy, std::abs(energy - swing) / swing);
    worstLength = std::max(worstLength, std::abs((s[0].x - pivot).norm() - L));
  }
  std::vector<Figure> Figures() const override {
    // Over 20 periods; over as many as there are when the swing dies out sooner.
    const std::size_t n = std::min<std::size_t>(crossings.size(), 21);
    const RScalar measured = n >= 2 ? (crossings[n - 1] - crossings[0]) / static_cast<RScalar>(n - 1) : std::nan("");
    return {{"period, relative", std::abs(measured / period - 1)},
            {"energy, relative (largest)", worstEnergy},
            {"length, m (largest)", worstLength}};
  }
};

// A 4 kg box wheel (half extents 0.5, 0.1, 0.5) on a hinge to the world about y, motor 10 rad/s
// with at most 2 N m: it spins up at tau / I exactly, then holds 10 rad/s (300 steps more).
class Motor : public Scene {
  static constexpr RScalar tau = 2, target = 10;
  const RVec3 centre = RVec3(0, 1, 0);
  RScalar I = 0, alpha = 0, worstDrift = 0, endSpeed = 0;
  int spinUp = 0;

 public:
  Motor() {
    name = "motor";
    title = "hinge motor, 2 N m to 10 rad/s";
    I = 4 * (0.25 + 0.25) / 3;  // about y, box of half extents 0.5 (x, z), 4 kg
    spinUp = static_cast<int>(target * I / (tau * kDt));
    steps = spinUp - 1 + 300;
  }
  void Build(RBodies& bodies) override {
    const RBodyHandle wheel = bodies.Add(BoxDef(RVec3(0.5, 0.1, 0.5)).Mass(4).At(centre));
    RJointDef d = Joint(RJointType::kHinge, wheel, RBodyHandle{}, centre);
    d.axis_W = RVec3(0, 1, 0);
    d.motor = {true, target, tau};
    bodies.AddJoint(d);
  }
  void Begin(const std::vector<State>&) override { alpha = 0, worstDrift = 0, endSpeed = 0; }
  void Observe(int step, const std::vector<State>& s) override {
    if (step == spinUp - 1) alpha = s[0].w.y() / (step * kDt);
    worstDrift = std::max(worstDrift, (s[0].x - centre).norm());
    endSpeed = s[0].w.y();
  }
  std::vector<Figure> Figures() const override {
    return {{"spin-up rate vs tau/I, relative", std::abs(alpha / (tau / I) - 1)},
            {"held speed, relative (end)", std::abs(endSpeed / target - 1)},
            {"centre off the pivot, m (largest)", worstDrift}};
  }
};

// Ten 1 kg links (0.1 x 0.5 x 0.1 m) on ball joints from the world, a 100 kg ball at the end,
// pushed sideways at (2, 0, 1) m/s: every joint's gap over 5 s.
class Chain : public Scene {
  std::vector<RJointHandle> handles;
  std::vector<Anchor> anchors;
  RScalar worst = 0, last = 0;

 public:
  Chain() {
    name = "chain";
    title = "10-link chain, 100:1 weight, swinging";
    steps = 300;
  }
  void Build(RBodies& bodies) override {
    const int links = 10;
    const RScalar len = 0.5;
    handles.clear(), anchors.clear();
    RBodyHandle previous;
    for (int k = 0; k < links; ++k) {
      const RVec3 top(0, 10 - k * len, 0);
      const RBodyHandle link =
          bodies.Add(BoxDef(RVec3(0.05, len / 2, 0.05)).Mass(1).At(top - RVec3(0, len / 2, 0)));
      handles.push_back(bodies.AddJoint(Joint(RJointType::kBall, link, previous, top)));
      previous = link;
    }
    const RVec3 end(0, 10 - links * len, 0);
    const RBodyHandle weight = bodies.Add(SphereDef(0.2).Mass(100).At(end - RVec3(0, 0.2, 0)));
    handles.push_back(bodies.AddJoint(Joint(RJointType::kBall, weight, previous, end)));
    bodies[weight].SetVelocity_W(RVec3(2, 0, 1));
    for (RJointHandle h : handles) anchors.push_back(AnchorOf(bodies, h));
  }
  void Begin(const std::vector<State>&) override { worst = 0, last = 0; }
  void Observe(int, const std::vector<State>& s) override {
    last = 0;
    for (const Anchor& a : anchors) last = std::max(last, a.Gap(s));
    worst = std::max(worst, last);
  }
  std::vector<Figure> Figures() const override {
    return {{"largest gap at a joint, m", worst}, {"largest gap at the end, m", last}};
  }
};

// A 5 kg ball on a 2 m rope (distance joint, min 0) from a point above it, dropped from 1 m
// below the point: it falls 1 m freely, the rope stops it at 2 m (inelastic), no bounce. 4 s.
// The closed form's path: 1 + g t^2 / 2 from the point until that reaches 2 m, then 2 m.
class Rope : public Scene {
  static constexpr RScalar L = 2;
  const RVec3 pivot = RVec3(0, 5, 0);
  RScalar longest = 0, shortestAfter = 0, endSpeed = 0, worstPath = 0;
  bool taut = false;

 public:
  Rope() {
    name = "rope";
    title = "rope stops a falling weight (Bullet: a 6-dof limit along it)";
    steps = 240;
  }
  void Build(RBodies& bodies) override {
    const RBodyHandle w = bodies.Add(SphereDef(0.1).Mass(5).At(pivot - RVec3(0, 1, 0)));
    RJointDef d = Joint(RJointType::kDistance, w, RBodyHandle{}, pivot - RVec3(0, 1, 0));
    d.hasAnchorB = true, d.anchorB_W = pivot;
    d.minDistance = 0, d.maxDistance = L;
    bodies.AddJoint(d);
  }
  void Begin(const std::vector<State>&) override {
    longest = 0, shortestAfter = L, endSpeed = 0, worstPath = 0, taut = false;
  }
  void Observe(int step, const std::vector<State>& s) override {
    const RScalar dist = (s[0].x - pivot).norm(), t = step * kDt;
    worstPath = std::max(worstPath, std::abs(dist - std::min(1 + 0.5 * kG * t * t, L)));
    longest = std::max(longest, dist);
    if (taut) shortestAfter = std::min(shortestAfter, dist);
    taut = taut || dist > L - 1e-9;
    endSpeed = s[0].v.norm();
  }
  std::vector<Figure> Figures() const override {
    return {{"off the closed form's path, m (largest)", worstPath},
            {"beyond the length, m (largest)", std::max<RScalar>(longest - L, 0)},
            {"back up after taut, m (largest)", taut ? L - shortestAfter : std::nan("")},
            {"speed at 4 s, m/s", endSpeed}};
  }
};

// An 800 kg car (box 0.8 x 0.4 x 1.4 m) on a vertical slider to the world with limits -1 and
// +0.5 m: it falls 1 m and stops at the lower limit, off its axis never. 3 s. The closed
// form's path: -g t^2 / 2 until that reaches -1 m, then -1 m.
class Slider : public Scene {
  const RVec3 start = RVec3(3, 4, -2);
  RScalar lowest = 0, offAxis = 0, turned = 0, endTravel = 0, worstPath = 0;

 public:
  Slider() {
    name = "slider";
    title = "slider limit stops a falling 800 kg car";
    steps = 180;
  }
  void Build(RBodies& bodies) override {
    const RBodyHandle car = bodies.Add(BoxDef(RVec3(0.4, 0.2, 0.7)).Mass(800).At(start));
    RJointDef d = Joint(RJointType::kSlider, car, RBodyHandle{}, start);
    d.axis_W = RVec3(0, 1, 0);
    d.hasLimits = true, d.lower = -1, d.upper = 0.5;
    bodies.AddJoint(d);
  }
  void Begin(const std::vector<State>&) override {
    lowest = 0, offAxis = 0, turned = 0, endTravel = 0, worstPath = 0;
  }
  void Observe(int step, const std::vector<State>& s) override {
    const RScalar t = step * kDt;
    endTravel = s[0].x.y() - start.y();
    worstPath = std::max(worstPath, std::abs(endTravel - std::max<RScalar>(-0.5 * kG * t * t, -1)));
    lowest = std::min(lowest, endTravel);
    offAxis = std::max(offAxis, (s[0].x - start).cwiseProduct(RVec3(1, 0, 1)).norm());
    turned = std::max(turned, QuatAngleBetween(s[0].q, RQuat::Identity()));
  }
  std::vector<Figure> Figures() const override {
    return {{"off the closed form's path, m (largest)", worstPath},
            {"below the limit, m (largest)", std::max<RScalar>(-1 - lowest, 0)},
            {"off the limit at 3 s, m", std::abs(endTravel + 1)},
            {"off the axis (m) or turned (rad), largest", std::max(offAxis, turned)}};
  }
};

// Two boxes (1000 kg/m^3, 1 x 0.4 x 0.6 and 0.6 x 0.8 x 0.4 m) welded and tumbling in zero g
// for 10 s: angular momentum, energy and shape kept, and box a where the same boxes as one
// compound body carry it (REngine's compound, whose free motion is exact to rounding: the
// closed form's stand-in, the same reference for both engines).
class Weld : public Scene {
  const RVec3 h1 = RVec3(0.5, 0.2, 0.3), h2 = RVec3(0.3, 0.4, 0.2);
  const RVec3 c1 = RVec3(-0.5, 0, 0), c2 = RVec3(0.3, 0.1, 0.05);
  static constexpr RScalar rho = 1000;
  const RVec3 w = RVec3(0.3, 1.0, 0.5), v = RVec3(0.2, -0.1, 0.05);
  std::vector<RVec3> twinPath;  // box a's centre where the compound carries it, each step
  Anchor anchor;
  RQuat relative0 = RQuat::Identity();
  RVec3 L0 = RVec3::Zero();
  RScalar E0 = 0, worstL = 0, worstE = 0, worstGap = 0, worstTurn = 0, worstTwin = 0;

  static std::pair<RVec3, RScalar> MomentAndEnergy(const std::vector<State>& s) {
    RVec3 L = RVec3::Zero();
    RScalar E = 0;
    for (const State& b : s) L += b.x.cross(b.m * b.v) + b.L(), E += b.Kinetic();
    return {L, E};
  }

 public:
  Weld() {
    name = "weld";
    title = "welded pair tumbling in zero g, 10 s";
    gravity = RVec3::Zero();
    steps = 600;
    // The compound twin's path, once.
    BodyDef twin;
    twin.shape.type = RShapeType::kCompound;
    for (const auto& [he, c] : {std::pair{h1, c1}, std::pair{h2, c2}}) {
      RCompoundChild child;
      child.shape = RShape::Box(he);
      child.position_S = c, child.density = rho;
      twin.shape.children.push_back(child);
    }
    twin.Moving(v).Spinning(w);
    RBodies world;
    const RBodyHandle t = world.Add(twin);
    RWorldSettings settings;
    settings.threads = 1;
    RIntegrator integrator(settings);
    for (int s = 0; s < steps; ++s) {
      integrator.Update(world, kDt);
      const RRigidBody& tw = world[t];
      twinPath.push_back(tw.ShapePosition_W() + tw.ShapeOrientation_WS() * c1);
    }
  }
  void Build(RBodies& bodies) override {
    const RScalar m1 = rho * 8 * h1.prod(), m2 = rho * 8 * h2.prod();
    const RVec3 com = (m1 * c1 + m2 * c2) / (m1 + m2);
    const RBodyHandle a =
        bodies.Add(BoxDef(h1).Density(rho).At(c1).Moving(v + w.cross(c1 - com)).Spinning(w));
    const RBodyHandle b =
        bodies.Add(BoxDef(h2).Density(rho).At(c2).Moving(v + w.cross(c2 - com)).Spinning(w));
    anchor = AnchorOf(bodies, bodies.AddJoint(Joint(RJointType::kFixed, a, b, RVec3(0, 0.05, 0))));
  }
  void Begin(const std::vector<State>& s) override {
    std::tie(L0, E0) = MomentAndEnergy(s);
    relative0 = s[0].q.conjugate() * s[1].q;
    worstL = worstE = worstGap = worstTurn = worstTwin = 0;
  }
  void Observe(int step, const std::vector<State>& s) override {
    const auto [L, E] = MomentAndEnergy(s);
    worstL = std::max(worstL, (L - L0).norm() / L0.norm());
    worstE = std::max(worstE, std::abs(E - E0) / E0);
    worstGap = std::max(worstGap, anchor.Gap(s));
    worstTurn = std::max(worstTurn, QuatAngleBetween(s[0].q * relative0, s[1].q));
    worstTwin = std::max(worstTwin, (s[0].x - twinPath[static_cast<std::size_t>(step - 1)]).norm());
  }
  std::vector<Figure> Figures() const override {
    return {{"angular momentum, relative (largest)", worstL},
            {"energy, relative (largest)", worstE},
            {"gap at the weld, m (largest)", worstGap},
            {"turned apart, rad (largest)", worstTurn},
            {"box a from the compound's, m (largest)", worstTwin}};
  }
};

}  // namespace

std::vector<std::unique_ptr<Scene>> REngine::bench::JointScenes() {
  std::vector<std::unique_ptr<Scene>> scenes;
  scenes.push_back(std::make_unique<Pendulum>());
  scenes.push_back(std::make_unique<Motor>());
  scenes.push_back(std::make_unique<Chain>());
  scenes.push_back(std::make_unique<Rope>());
  scenes.push_back(std::make_unique<Slider>());
  scenes.push_back(std::make_unique<Weld>());
  return scenes;
}
