// rengine-bench: work-precision benchmark (issue #6, "benchmark run time against error").
//
//   rengine-bench [--scenes a,b,...] [--csv FILE] [--repeats N] [--quick]
//   rengine-bench --shortcuts [--csv FILE] [--repeats N] [--quick]   (see shortcuts.h)
//
// Runs reference scenes whose answer is known in closed form (or whose conserved quantities
// are) over a grid of step sizes (and, for contact scenes, solver iterations), and writes one
// CSV row per run and engine:
//
//   scene,method,dt,iterations,ms_per_step,error,energy_drift,momentum_drift
//
// method is `REngine`, and `bullet` where Bullet was found at configure time
// (RENGINE_HAVE_BULLET): every scene is then also run on Bullet, in the same process, with
// the same bodies, step and solver iterations (btContactSolverInfo::m_numIterations), built by
// tools/bench/BulletWorld.h as bench_bullet builds its worlds (exact mass properties from
// REngine, static bodies as mass 0, restitution and friction mapped so that Bullet's product
// of the pair's values equals REngine's combined value, sleeping off), stepped with
// stepSimulation(dt, 0) (one internal step of dt per call). Its errors are computed from
// Bullet's state exactly as REngine's are.
//
// ms_per_step is the median over --repeats timed runs (after one untimed run) of the
// steady_clock time around the step loop only, divided by the step count. The errors come
// from the untimed run, which observes every step; both engines are deterministic, so the
// timed runs step exactly the same trajectory without paying for the observation.
// `iterations` is empty for scenes without contacts (the solver never runs), and an error
// column is empty where the quantity is not conserved or not defined for the scene.
//
// Scenes and their `error` (all dimensionless unless a unit is given):
//   tumbling      box, half extents (0.5, 0.3, 0.1), 1 kg, no gravity, spun about its
//                 intermediate axis, w = (0.01, 5, 0.01) rad/s (as in the shared
//                 dzhanibekov.json), 10 s. error = momentum_drift = max over steps of
//                 |L(t) - L(0)| / |L(0)| (world angular momentum); energy_drift = max over
//                 steps of |E(t) - E(0)| / E(0) (kinetic energy).
//   projectile    sphere under g = 9.81 m/s^2, launched at 30 m/s, 40 deg, 3 s, no contacts.
//                 error = |x(T) - (x0 + v0 T + g T^2/2)|, m; energy_drift = max over steps
//                 of |E(t) - E(0)| / E(0), E kinetic plus potential.
//   elastic_pair  two spheres head-on, e = 1, masses 1 and 3.7 kg at 3 and -1 m/s, 2 s.
//                 error = max over bodies and over the steps that end at least one step
//                 after the contact time of |v - v'| / |v'|, v' the closed-form velocity
//                 after the collision; energy_drift = max |dE| / E(0); momentum_drift =
//                 max |dP| / sum(m |v0|).
//   inelastic_pair  the same pair with e = 0.5: v1' = (m1 v1 + m2 v2 - m2 e (v1 - v2)) / M,
//                 v2' = (m1 v1 + m2 v2 + m1 e (v1 - v2)) / M, M = m1 + m2. error as for
//                 elastic_pair; energy_drift = max over the same steps of |E - E'| / E(0), E'
//                 the closed-form kinetic energy after the collision; momentum_drift as for
//                 elastic_pair.
//   sliding_box   unit box (1 kg) on a static floor (top at y = 0), mu = 0.5, v0 = 5 m/s,
//                 3 s. error = |d - v0^2/(2 mu g)| / (v0^2/(2 mu g)), d the distance slid.
//   incline       unit box (1 kg) at rest on a static 20 deg incline, mu = 0.2 on both
//                 bodies (the geometric combine gives 0.2), 2 s: it slides (tan 20 deg >
//                 0.2) 3.0 m of the 10 m left before the incline's end. error =
//                 |d - g (sin t - mu cos t) T^2 / 2| / (g (sin t - mu cos t) T^2 / 2), d the
//                 centre of mass's displacement down the slope.
//   stack10       ../shared/scenes/box_stack_10.json with the grid's dt and iterations, for
//                 the scene's duration (steps x dt). error = |x_top(T) - x_top(0)|, m: the
//                 top box's drift from its start (it should rest).
//   debris_cloud  ../shared/scenes/debris_cloud_1000.json (1000 unit boxes, zero g, e = 1, no
//                 friction) with the grid's dt and iterations, for 2 s (1 s in --quick). No
//                 closed form; what the exact motion conserves: error = |E(T) - E(0)| / E(0),
//                 the final relative change of kinetic energy (elastic and frictionless: the
//                 exact answer keeps E(0)); energy_drift = max over steps of
//                 (E(t) - E(0)) / E(0), SIGNED: > 0 is a gain, which must never happen;
//                 <= 0 means the energy never rose above its start; momentum_drift = max over
//                 steps of |P(t) - P(0)| / sum(m |v0|).
//   asteroid_field  150 random convex hulls (12 to 24 points on a rough ellipsoid, semi-axes
//                 0.5 to 1.2 m, 2500 kg/m^3) on a 5 x 5 x 6 grid 4 m apart, random
//                 orientations, velocities up to 1.5 m/s and spins up to 2 rad/s per axis
//                 (std::mt19937_64, fixed seed, our own uniform mapping: the same field on
//                 every platform), zero g, e = 1, no friction, 3 s (1 s in --quick); about a
//                 quarter collide (34 of 150 in REngine's run at 1/30 s, 38 in Bullet's).
//                 error = max over steps of |L(t) - L(0)| / sum(|x x m v| + |L_spin|)(0),
//                 L = sum(x x m v + L_spin) the angular momentum about the origin (conserved:
//                 contact forces are internal and act along one line between the bodies,
//                 friction or not); energy_drift and momentum_drift as for debris_cloud.
//
// Cost: debris_cloud and asteroid_field dominate the run (1000 and 150 bodies); they run the
// same grid as the other contact scenes. The full run takes under 2 minutes on the 2-core
// development machine, Bullet included; --quick under 1 s.
//
// Exit codes: 0 success; 2 bad input (options, a scene file, the CSV path).
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#ifdef RENGINE_HAVE_BULLET
#include "BulletWorld.h"
#endif

#include <CLI/CLI.hpp>

#include "shortcuts.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using namespace REngine;

namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;
constexpr RScalar kG = RScalar(9.81);  // m/s^2

using Clock = std::chrono::steady_clock;

// A bad command line: reported like rengine-sim's, exit code 2.
struct UsageError {
  std::string message;
};

// One point of the grid.
struct GridPoint {
  RScalar dt = 0;      // s
  int iterations = 0;  // contact solver passes (both engines)
  bool quick = false;  // --quick: the expensive scenes run a shorter time
};

// A world ready to step: what a scene builds for one grid point, for either engine.
struct World {
  RWorldSettings settings;
  std::vector<RRigidBody> bodies;
  RScalar dt = 0;  // s
  std::uint64_t steps = 0;
};

// A run's errors against the closed form; unset: not applicable to the scene (empty field).
struct Errors {
  std::optional<double> error, energyDrift, momentumDrift;
};

// Whole steps covering `duration` seconds: every duration and step size in the grid divide
// exactly, so this is the exact count, not a rounding of it.
std::uint64_t StepsFor(RScalar duration, RScalar dt) {
  return static_cast<std::uint64_t>(std::llround(duration / dt));
}

// ---- engines ----------------------------------------------------------------------------
// The errors are computed from this state, read the same way from either engine: centre of
// mass, orientation of the principal frame, world velocities, and REngine's exact mass
// properties (which both engines were given).

struct BodyState {
  bool isStatic = false;
  RScalar mass = 0;                 // kg (0 when static)
  RVec3 inertia_B = RVec3::Zero();  // principal moments, kg m^2
  RVec3 x_W = RVec3::Zero();        // centre of mass, m
  RQuat q_WB = RQuat::Identity();
  RVec3 v_W = RVec3::Zero();        // m/s
  RVec3 w_W = RVec3::Zero();        // rad/s

  RVec3 Momentum_W() const { return mass * v_W; }
  // About the centre of mass, world frame, kg m^2/s.
  RVec3 SpinMomentum_W() const { return q_WB * inertia_B.cwiseProduct(q_WB.conjugate() * w_W); }
  RScalar Kinetic() const {
    const RVec3 w_B = q_WB.conjugate() * w_W;
    return RScalar(0.5) * mass * v_W.squaredNorm() +
           RScalar(0.5) * w_B.dot(inertia_B.cwiseProduct(w_B));
  }
};
using State = std::vector<BodyState>;

RScalar KineticEnergy(const State& s) {
  RScalar e = 0;
  for (const BodyState& b : s) e += b.Kinetic();
  return e;
}

RVec3 Momentum_W(const State& s) {
  RVec3 p = RVec3::Zero();
  for (const BodyState& b : s) p += b.Momentum_W();
  return p;
}

// Sum of m |v|: what a momentum drift is relative to (the total may cancel to nearly 0).
RScalar MomentumScale(const State& s) {
  RScalar sum = 0;
  for (const BodyState& b : s) sum += b.mass * b.v_W.norm();
  return sum;
}

// Angular momentum about the world origin, kg m^2/s, and its scale sum(|x x m v| + |L_spin|).
RVec3 AngularMomentumAboutOrigin_W(const State& s) {
  RVec3 l = RVec3::Zero();
  for (const BodyState& b : s) l += b.x_W.cross(b.Momentum_W()) + b.SpinMomentum_W();
  return l;
}
RScalar AngularMomentumScale(const State& s) {
  RScalar sum = 0;
  for (const BodyState& b : s) {
    sum += b.x_W.cross(b.Momentum_W()).norm() + b.SpinMomentum_W().norm();
  }
  return sum;
}

enum class Method { kREngine, kBullet };

const char* MethodName(Method m) { return m == Method::kREngine ? "REngine" : "bullet"; }

// One engine stepping one world. Step(n) loops inside, so timing a run costs one virtual
// call, not one per step.
class Engine {
 public:
  Engine(RScalar dt, std::uint64_t steps) : m_dt(dt), m_steps(steps) {}
  virtual ~Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  RScalar Dt() const { return m_dt; }
  std::uint64_t Steps() const { return m_steps; }
  virtual void Step(std::uint64_t n) = 0;
  virtual void Read(State& out) const = 0;

 private:
  RScalar m_dt;
  std::uint64_t m_steps;
};

class REngineEngine final : public Engine {
  // The grid measures the solver: every body simulated every step, as Bullet's are with its
  // sleeping off. What sleeping and the other shortcuts buy is --shortcuts' subject.
  static World Unslept(World w) {
    w.settings.shortcuts.sleeping = false;
    return w;
  }

 public:
  explicit REngineEngine(World world)
      : Engine(world.dt, world.steps), m_world(Unslept(std::move(world))), m_integrator(m_world.settings) {}
  void Step(std::uint64_t n) override {
    for (std::uint64_t i = 0; i < n; ++i) m_integrator.Update(m_world.bodies, m_world.dt);
  }
  void Read(State& out) const override {
    out.resize(m_world.bodies.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
      const RRigidBody& b = m_world.bodies[i];
      out[i] = {b.IsStatic(),       b.Mass(),       b.Inertia_B(),        b.Position_W(),
                b.Orientation_WB(), b.Velocity_W(), b.AngularVelocity_W()};
    }
  }

 private:
  World m_world;
  RIntegrator m_integrator;
};

#ifdef RENGINE_HAVE_BULLET
class BulletEngine final : public Engine {
 public:
  // The World keeps REngine's bodies: the Bullet world points to them for mass properties,
  // so they stay here, unmoved, for the engine's life.
  explicit BulletEngine(World world) : Engine(world.dt, world.steps), m_world(std::move(world)) {
    const bench::BulletCoefficients coeffs =
        bench::ChooseCoefficients(m_world.settings, m_world.bodies, /*match=*/true);
    m_bullet = bench::BuildBullet(m_world.settings, m_world.bodies, coeffs, /*sleep=*/false);
    // Gyroscopic term: BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY, the flag Bullet recommends
    // for a free tumbling body (btRigidBody.h: BT_ENABLE_GYROPSCOPIC_FORCE is an alias of it,
    // on by default since 2.83; the explicit variant is unstable at large spins and the
    // implicit world-frame one is the less accurate of the two implicit forms, per Bullet's
    // GyroscopicDemo). Set explicitly so the choice does not depend on the default.
    const int gyro = BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT |
                     BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD |
                     BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY;
    for (auto& b : m_bullet->bodies) {
      if (b->isStaticObject()) continue;
      b->setFlags((b->getFlags() & ~gyro) | BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
    }
  }
  void Step(std::uint64_t n) override {
    const btScalar dt = bench::Bt(m_world.dt);
    for (std::uint64_t i = 0; i < n; ++i) m_bullet->world.stepSimulation(dt, 0);
  }
  void Read(State& out) const override {
    out.resize(m_bullet->bodies.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
      const RRigidBody& ref = *m_bullet->reference[i];
      const btRigidBody& b = *m_bullet->bodies[i];
      const btTransform& X_WB = b.getCenterOfMassTransform();
      out[i] = {ref.IsStatic(),
                ref.Mass(),
                ref.Inertia_B(),
                bench::R(X_WB.getOrigin()),
                bench::R(X_WB.getRotation()),
                ref.IsStatic() ? RVec3(RVec3::Zero()) : bench::R(b.getLinearVelocity()),
                ref.IsStatic() ? RVec3(RVec3::Zero()) : bench::R(b.getAngularVelocity())};
    }
  }

 private:
  World m_world;
  std::unique_ptr<bench::BulletWorld> m_bullet;
};
#endif

std::unique_ptr<Engine> MakeEngine(Method method, World world) {
#ifdef RENGINE_HAVE_BULLET
  if (method == Method::kBullet) return std::make_unique<BulletEngine>(std::move(world));
#endif
  (void)method;
  return std::make_unique<REngineEngine>(std::move(world));
}

// Steps an engine through its world, calling afterStep(state, t) with the state and the time
// at the end of each step. Time is a product, not a running sum, so the contact-time tests
// below carry no accumulated rounding.
template <class AfterStep>
void Simulate(Engine& engine, AfterStep&& afterStep) {
  State state;
  for (std::uint64_t step = 1; step <= engine.Steps(); ++step) {
    engine.Step(1);
    engine.Read(state);
    afterStep(state, static_cast<RScalar>(step) * engine.Dt());
  }
}

State Initial(const Engine& engine) {
  State s;
  engine.Read(s);
  return s;
}

// ---- bodies -----------------------------------------------------------------------------

RBodyDef Sphere(const std::string& name, RScalar radius, RScalar mass) {
  RBodyDef def;
  def.name = name;
  def.shape.type = RShapeType::kSphere;
  def.shape.radius = radius;
  def.mass = mass;
  return def;
}

RBodyDef Box(const std::string& name, const RVec3& halfExtents, std::optional<RScalar> mass) {
  RBodyDef def;
  def.name = name;
  def.shape.type = RShapeType::kBox;
  def.shape.halfExtents = halfExtents;
  def.isStatic = !mass;
  def.mass = mass;
  return def;
}

// ---- tumbling ---------------------------------------------------------------------------
// Torque-free, so energy and world angular momentum are conserved exactly; near the
// intermediate axis the motion is unstable (Dzhanibekov flips), which is what makes a
// stepper that approximates the rotation drift.

World TumblingWorld(const GridPoint& p) {
  World w;
  RBodyDef box = Box("box", RVec3(0.5, 0.3, 0.1), RScalar(1));
  box.angularVelocity_W = RVec3(0.01, 5.0, 0.01);
  w.bodies.emplace_back(box);
  w.dt = p.dt;
  w.steps = StepsFor(10, p.dt);
  return w;
}

Errors TumblingErrors(Engine& engine) {
  const BodyState b0 = Initial(engine)[0];
  const RScalar e0 = b0.Kinetic();
  const RVec3 l0 = b0.SpinMomentum_W();
  double dE = 0, dL = 0;
  Simulate(engine, [&](const State& s, RScalar) {
    const BodyState& b = s[0];
    dE = std::max(dE, double(std::abs(b.Kinetic() - e0) / e0));
    dL = std::max(dL, double((b.SpinMomentum_W() - l0).norm() / l0.norm()));
  });
  return {dL, dE, dL};
}

// ---- projectile -------------------------------------------------------------------------

const RVec3 kGravity_W(0, -kG, 0);

RVec3 LaunchVelocity_W() {
  const RScalar angle = 40 * kPi / 180;
  return 30 * RVec3(std::cos(angle), std::sin(angle), 0);
}

World ProjectileWorld(const GridPoint& p) {
  World w;
  w.settings.gravity_W = kGravity_W;
  RBodyDef ball = Sphere("ball", 0.1, 1);
  ball.velocity_W = LaunchVelocity_W();
  w.bodies.emplace_back(ball);
  w.dt = p.dt;
  w.steps = StepsFor(3, p.dt);
  return w;
}

Errors ProjectileErrors(Engine& engine) {
  const BodyState b0 = Initial(engine)[0];
  const RVec3 x0 = b0.x_W, v0 = b0.v_W;
  // Energy with the potential of uniform gravity, m (-g . x).
  const auto energy = [](const BodyState& b) {
    return b.Kinetic() - b.mass * kGravity_W.dot(b.x_W);
  };
  const RScalar e0 = energy(b0);
  double dE = 0;
  RScalar tEnd = 0;
  RVec3 xEnd = x0;
  Simulate(engine, [&](const State& s, RScalar t) {
    dE = std::max(dE, double(std::abs(energy(s[0]) - e0) / e0));
    tEnd = t;
    xEnd = s[0].x_W;
  });
  const RVec3 exact = x0 + v0 * tEnd + RScalar(0.5) * kGravity_W * tEnd * tEnd;
  return {double((xEnd - exact).norm()), dE, std::nullopt};
}

// ---- elastic_pair, inelastic_pair -------------------------------------------------------
// Radii 0.5 m, centres 4 m apart: they close at 4 m/s over a 3 m gap and touch at 0.75 s.

// Masses whose outcome is not exact in binary (1 and 3 kg give -3 and 1 m/s exactly, and
// every setting would show an error of 0).
constexpr RScalar kPairM1 = 1, kPairM2 = 3.7, kPairV1 = 3, kPairV2 = -1;
constexpr RScalar kPairContactTime = 0.75;  // s
constexpr RScalar kInelasticE = 0.5;

World PairWorld(const GridPoint& p, RScalar restitution) {
  World w;
  w.settings.solverIterations = p.iterations;
  RBodyDef a = Sphere("a", 0.5, kPairM1), b = Sphere("b", 0.5, kPairM2);
  a.position_W = RVec3(-2, 0, 0);
  b.position_W = RVec3(2, 0, 0);
  a.velocity_W = RVec3(kPairV1, 0, 0);
  b.velocity_W = RVec3(kPairV2, 0, 0);
  for (RBodyDef* def : {&a, &b}) {
    def->restitution = restitution;  // the same on both: min combine = the value
    def->friction = 0;
    w.bodies.emplace_back(*def);
  }
  w.dt = p.dt;
  w.steps = StepsFor(2, p.dt);
  return w;
}
World ElasticPairWorld(const GridPoint& p) { return PairWorld(p, 1); }
World InelasticPairWorld(const GridPoint& p) { return PairWorld(p, kInelasticE); }

// e = 1: energy_drift over every step against E(0). e < 1: over the steps after the contact,
// against the closed-form energy after it.
Errors PairErrors(Engine& engine, RScalar e) {
  // 1D collision with restitution e (Newton's law, momentum conserved):
  //   v1' = (m1 v1 + m2 v2 - m2 e (v1 - v2)) / M,  v2' = (m1 v1 + m2 v2 + m1 e (v1 - v2)) / M.
  const RScalar m = kPairM1 + kPairM2;
  const RScalar p = kPairM1 * kPairV1 + kPairM2 * kPairV2, approach = kPairV1 - kPairV2;
  const RVec3 after[2] = {RVec3((p - kPairM2 * e * approach) / m, 0, 0),
                          RVec3((p + kPairM1 * e * approach) / m, 0, 0)};
  const RScalar eAfter = RScalar(0.5) * kPairM1 * after[0].squaredNorm() +
                         RScalar(0.5) * kPairM2 * after[1].squaredNorm();
  const State s0 = Initial(engine);
  const RScalar e0 = KineticEnergy(s0);
  const RVec3 p0 = Momentum_W(s0);
  // Drift relative to the momentum the bodies carry (the total is small: 3 - 3.7 kg m/s).
  const RScalar pScale = kPairM1 * std::abs(kPairV1) + kPairM2 * std::abs(kPairV2);
  const RScalar dt = engine.Dt();
  const bool elastic = e == 1;
  double dV = 0, dE = 0, dP = 0;
  Simulate(engine, [&](const State& s, RScalar t) {
    dP = std::max(dP, double((Momentum_W(s) - p0).norm() / pScale));
    if (elastic) dE = std::max(dE, double(std::abs(KineticEnergy(s) - e0) / e0));
    // A step ending exactly at the contact time may report either side of it; a full step
    // later the collision must have happened whatever the step size.
    if (t < kPairContactTime + dt) return;
    if (!elastic) dE = std::max(dE, double(std::abs(KineticEnergy(s) - eAfter) / e0));
    for (int i = 0; i < 2; ++i) {
      dV = std::max(dV, double((s[i].v_W - after[i]).norm() / after[i].norm()));
    }
  });
  return {dV, dE, dP};
}
Errors ElasticPairErrors(Engine& engine) { return PairErrors(engine, 1); }
Errors InelasticPairErrors(Engine& engine) { return PairErrors(engine, kInelasticE); }

// ---- sliding_box ------------------------------------------------------------------------

constexpr RScalar kSlideMu = 0.5, kSlideV0 = 5;  // -, m/s

World SlidingBoxWorld(const GridPoint& p) {
  World w;
  w.settings.gravity_W = kGravity_W;
  w.settings.solverIterations = p.iterations;
  RBodyDef floor = Box("floor", RVec3(50, 0.5, 50), std::nullopt);
  floor.position_W = RVec3(0, -0.5, 0);
  RBodyDef box = Box("box", RVec3(0.5, 0.5, 0.5), RScalar(1));
  box.position_W = RVec3(0, 0.5, 0);
  box.velocity_W = RVec3(kSlideV0, 0, 0);
  // The default combine (geometric mean) of two equal coefficients is that coefficient.
  for (RBodyDef* def : {&floor, &box}) {
    def->friction = kSlideMu;
    def->restitution = 0;
    w.bodies.emplace_back(*def);
  }
  w.dt = p.dt;
  w.steps = StepsFor(3, p.dt);  // it stops after v0 / (mu g) = 1.02 s
  return w;
}

Errors SlidingBoxErrors(Engine& engine) {
  const RScalar x0 = Initial(engine)[1].x_W.x();
  RScalar x = x0;
  Simulate(engine, [&](const State& s, RScalar) { x = s[1].x_W.x(); });
  const RScalar exact = kSlideV0 * kSlideV0 / (2 * kSlideMu * kG);
  return {double(std::abs(x - x0 - exact) / exact), std::nullopt, std::nullopt};
}

// ---- incline ----------------------------------------------------------------------------
// A static box (half extents 10 x 0.5 x 3 m) turned 20 deg about z: its top face rises
// towards +x. The unit box starts at rest on it, 7 m up the slope from the incline's centre,
// and slides down (towards -x) with a = g (sin t - mu cos t) = 1.51 m/s^2: 3.0 m in 2 s.

constexpr RScalar kInclineDeg = 20, kInclineMu = 0.2, kInclineT = 2;  // deg, -, s

RQuat InclineRotation() {
  return RQuat(Eigen::AngleAxis<RScalar>(kInclineDeg * kPi / 180, RVec3::UnitZ()));
}

World InclineWorld(const GridPoint& p) {
  World w;
  w.settings.gravity_W = kGravity_W;
  w.settings.solverIterations = p.iterations;
  const RQuat q = InclineRotation();
  RBodyDef incline = Box("incline", RVec3(10, 0.5, 3), std::nullopt);
  incline.q_WS = q;
  RBodyDef box = Box("box", RVec3(0.5, 0.5, 0.5), RScalar(1));
  box.q_WS = q;
  box.position_W = q * RVec3(7, 1, 0);  // face on face: the incline's top is at local y 0.5
  // Geometric combine (the default) of 0.2 and 0.2 is 0.2.
  for (RBodyDef* def : {&incline, &box}) {
    def->friction = kInclineMu;
    def->restitution = 0;
    w.bodies.emplace_back(*def);
  }
  w.dt = p.dt;
  w.steps = StepsFor(kInclineT, p.dt);
  return w;
}

Errors InclineErrors(Engine& engine) {
  const RScalar theta = kInclineDeg * kPi / 180;
  const RVec3 down_W = InclineRotation() * RVec3(-1, 0, 0);
  const RVec3 x0 = Initial(engine)[1].x_W;
  RVec3 x = x0;
  Simulate(engine, [&](const State& s, RScalar) { x = s[1].x_W; });
  const RScalar exact =
      kG * (std::sin(theta) - kInclineMu * std::cos(theta)) * kInclineT * kInclineT / 2;
  return {double(std::abs((x - x0).dot(down_W) - exact) / exact), std::nullopt, std::nullopt};
}

// ---- stack10 ----------------------------------------------------------------------------

const RScene& StackScene() {
  static const RScene scene = LoadScene(RENGINE_SHARED_SCENES "/box_stack_10.json");
  return scene;
}

// A shared scene at the grid point's dt and iterations, for `duration` seconds.
World SceneWorld(const RScene& scene, const GridPoint& p, RScalar duration) {
  World w;
  w.settings = scene.settings;
  w.settings.solverIterations = p.iterations;
  w.bodies = CreateBodies(scene);
  w.dt = p.dt;
  w.steps = StepsFor(duration, p.dt);
  return w;
}

World StackWorld(const GridPoint& p) {
  const RScene& scene = StackScene();
  return SceneWorld(scene, p, static_cast<RScalar>(scene.steps) * scene.dt);
}

Errors StackErrors(Engine& engine) {
  const State s0 = Initial(engine);
  // The top box: the dynamic body that starts highest.
  std::size_t top = 0;
  for (std::size_t i = 0; i < s0.size(); ++i) {
    if (s0[i].isStatic) continue;
    if (s0[top].isStatic || s0[i].x_W.y() > s0[top].x_W.y()) top = i;
  }
  RVec3 x = s0[top].x_W;
  Simulate(engine, [&](const State& s, RScalar) { x = s[top].x_W; });
  return {double((x - s0[top].x_W).norm()), std::nullopt, std::nullopt};
}

// ---- debris_cloud, asteroid_field: conserved quantities ---------------------------------

// Over an elastic, frictionless, zero-g run: kinetic energy (max signed gain, final change),
// momentum and angular momentum about the origin (max drifts).
struct Conservation {
  double finalEnergyChange = 0;  // |E(T) - E0| / E0
  double maxEnergyGain = std::numeric_limits<double>::lowest();  // max (E(t) - E0) / E0
  double momentumDrift = 0;      // max |P(t) - P0| / sum m|v0|
  double angularDrift = 0;       // max |L(t) - L0| / sum(|x x m v| + |L_spin|)(0)
};

Conservation MeasureConservation(Engine& engine) {
  const State s0 = Initial(engine);
  const RScalar e0 = KineticEnergy(s0);
  const RVec3 p0 = Momentum_W(s0), l0 = AngularMomentumAboutOrigin_W(s0);
  const RScalar pScale = MomentumScale(s0), lScale = AngularMomentumScale(s0);
  Conservation c;
  RScalar e = e0;
  Simulate(engine, [&](const State& s, RScalar) {
    e = KineticEnergy(s);
    c.maxEnergyGain = std::max(c.maxEnergyGain, double((e - e0) / e0));
    c.momentumDrift = std::max(c.momentumDrift, double((Momentum_W(s) - p0).norm() / pScale));
    c.angularDrift =
        std::max(c.angularDrift, double((AngularMomentumAboutOrigin_W(s) - l0).norm() / lScale));
  });
  c.finalEnergyChange = double(std::abs(e - e0) / e0);
  return c;
}

const RScene& DebrisScene() {
  static const RScene scene = LoadScene(RENGINE_SHARED_SCENES "/debris_cloud_1000.json");
  return scene;
}

World DebrisWorld(const GridPoint& p) { return SceneWorld(DebrisScene(), p, p.quick ? 1 : 2); }

Errors DebrisErrors(Engine& engine) {
  const Conservation c = MeasureConservation(engine);
  return {c.finalEnergyChange, c.maxEnergyGain, c.momentumDrift};
}

// A uniform double in [0, 1) from the top 53 bits: std::mt19937_64's output is specified
// by the standard, this mapping too (std::uniform_real_distribution's is not).
RScalar Uniform(std::mt19937_64& rng, RScalar lo, RScalar hi) {
  const RScalar u = static_cast<RScalar>(rng() >> 11) * RScalar(0x1.0p-53);
  return lo + (hi - lo) * u;
}
// Components drawn in x, y, z order (a constructor's arguments have no evaluation order).
RVec3 UniformVec(std::mt19937_64& rng, RScalar lo, RScalar hi) {
  const RScalar x = Uniform(rng, lo, hi);
  const RScalar y = Uniform(rng, lo, hi);
  const RScalar z = Uniform(rng, lo, hi);
  return RVec3(x, y, z);
}

// A rock: 12 to 24 points on an ellipsoid with random semi-axes, each pulled in by up to 20%.
std::vector<RVec3> RockPoints(std::mt19937_64& rng) {
  const RVec3 semiAxes = UniformVec(rng, 0.5, 1.2);
  const int n = 12 + static_cast<int>(rng() % 13);
  std::vector<RVec3> points;
  for (int k = 0; k < n; ++k) {
    RVec3 d;
    do {
      d = UniformVec(rng, -1, 1);
    } while (d.squaredNorm() > 1 || d.squaredNorm() < 0.01);  // uniform directions
    const RScalar r = Uniform(rng, 0.8, 1.0);
    points.push_back((r / d.norm()) * d.cwiseProduct(semiAxes));
  }
  return points;
}

RQuat UniformRotation(std::mt19937_64& rng) {
  RVec3 v;
  RScalar w = 0;
  RScalar n2 = 0;
  do {
    v = UniformVec(rng, -1, 1);
    w = Uniform(rng, -1, 1);
    n2 = v.squaredNorm() + w * w;
  } while (n2 > 1 || n2 < 0.01);
  return RQuat(w, v.x(), v.y(), v.z()).normalized();
}

World AsteroidWorld(const GridPoint& p) {
  World w;  // zero gravity
  w.settings.solverIterations = p.iterations;
  std::mt19937_64 rng(20240601);
  constexpr int kNx = 5, kNy = 5, kNz = 6;
  constexpr RScalar kSpacing = 4;  // m: with 0.4 m of jitter and a rock within 1.2 m of its
                                   // origin, no two start closer than 3.2 - 2.4 = 0.8 m
  for (int i = 0; i < kNx; ++i) {
    for (int j = 0; j < kNy; ++j) {
      for (int k = 0; k < kNz; ++k) {
        RBodyDef rock;
        rock.name = "rock" + std::to_string((i * kNy + j) * kNz + k);
        rock.shape.type = RShapeType::kHull;
        rock.shape.points = RockPoints(rng);
        rock.density = 2500;
        const RVec3 cell(kSpacing * (i - RScalar(kNx - 1) / 2),
                         kSpacing * (j - RScalar(kNy - 1) / 2),
                         kSpacing * (k - RScalar(kNz - 1) / 2));
        rock.position_W = cell + UniformVec(rng, -0.4, 0.4);
        rock.q_WS = UniformRotation(rng);
        rock.velocity_W = UniformVec(rng, -1.5, 1.5);
        rock.angularVelocity_W = UniformVec(rng, -2, 2);
        rock.restitution = 1;
        rock.friction = 0;
        w.bodies.emplace_back(rock);
      }
    }
  }
  w.dt = p.dt;
  w.steps = StepsFor(p.quick ? 1 : 3, p.dt);
  return w;
}

// Position correction (split impulses) moves bodies without changing their velocities, so it
// changes x x m v: an engine that corrects overlap by moving bodies drifts here even when its
// impulses conserve L exactly.
Errors AsteroidErrors(Engine& engine) {
  const Conservation c = MeasureConservation(engine);
  return {c.angularDrift, c.maxEnergyGain, c.momentumDrift};
}

// ---- the scene table --------------------------------------------------------------------

struct Scene {
  const char* name;
  bool contacts;   // the solver runs: iterations is a grid axis
  bool expensive;  // --quick runs it at one grid point only (and a shorter time)
  World (*world)(const GridPoint& point);
  Errors (*errors)(Engine& engine);  // an observed run of the engine's world
};

const Scene kScenes[] = {
    {"tumbling", false, false, TumblingWorld, TumblingErrors},
    {"projectile", false, false, ProjectileWorld, ProjectileErrors},
    {"elastic_pair", true, false, ElasticPairWorld, ElasticPairErrors},
    {"inelastic_pair", true, false, InelasticPairWorld, InelasticPairErrors},
    {"sliding_box", true, false, SlidingBoxWorld, SlidingBoxErrors},
    {"incline", true, false, InclineWorld, InclineErrors},
    {"stack10", true, false, StackWorld, StackErrors},
    {"debris_cloud", true, true, DebrisWorld, DebrisErrors},
    {"asteroid_field", true, true, AsteroidWorld, AsteroidErrors},
};

constexpr const char* kErrorHelp = R"(Scenes and their `error` column (see also tools/rengine-bench/main.cpp):
  tumbling      box (0.5, 0.3, 0.1) spun near its intermediate axis, no gravity, 10 s:
                max |L(t) - L0| / |L0| (world angular momentum; also momentum_drift);
                energy_drift = max |E(t) - E0| / E0
  projectile    sphere, g = 9.81, 30 m/s at 40 deg, 3 s: |x(T) - closed form| (m);
                energy_drift = max |dE| / E0 (kinetic + potential)
  elastic_pair  spheres of 1 and 3.7 kg head-on at 3 and -1 m/s, e = 1, 2 s: max |v - v'| / |v'|
                over both bodies from one step after the contact; energy_drift = max |dE| / E0;
                momentum_drift = max |dP| / sum m|v0|
  inelastic_pair  the same with e = 0.5: v1' = (m1 v1 + m2 v2 - m2 e (v1 - v2)) / (m1 + m2),
                v2' = (m1 v1 + m2 v2 + m1 e (v1 - v2)) / (m1 + m2); error as elastic_pair;
                energy_drift = max |E - E'| / E0 from one step after the contact (E' closed
                form); momentum_drift = max |dP| / sum m|v0|
  sliding_box   unit box on a floor, mu = 0.5, v0 = 5 m/s, 3 s:
                |d - v0^2/(2 mu g)| / (v0^2/(2 mu g)), d the distance slid
  incline       unit box from rest on a static 20 deg incline, mu = 0.2, 2 s:
                |d - g (sin t - mu cos t) T^2/2| / (g (sin t - mu cos t) T^2/2), d slid
  stack10       box_stack_10.json for its duration: top box drift |x(T) - x(0)| (m)
  debris_cloud  debris_cloud_1000.json (zero g, e = 1, no friction), 2 s (1 s with --quick):
                |E(T) - E0| / E0 (kinetic; exact motion keeps E0); energy_drift = max over
                steps of (E(t) - E0) / E0, SIGNED (> 0: a gain); momentum_drift = max |dP| /
                sum m|v0|
  asteroid_field  150 random convex hulls (fixed seed), zero g, e = 1, no friction, 3 s (1 s
                with --quick): max |L(t) - L0| / sum(|x x m v| + |L_spin|)(0), L the angular
                momentum about the origin; energy_drift and momentum_drift as debris_cloud
Grid: dt in {1/30, 1/60, 1/120, 1/240, 1/480}; iterations in {4, 10, 20} for the contact
scenes (empty for the others). --quick: dt in {1/30, 1/120} (debris_cloud and
asteroid_field: 1/30 only), 10 iterations, 1 timed run. ms_per_step: median of the timed
repeats after one untimed run, which measures the errors. Empty error fields: not
applicable. Methods: REngine, and bullet when built with Bullet (same bodies, step and
iterations; see tools/bench/BulletWorld.h).)";

// ---- running and reporting --------------------------------------------------------------

struct Row {
  const char* scene;
  Method method;
  RScalar dt;
  std::optional<int> iterations;
  double msPerStep;
  Errors errors;
};

// One timed run: milliseconds per step of the step loop alone (building the world is not
// timed).
double TimeOneRun(const Scene& scene, Method method, const GridPoint& point) {
  const std::unique_ptr<Engine> engine = MakeEngine(method, scene.world(point));
  const Clock::time_point t0 = Clock::now();
  engine->Step(engine->Steps());
  const Clock::time_point t1 = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  return ms / static_cast<double>(engine->Steps());
}

double Median(std::vector<double> xs) {
  std::sort(xs.begin(), xs.end());
  const std::size_t n = xs.size();
  return n % 2 ? xs[n / 2] : 0.5 * (xs[n / 2 - 1] + xs[n / 2]);
}

std::string Number(const std::optional<double>& x, const char* format) {
  if (!x) return "";
  char text[32];
  std::snprintf(text, sizeof text, format, *x);
  return text;
}

std::string DtLabel(RScalar dt) {
  return "1/" + std::to_string(std::llround(1 / dt));
}

void PrintTableHeader() {
  std::printf("%-15s %-8s %-6s %5s %11s %11s %13s %15s\n", "scene", "method", "dt", "iter",
              "ms/step", "error", "energy_drift", "momentum_drift");
}

void PrintRow(const Row& r) {
  std::printf("%-15s %-8s %-6s %5s %11.4g %11s %13s %15s\n", r.scene, MethodName(r.method),
              DtLabel(r.dt).c_str(), r.iterations ? std::to_string(*r.iterations).c_str() : "-",
              r.msPerStep, Number(r.errors.error, "%.3e").c_str(),
              Number(r.errors.energyDrift, "%.3e").c_str(),
              Number(r.errors.momentumDrift, "%.3e").c_str());
  std::fflush(stdout);
}

bool WriteCsv(const std::string& path, const std::vector<Row>& rows) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) return false;
  std::fprintf(file,
               "scene,method,dt,iterations,ms_per_step,error,energy_drift,momentum_drift\n");
  for (const Row& r : rows) {
    std::fprintf(file, "%s,%s,%.17g,%s,%.6g,%s,%s,%s\n", r.scene, MethodName(r.method), r.dt,
                 r.iterations ? std::to_string(*r.iterations).c_str() : "", r.msPerStep,
                 Number(r.errors.error, "%.6e").c_str(),
                 Number(r.errors.energyDrift, "%.6e").c_str(),
                 Number(r.errors.momentumDrift, "%.6e").c_str());
  }
  const bool ok = !std::ferror(file);
  return std::fclose(file) == 0 && ok;
}

// Options are read as text and converted here: CLI11's integer parsing (strtoull, base 0)
// takes "-1" as 2^64 - 1 and "010" as 8 (the same reason as in rengine-sim).
int ParseRepeats(const std::string& text) {
  int n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || end != text.data() + text.size() || n < 1) {
    throw UsageError{"--repeats: must be an integer >= 1 (got \"" + text + "\")"};
  }
  return n;
}

std::string KnownScenes() {
  std::string known;
  for (const Scene& s : kScenes) known += std::string(known.empty() ? "" : ", ") + s.name;
  return known;
}

std::vector<const Scene*> ParseScenes(const std::string& list) {
  std::vector<const Scene*> chosen;
  if (list.empty()) {
    for (const Scene& s : kScenes) chosen.push_back(&s);
    return chosen;
  }
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    const Scene* found = nullptr;
    for (const Scene& s : kScenes) {
      if (name == s.name) found = &s;
    }
    if (!found) {
      throw UsageError{"--scenes: unknown scene \"" + name + "\" (known: " + KnownScenes() + ")"};
    }
    // Table order, not command-line order, and once each: the CSV is the same either way.
    if (std::find(chosen.begin(), chosen.end(), found) == chosen.end()) chosen.push_back(found);
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

#ifdef RENGINE_HAVE_BULLET
// Bullet multiplies a pair's coefficients; the mapping in BulletWorld.h matches REngine's
// combine for every scene here. Said once per scene if it ever does not.
void WarnCombineMismatch(const Scene& scene, const GridPoint& point) {
  const World w = scene.world(point);
  const bench::BulletCoefficients c = bench::ChooseCoefficients(w.settings, w.bodies, true);
  if (c.restitutionError > 1e-12) {
    std::printf("note: %s: Bullet's restitution differs from REngine's by up to %.3g (%s)\n",
                scene.name, c.restitutionError, c.restitutionExample.c_str());
  }
  if (c.frictionError > 1e-12) {
    std::printf("note: %s: Bullet's friction differs from REngine's by up to %.3g (%s)\n",
                scene.name, c.frictionError, c.frictionExample.c_str());
  }
}
#endif

int Run(int argc, char** argv) {
  CLI::App app{"Work-precision benchmark: ms/step against the error from a closed-form answer "
               "(or a conserved quantity), over a grid of step sizes and solver iterations; "
               "REngine, and Bullet where it was found at build time.",
               "rengine-bench"};
  std::string scenesText, csvPath = "build/bench/bench.csv", repeatsText = "5";
  bool quick = false, shortcuts = false;
  app.add_option("--scenes", scenesText, "Comma-separated scenes (default all): " + KnownScenes());
  app.add_option("--csv", csvPath, "CSV output, one row per run")->capture_default_str();
  app.add_option("--repeats", repeatsText, "Timed runs per grid point (median reported)")
      ->capture_default_str();
  app.add_flag("--quick", quick,
               "Smoke test: dt in {1/30, 1/120} (debris_cloud, asteroid_field: 1/30, 1 s), "
               "10 iterations, 1 timed run");
  app.add_flag("--shortcuts", shortcuts,
               "Instead of the grid: each shortcut's scene with and without it (time per step "
               "and error; CSV default build/bench/shortcuts.csv)");
  app.footer(kErrorHelp);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints the help or the error
    return code == 0 ? kExitOk : kExitBadInput;
  }

  if (shortcuts && app.count("--csv") == 0) csvPath = "build/bench/shortcuts.csv";
  std::vector<const Scene*> scenes;
  int repeats = 0;
  try {
    scenes = ParseScenes(scenesText);
    repeats = quick ? 1 : ParseRepeats(repeatsText);
    // Loaded before any run: a missing scene file is an input error, reported at once.
    for (const Scene* s : scenes) {
      if (s->world == StackWorld) StackScene();
      if (s->world == DebrisWorld) DebrisScene();
    }
  } catch (const UsageError& e) {
    std::fprintf(stderr, "error: %s\n", e.message.c_str());
    return kExitBadInput;
  } catch (const RSceneError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  // Created before the runs, so a bad path fails in a second rather than after minutes.
  const std::filesystem::path parent = std::filesystem::path(csvPath).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (std::FILE* probe = std::fopen(csvPath.c_str(), "ab")) {
    std::fclose(probe);
  } else {
    std::fprintf(stderr, "error: %s: cannot open for writing: %s\n", csvPath.c_str(),
                 std::strerror(errno));
    return kExitBadInput;
  }

  if (shortcuts) {
    std::vector<rbench::ShortcutRow> rows;
    try {
      rows = rbench::RunShortcuts(quick, repeats);
    } catch (const RSceneError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return kExitBadInput;
    }
    rbench::PrintShortcutTable(rows);
    if (!rbench::WriteShortcutCsv(csvPath, rows)) {
      std::fprintf(stderr, "error: %s: write failed: %s\n", csvPath.c_str(), std::strerror(errno));
      return kExitBadInput;
    }
    std::printf("wrote %s (%zu rows, %d timed run%s per point)\n", csvPath.c_str(), rows.size(),
                repeats, repeats == 1 ? "" : "s");
    return kExitOk;
  }

  std::vector<Method> methods{Method::kREngine};
#ifdef RENGINE_HAVE_BULLET
  methods.push_back(Method::kBullet);
  std::printf("methods: REngine (double), bullet: Bullet %d.%02d (%s precision), "
              "stepSimulation(dt, 0), sleeping off\n",
              btGetVersion() / 100, btGetVersion() % 100,
              sizeof(btScalar) == 8 ? "double" : "single");
#else
  std::printf("methods: REngine (built without Bullet: no bullet series)\n");
#endif

  const std::vector<int> rates = quick ? std::vector<int>{30, 120}
                                       : std::vector<int>{30, 60, 120, 240, 480};
  const std::vector<int> iterationGrid = quick ? std::vector<int>{10} : std::vector<int>{4, 10, 20};
  const int kDefaultIterations = RWorldSettings{}.solverIterations;

  PrintTableHeader();
  std::vector<Row> rows;
  for (const Scene* scene : scenes) {
    const std::vector<int> iterations =
        scene->contacts ? iterationGrid : std::vector<int>{kDefaultIterations};
    const std::vector<int> sceneRates =
        quick && scene->expensive ? std::vector<int>{rates.front()} : rates;
#ifdef RENGINE_HAVE_BULLET
    WarnCombineMismatch(*scene, {RScalar(1) / sceneRates.front(), iterations.front(), quick});
#endif
    for (int it : iterations) {
      for (int rate : sceneRates) {
        const GridPoint point{RScalar(1) / rate, it, quick};
        for (Method method : methods) {
          // The untimed observed run doubles as the warm-up (caches, page faults, clocks).
          const std::unique_ptr<Engine> observed = MakeEngine(method, scene->world(point));
          Row row{scene->name, method, point.dt, std::nullopt, 0, scene->errors(*observed)};
          if (scene->contacts) row.iterations = it;
          std::vector<double> times;
          for (int r = 0; r < repeats; ++r) times.push_back(TimeOneRun(*scene, method, point));
          row.msPerStep = Median(times);
          PrintRow(row);
          rows.push_back(row);
        }
      }
    }
  }

  if (!WriteCsv(csvPath, rows)) {
    std::fprintf(stderr, "error: %s: write failed: %s\n", csvPath.c_str(), std::strerror(errno));
    return kExitBadInput;
  }
  std::printf("wrote %s (%zu rows, %d timed run%s per point)\n", csvPath.c_str(), rows.size(),
              repeats, repeats == 1 ? "" : "s");
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) { return Run(argc, argv); }
