// bench_joints: REngine's joints against Bullet's on the closed-form scenes of
// tests/joints/joints_test.cpp, in the same process (that suite asserts REngine's side of each).
//
//   bench_joints [--repeats N] [--csv FILE] [--quick]
//
// Six scenes at 60 Hz, 10 solver iterations in both engines, gravity 9.81 m/s^2 (zero for the
// weld): a pendulum on a ball joint, a hinge motor spinning a wheel up, a 10-link chain holding
// a 100 kg weight, a rope stopping a falling weight, a slider's limit stopping a falling car,
// and a welded pair tumbling in zero g. Each scene is built once in REngine (RBodies, AddJoint)
// and its Bullet twin is built from those same bodies and joints: the same masses, principal
// moments, poses and velocities (tools/bench/BulletWorld.h: Bullet's body frame is REngine's,
// centre of mass and principal axes) and the joints' anchors and axes in those frames.
// The figures are computed the same way for both engines from the bodies' states (position,
// orientation, velocity, angular velocity of the centre of mass) and REngine's mass properties.
//
// Bullet's joints (Bullet's default ERP and CFM everywhere; its bodies never sleep):
//   ball     btPoint2PointConstraint
//   hinge    btHingeConstraint, enableAngularMotor(true, speed, maxImpulse = maxForce dt)
//            (Bullet drives A's speed relative to B; a joint to the world is A alone)
//   slider   btSliderConstraint (x of its frames along the axis), setLower/UpperLinLimit,
//            rotation locked (its default); Bullet's defaults for the limit's softness (1),
//            damping (1: no restitution) and ERP
//   fixed    btFixedConstraint, both frames at the anchor
//   distance Bullet has no distance joint: btPoint2PointConstraint holds the anchors together,
//            it cannot be slack. The rope is a btGeneric6DofSpring2Constraint whose frames'
//            x axis is the rope's direction at the start, x limited to the rope's length, y,
//            z and every rotation free: a plane the weight cannot pass, the same as the rope
//            for a weight that falls straight along it (this scene), not in general.
// Joined bodies do not collide in either engine (collideConnected false; Bullet's
// addConstraint(c, true)). REngine runs on one thread (Bullet's is single-threaded), sleeping
// off in both, so both step every body every step.
//
// Timing: each scene runs --repeats times in each engine, interleaved (REngine, Bullet,
// REngine, ...); the clock (steady_clock) is read around each step call alone, setup and the
// figures excluded. us_per_step is the median over the repeats. Both engines are
// deterministic: the figures come from the first repeat.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include "BulletWorld.h"
#include "support/Joints.h"
#include "support/TestBodies.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

using namespace REngine;
using namespace REngine::bench;
using namespace REngine::test;

namespace {

using Clock = std::chrono::steady_clock;

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kG = 9.81;
constexpr int kIterations = 10;

// One body's state after a step, as both engines report it, with its mass properties.
struct State {
  RVec3 x = RVec3::Zero();  // centre of mass, world
  RQuat q = RQuat::Identity();  // body frame (principal axes) to world
  RVec3 v = RVec3::Zero(), w = RVec3::Zero();
  RScalar m = 0;
  RVec3 I_B = RVec3::Zero();  // principal moments
  RVec3 L() const { return q * I_B.cwiseProduct(q.conjugate() * w); }  // about the centre
  RScalar Kinetic() const { return 0.5 * m * v.squaredNorm() + 0.5 * w.dot(L()); }
};

struct Figure {
  std::string name;  // what and its unit
  RScalar value = 0;
};

// A joint's anchors in its bodies' frames (the same in both engines), to measure its gap.
struct Anchor {
  std::size_t a = 0, b = 0;
  bool world = false;       // b is the world: anchorB is a world point
  RVec3 anchorA_B, anchorB_B;
  RScalar Gap(const std::vector<State>& s) const {
    const RVec3 pA = s[a].x + s[a].q * anchorA_B;
    const RVec3 pB = world ? anchorB_B : RVec3(s[b].x + s[b].q * anchorB_B);
    return (pA - pB).norm();
  }
};

std::size_t DenseOf(const RBodies& bodies, RBodyHandle h) {
  return static_cast<std::size_t>(&bodies[h] - bodies.begin());
}

Anchor AnchorOf(const RBodies& bodies, RJointHandle h) {
  const RJoint& j = bodies.Joint(h);
  Anchor an;
  an.a = DenseOf(bodies, j.def.a);
  an.world = !j.def.b.IsValid();
  if (!an.world) an.b = DenseOf(bodies, j.def.b);
  an.anchorA_B = j.anchorA_B, an.anchorB_B = j.anchorB_B;
  return an;
}



// A scene: its bodies and joints (built in REngine; Bullet's twin is made from them), how
// many steps, and what is measured. Begin is called before each run, Observe after each step
// with the step's number (1-based) and the states, Figures at the end.
class Scene {
 public:
  virtual ~Scene() = default;
  std::string name, title;
  RVec3 gravity = RVec3(0, -kG, 0);
  int steps = 0;
  virtual void Build(RBodies& bodies) = 0;
  virtual void Begin(const std::vector<State>& /*initial*/) {}
  virtual void Observe(int step, const std::vector<State>& s) = 0;
  virtual std::vector<Figure> Figures() const = 0;
};

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

// ---- the engines -------------------------------------------------------------------------

struct Run {
  std::vector<Figure> figures;
  double seconds = 0;  // in the step calls
};

RWorldSettings Settings(const Scene& scene) {
  RWorldSettings s;
  s.gravity_W = scene.gravity;
  s.solverIterations = kIterations;
  s.threads = 1;
  s.shortcuts.sleeping = false;
  return s;
}

std::vector<State> Masses(const RBodies& bodies) {
  std::vector<State> s(bodies.Size());
  for (std::size_t i = 0; i < s.size(); ++i) s[i].m = bodies.At(i).Mass(), s[i].I_B = bodies.At(i).Inertia_B();
  return s;
}

void Read(const RBodies& bodies, std::vector<State>& s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const RRigidBody& b = bodies.At(i);
    s[i].x = b.Position_W(), s[i].q = b.Orientation_WB();
    s[i].v = b.Velocity_W(), s[i].w = b.AngularVelocity_W();
  }
}

Run RunREngine(Scene& scene) {
  RBodies bodies;
  scene.Build(bodies);
  RIntegrator integrator(Settings(scene));
  std::vector<State> s = Masses(bodies);
  Read(bodies, s);
  scene.Begin(s);
  Run run;
  for (int step = 1; step <= scene.steps; ++step) {
    const auto t0 = Clock::now();
    integrator.Update(bodies, kDt);
    run.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    Read(bodies, s);
    scene.Observe(step, s);
  }
  run.figures = scene.Figures();
  return run;
}

// A rotation whose x axis is `axis` (unit): a joint frame's basis.
RQuat FrameWithX(const RVec3& axis) {
  RVec3 y = std::abs(axis.x()) < 0.9 ? RVec3::UnitX() : RVec3::UnitY();
  y = (y - axis * axis.dot(y)).normalized();
  RMat3 m;
  m.col(0) = axis, m.col(1) = y, m.col(2) = axis.cross(y);
  return RQuat(m);
}

btTransform BtFrame(const RQuat& q, const RVec3& p) { return btTransform(Bt(q), Bt(p)); }

// Bullet's twin of an REngine joint (see the file's comment), added to the world.
std::unique_ptr<btTypedConstraint> BulletJoint(BulletWorld& w, const RBodies& bodies, const RJoint& j) {
  const std::size_t ia = DenseOf(bodies, j.def.a);
  btRigidBody& A = *w.bodies[ia];
  const bool world = !j.def.b.IsValid();
  btRigidBody* B = world ? nullptr : w.bodies[DenseOf(bodies, j.def.b)].get();
  const RRigidBody& ra = bodies.At(ia);
  const RQuat qA = ra.Orientation_WB();
  const RQuat qB = world ? RQuat::Identity() : bodies[j.def.b].Orientation_WB();
  // anchorB_B is a world point for a joint to the world.
  const RVec3 pivotA = j.anchorA_B, pivotB = j.anchorB_B;
  std::unique_ptr<btTypedConstraint> c;
  switch (j.def.type) {
    case RJointType::kBall:
      if (world) c = std::make_unique<btPoint2PointConstraint>(A, Bt(pivotA));
      else c = std::make_unique<btPoint2PointConstraint>(A, *B, Bt(pivotA), Bt(pivotB));
      break;
    case RJointType::kHinge: {
      if (j.def.hasLimits) {
        std::fprintf(stderr, "bench_joints: hinge limits are not translated to Bullet\n");
        std::exit(2);
      }
      const RVec3 axis_W = j.def.axis_W.normalized();
      std::unique_ptr<btHingeConstraint> h;
      if (world) {
        h = std::make_unique<btHingeConstraint>(A, Bt(pivotA), Bt(RVec3(qA.conjugate() * axis_W)), false);
      } else {
        h = std::make_unique<btHingeConstraint>(A, *B, Bt(pivotA), Bt(pivotB), Bt(RVec3(qA.conjugate() * axis_W)),
                                                Bt(RVec3(qB.conjugate() * axis_W)), false);
      }
      if (j.def.motor.enabled) {
        // REngine's speed is b's relative to a (a's to the world for a joint to the world);
        // Bullet's is A's relative to B.
        const RScalar speed = world ? j.def.motor.speed : -j.def.motor.speed;
        h->enableAngularMotor(true, Bt(speed), Bt(j.def.motor.maxForce * kDt));
      }
      c = std::move(h);
      break;
    }
    case RJointType::kSlider: {
      if (!world || j.def.motor.enabled) {
        std::fprintf(stderr, "bench_joints: only a slider to the world without a motor is translated\n");
        std::exit(2);
      }
      // Bullet's one-body slider holds its body as B; its travel is B's along the axis, as
      // REngine's is a's relative to the world.
      const RQuat frame_W = FrameWithX(j.def.axis_W.normalized());
      auto s = std::make_unique<btSliderConstraint>(A, BtFrame(qA.conjugate() * frame_W, pivotA), true);
      if (j.def.hasLimits) {
        s->setLowerLinLimit(Bt(j.def.lower));
        s->setUpperLinLimit(Bt(j.def.upper));
      }
      c = std::move(s);
      break;
    }
    case RJointType::kFixed: {
      if (world) {
        std::fprintf(stderr, "bench_joints: a weld to the world is not translated\n");
        std::exit(2);
      }
      c = std::make_unique<btFixedConstraint>(A, *B, BtFrame(qA.conjugate(), pivotA),
                                              BtFrame(qB.conjugate(), pivotB));
      break;
    }
    case RJointType::kDistance: {
      if (!world || j.minDistance > 0) {
        std::fprintf(stderr, "bench_joints: only a rope (min 0) to the world is translated\n");
        std::exit(2);
      }
      // The rope's direction at the start, from the world point to the body's anchor: x of
      // both frames. Bullet's one-body constraint holds its body as B; x is B's travel.
      const RVec3 onBody_W = ra.Position_W() + qA * pivotA;
      const RVec3 along = onBody_W - pivotB;
      const RScalar d0 = along.norm();
      const RQuat frame_W = FrameWithX(along / d0);
      auto g = std::make_unique<btGeneric6DofSpring2Constraint>(A, BtFrame(qA.conjugate() * frame_W, pivotA));
      g->setLinearLowerLimit(btVector3(Bt(-1e3), 1, 1));  // lower > upper: free
      g->setLinearUpperLimit(btVector3(Bt(j.maxDistance - d0), -1, -1));
      g->setAngularLowerLimit(btVector3(1, 1, 1));
      g->setAngularUpperLimit(btVector3(-1, -1, -1));
      c = std::move(g);
      break;
    }
  }
  w.world.addConstraint(c.get(), !j.def.collideConnected);
  return c;
}

Run RunBullet(Scene& scene) {
  RBodies bodies;
  scene.Build(bodies);
  const RWorldSettings settings = Settings(scene);
  const std::vector<RRigidBody> reference(bodies.begin(), bodies.end());
  const BulletCoefficients coeffs = ChooseCoefficients(settings, reference, false);
  std::unique_ptr<BulletWorld> w = BuildBullet(settings, reference, coeffs, /*sleep=*/false);
  std::vector<std::unique_ptr<btTypedConstraint>> joints;
  for (std::size_t k = 0; k < bodies.JointCount(); ++k) joints.push_back(BulletJoint(*w, bodies, bodies.JointAt(k)));
  std::vector<State> s = Masses(bodies);
  auto read = [&] {
    for (std::size_t i = 0; i < s.size(); ++i) {
      const btRigidBody& b = *w->bodies[i];
      s[i].x = R(b.getCenterOfMassPosition()), s[i].q = R(b.getOrientation());
      s[i].v = R(b.getLinearVelocity()), s[i].w = R(b.getAngularVelocity());
    }
  };
  read();
  scene.Begin(s);
  Run run;
  for (int step = 1; step <= scene.steps; ++step) {
    const auto t0 = Clock::now();
    w->world.stepSimulation(Bt(kDt), 0);
    run.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    read();
    scene.Observe(step, s);
  }
  run.figures = scene.Figures();
  for (auto& c : joints) w->world.removeConstraint(c.get());
  return run;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 7;
  std::string csvPath;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repeats" && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "--csv" && i + 1 < argc) {
      csvPath = argv[++i];
    } else if (arg == "--quick") {
      repeats = 1;
    } else {
      std::fprintf(stderr,
                   "usage: bench_joints [--repeats N (default 7)] [--csv FILE] [--quick (one repeat)]\n"
                   "REngine's joints against Bullet's on joints_test's closed-form scenes, 60 Hz,\n"
                   "%d iterations; see the source's comment for the scenes and Bullet's joints.\n",
                   kIterations);
      return arg == "--help" || arg == "-h" ? 0 : 2;
    }
  }
  std::vector<std::unique_ptr<Scene>> scenes;
  scenes.push_back(std::make_unique<Pendulum>());
  scenes.push_back(std::make_unique<Motor>());
  scenes.push_back(std::make_unique<Chain>());
  scenes.push_back(std::make_unique<Rope>());
  scenes.push_back(std::make_unique<Slider>());
  scenes.push_back(std::make_unique<Weld>());

  std::FILE* csv = nullptr;
  if (!csvPath.empty()) {
    csv = std::fopen(csvPath.c_str(), "w");
    if (!csv) {
      std::fprintf(stderr, "bench_joints: cannot write %s\n", csvPath.c_str());
      return 1;
    }
    std::fprintf(csv, "scene,engine,steps,dt,iterations,repeats,us_per_step");
    for (int k = 1; k <= 5; ++k) std::fprintf(csv, ",figure%d,value%d", k, k);
    std::fprintf(csv, "\n");
  }
  std::printf("bench_joints: 60 Hz, %d iterations, %d interleaved repeats; Bullet %d (%s precision)\n",
              kIterations, repeats, btGetVersion(), sizeof(btScalar) == 8 ? "double" : "single");
  bool finite = true;
  for (auto& scene : scenes) {
    std::vector<double> times[2];
    std::vector<Figure> figures[2];
    for (int r = 0; r < repeats; ++r) {
      for (int e = 0; e < 2; ++e) {
        const Run run = e == 0 ? RunREngine(*scene) : RunBullet(*scene);
        times[e].push_back(run.seconds / scene->steps * 1e6);
        if (r == 0) figures[e] = run.figures;
      }
    }
    std::printf("\n%s: %s, %d steps\n", scene->name.c_str(), scene->title.c_str(), scene->steps);
    std::printf("  %-40s %12s %12s\n", "", "REngine", "Bullet");
    std::printf("  %-40s %12.3f %12.3f\n", "us/step (median)", Median(times[0]), Median(times[1]));
    for (std::size_t k = 0; k < figures[0].size(); ++k) {
      std::printf("  %-40s %12.3e %12.3e\n", figures[0][k].name.c_str(), figures[0][k].value, figures[1][k].value);
      finite = finite && std::isfinite(figures[0][k].value);
    }
    if (csv) {
      for (int e = 0; e < 2; ++e) {
        std::fprintf(csv, "%s,%s,%d,%.17g,%d,%d,%.4f", scene->name.c_str(), e == 0 ? "rengine" : "bullet",
                     scene->steps, kDt, kIterations, repeats, Median(times[e]));
        for (std::size_t k = 0; k < 5; ++k) {
          if (k < figures[e].size()) std::fprintf(csv, ",\"%s\",%.6e", figures[e][k].name.c_str(), figures[e][k].value);
          else std::fprintf(csv, ",,");
        }
        std::fprintf(csv, "\n");
      }
    }
  }
  if (csv) std::fclose(csv);
  // REngine's figures are always finite; a NaN is a broken run (the smoke test's check).
  return finite ? 0 : 1;
}
