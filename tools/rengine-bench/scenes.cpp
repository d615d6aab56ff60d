// rengine-bench's scenes (scenes.h): the closed forms and conserved quantities each run is
// measured against.
#include "scenes.h"

#include <REnginePhysics/RScene.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "support/ReferenceScenes.h"
#include "support/TestBodies.h"

using namespace REngine;
using test::BoxDef;
using test::GroundDef;
using test::HeadOnSpheres;
using test::LoadReferenceScene;
using test::SphereDef;
using test::UniformIn;
using test::UnitBoxDef;

namespace rbench {

namespace {

constexpr RScalar kG = RScalar(9.81);  // m/s^2

// ---- tumbling ---------------------------------------------------------------------------
// Torque-free, so energy and world angular momentum are conserved exactly; near the
// intermediate axis the motion is unstable (Dzhanibekov flips), which is what makes a
// stepper that approximates the rotation drift.

World TumblingWorld(const GridPoint& p) {
  World w;
  w.bodies.emplace_back(
      BoxDef(RVec3(0.5, 0.3, 0.1)).Mass(1).Named("box").Spinning(RVec3(0.01, 5.0, 0.01)));
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
  w.bodies.emplace_back(SphereDef(0.1).Mass(1).Named("ball").Moving(LaunchVelocity_W()));
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
  // The same restitution on both: min combine = the value.
  for (const RBodyDef& def : HeadOnSpheres(kPairM1, kPairV1, kPairM2, kPairV2, restitution)) {
    w.bodies.emplace_back(def);
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
  RBodyDef floor = GroundDef().Named("floor");
  RBodyDef box = UnitBoxDef(RVec3(0, 0.5, 0)).Moving(RVec3(kSlideV0, 0, 0));
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
  RBodyDef incline = BoxDef(RVec3(10, 0.5, 3)).Static().Oriented(q).Named("incline");
  // Face on face: the incline's top is at local y 0.5.
  RBodyDef box = UnitBoxDef(q * RVec3(7, 1, 0)).Oriented(q);
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
  static const RScene scene = LoadReferenceScene("box_stack_10");
  return scene;
}

// A reference scene (scenes/) at the grid point's dt and iterations, for `duration` seconds.
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
  static const RScene scene = LoadReferenceScene("debris_cloud_1000");
  return scene;
}

World DebrisWorld(const GridPoint& p) { return SceneWorld(DebrisScene(), p, p.quick ? 1 : 2); }

Errors DebrisErrors(Engine& engine) {
  const Conservation c = MeasureConservation(engine);
  return {c.finalEnergyChange, c.maxEnergyGain, c.momentumDrift};
}

// Components drawn in x, y, z order (a constructor's arguments have no evaluation order),
// each by UniformIn: the same field on every platform.
RVec3 UniformVec(std::mt19937_64& rng, RScalar lo, RScalar hi) {
  const RScalar x = UniformIn(rng, lo, hi);
  const RScalar y = UniformIn(rng, lo, hi);
  const RScalar z = UniformIn(rng, lo, hi);
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
    const RScalar r = UniformIn(rng, 0.8, 1.0);
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
    w = UniformIn(rng, -1, 1);
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
        rock.shape = RShape::Hull(RockPoints(rng));
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

}  // namespace

const std::vector<Scene>& AllScenes() {
  static const std::vector<Scene> scenes = {
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
  return scenes;
}

void LoadSceneFiles(const Scene& scene) {
  if (scene.world == StackWorld) StackScene();
  if (scene.world == DebrisWorld) DebrisScene();
}

}  // namespace rbench
