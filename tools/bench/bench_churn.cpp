// Churn: what adding, removing, disabling and spawning bodies cost a world at rest.
//
// A pile of 500 boxes (100 columns of 5, resting exactly, asleep) under gravity, stepped in
// periods of 10 steps (one benchmark iteration = one period = 10 steps):
//   Constant       a small body far away falls and is put back once a period: the
//                  constant-count step.
//   Churn          a small body is added far away and the previous one removed once a period
//                  (RBodies): the pile must stay asleep, and the step cost at most 1.5x
//                  the constant one.
//   ChurnVector    the same through a plain std::vector (identity by index): every removal
//                  wakes the world.
//   Pooled         Constant plus 500 parked (disabled) bodies: parking costs nothing.
// Spawning one hull body: from its RShape (Qhull runs) or from a prepared shape (shared).
//
// Run: build/bin/bench_churn, or tools/bench/churn_ratio.py for the medians of interleaved
// repetitions and their ratios.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <benchmark/benchmark.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

using namespace REngine;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr int kPeriod = 10;

RBodyDef BoxDef(const RVec3& x) {
  RBodyDef d;
  d.restitution = 0.5;
  d.shape = RShape::Box(RVec3::Constant(0.5));
  d.position_W = x;
  d.mass = 1;
  return d;
}

std::vector<RBodyDef> PileDefs() {
  std::vector<RBodyDef> defs;
  RBodyDef ground = BoxDef(RVec3(0, -0.5, 0));
  ground.name = "ground";
  ground.shape.halfExtents = RVec3(100, 0.5, 100);
  ground.kind = RBodyKind::kStatic;
  ground.mass.reset();
  defs.push_back(ground);
  for (int c = 0; c < 100; ++c) {
    for (int k = 0; k < 5; ++k) {
      RBodyDef d = BoxDef(RVec3(1.5 * (c % 10), 0.5 + k, 1.5 * (c / 10)));
      d.name = "box" + std::to_string(5 * c + k);
      defs.push_back(d);
    }
  }
  return defs;
}

RBodyDef Debris(int i) {
  RBodyDef d;
  d.restitution = 0.5;
  d.name = "debris";
  d.shape = RShape::Sphere(0.1);
  d.position_W = RVec3(80, 5 + 0.01 * (i % 7), 80);
  d.mass = 0.1;
  return d;
}

RWorldSettings Gravity() {
  RWorldSettings s;
  s.gravity_W = RVec3(0, -9.81, 0);
  return s;
}

// Steps until the pile sleeps (it rests exactly: the sleep time and a little).
template <class Bodies>
void Settle(RIntegrator& integrator, Bodies& bodies) {
  for (int i = 0; i < 60; ++i) integrator.Update(bodies, kDt);
  if (integrator.PairStats().sleepingBodies != 500) throw std::logic_error("the pile did not sleep");
}

// Items are steps; "asleep" is the pile's sleeping bodies at the end.
void Report(benchmark::State& state, const RIntegrator& integrator) {
  state.SetItemsProcessed(state.iterations() * kPeriod);
  state.counters["asleep"] = static_cast<double>(integrator.PairStats().sleepingBodies);
}

void ResetDebris(RBodies& bodies, RBodyHandle debris, int i) {
  bodies[debris].SetShapePose(Debris(i).position_W, RQuat::Identity());
  bodies[debris].SetVelocity_W(RVec3::Zero());
}

// The same falling debris, put back at its start once a period instead of replaced: one
// awake body, as in the churn, at a constant count.
void BM_Pile_Constant(benchmark::State& state) {
  RBodies bodies;
  for (const RBodyDef& d : PileDefs()) bodies.Add(d);
  const RBodyHandle debris = bodies.Add(Debris(0));
  RIntegrator integrator(Gravity());
  Settle(integrator, bodies);
  int spawned = 0;
  for (auto _ : state) {
    ResetDebris(bodies, debris, ++spawned);
    for (int k = 0; k < kPeriod; ++k) integrator.Update(bodies, kDt);
  }
  Report(state, integrator);
}

void BM_Pile_Churn(benchmark::State& state) {
  RBodies bodies;
  for (const RBodyDef& d : PileDefs()) bodies.Add(d);
  RBodyHandle debris = bodies.Add(Debris(0));
  RIntegrator integrator(Gravity());
  Settle(integrator, bodies);
  int spawned = 0;
  for (auto _ : state) {
    bodies.Remove(debris);
    debris = bodies.Add(Debris(++spawned));
    for (int k = 0; k < kPeriod; ++k) integrator.Update(bodies, kDt);
  }
  Report(state, integrator);
}

void BM_Pile_ChurnVector(benchmark::State& state) {
  std::vector<RRigidBody> bodies;
  for (const RBodyDef& d : PileDefs()) bodies.emplace_back(d);
  bodies.emplace_back(Debris(0));
  RIntegrator integrator(Gravity());
  Settle(integrator, bodies);
  int spawned = 0;
  for (auto _ : state) {
    bodies.pop_back();
    bodies.emplace_back(Debris(++spawned));
    for (int k = 0; k < kPeriod; ++k) integrator.Update(bodies, kDt);
  }
  Report(state, integrator);
}

// Constant, with 500 more bodies parked (disabled) in the container.
void BM_Pile_Pooled(benchmark::State& state) {
  RBodies bodies;
  for (const RBodyDef& d : PileDefs()) bodies.Add(d);
  const RBodyHandle debris = bodies.Add(Debris(0));
  for (int i = 0; i < 500; ++i) {
    RBodyDef d = Debris(i);
    d.position_W = RVec3(-50, 1, 0.5 * i);
    bodies.Disable(bodies.Add(d));
  }
  RIntegrator integrator(Gravity());
  Settle(integrator, bodies);
  int spawned = 0;
  for (auto _ : state) {
    ResetDebris(bodies, debris, ++spawned);
    for (int k = 0; k < kPeriod; ++k) integrator.Update(bodies, kDt);
  }
  Report(state, integrator);
}

// A fragment: a hull of 40 points on an ellipsoid.
RShape FragmentShape() {
  RShape s;
  s.type = RShapeType::kHull;
  for (int i = 0; i < 40; ++i) {
    const RScalar z = 1 - (2 * i + 1) / 40.0, r = std::sqrt(1 - z * z), phi = 2.39996323 * i;
    s.points.push_back(RVec3(0.6 * r * std::cos(phi), 0.4 * r * std::sin(phi), 0.3 * z));
  }
  return s;
}

void BM_Spawn_FromShape(benchmark::State& state) {
  RBodies bodies;
  RBodyDef def;
  def.restitution = 0.5;
  def.name = "fragment";
  def.shape = FragmentShape();
  for (auto _ : state) bodies.Remove(bodies.Add(def));
  state.SetItemsProcessed(state.iterations());
}

void BM_Spawn_FromPreparedShape(benchmark::State& state) {
  RBodies bodies;
  RBodyDef def;
  def.restitution = 0.5;
  def.name = "fragment";
  def.prepared = PrepareShape(FragmentShape());
  for (auto _ : state) bodies.Remove(bodies.Add(def));
  state.SetItemsProcessed(state.iterations());
}

}  // namespace

BENCHMARK(BM_Pile_Constant)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Pile_Churn)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Pile_ChurnVector)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Pile_Pooled)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Spawn_FromShape)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Spawn_FromPreparedShape)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
