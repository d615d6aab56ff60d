// Cost per body-step of UpdateObjects (timed alone, from the integrator's profile), by
// inertia symmetry and by whether the body's angular momentum changed this step (a kick
// forces the elliptic constants to be recomputed; a free body reuses them).
// Run: build/bin/bench_motion
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RIntegrator.h>

#include <benchmark/benchmark.h>

#include <random>

using namespace REngine;

namespace {

// kind: 0 sphere, 1 symmetric box, 2 general box.
std::vector<RRigidBody> MakeBodies(int kind, int n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<RScalar> u(-3, 3);
  std::vector<RRigidBody> bodies;
  bodies.reserve(n);
  for (int i = 0; i < n; ++i) {
    RBodyDef def;
    def.restitution = 0.5;
    def.name = "b" + std::to_string(i);
    if (kind == 0) {
      def.shape = RShape::Sphere(0.5);
    } else {
      def.shape = RShape::Box(kind == 1 ? RVec3(0.5, 0.5, 1.5) : RVec3(0.5, 1.0, 1.5));
    }
    def.position_W = RVec3(u(rng), u(rng), u(rng)) * 100;
    def.velocity_W = RVec3(u(rng), u(rng), u(rng));
    def.angularVelocity_W = RVec3(u(rng), u(rng), u(rng));
    def.q_WS = QuatExp(RVec3(u(rng), u(rng), u(rng)));
    bodies.emplace_back(def);
  }
  return bodies;
}

void BM_UpdateObjects(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const bool kicked = state.range(1) != 0;
  const int n = 1000;
  std::vector<RRigidBody> bodies = MakeBodies(kind, n);
  RWorldSettings settings;
  settings.gravity_W = RVec3(0, -9.81, 0);
  RIntegrator integrator(settings);
  const RVec3 tinyImpulse(0, 1e-9, 0);
  for (auto _ : state) {
    if (kicked) {
      for (RRigidBody& b : bodies) b.AddAngularImpulse_W(tinyImpulse);
    }
    integrator.Update(bodies, 1.0 / 60);
    benchmark::DoNotOptimize(bodies.data());
    // Only the motion stage: Update also sweeps all pairs for collisions (measured by
    // bench_collision and the scene benchmarks), which these far-apart bodies never have.
    state.SetIterationTime(integrator.Profile().updateObjects * 1e-3);
  }
  state.SetItemsProcessed(state.iterations() * n);
  static const char* kKinds[] = {"sphere", "symmetric", "general"};
  state.SetLabel(std::string(kKinds[kind]) + (kicked ? ", kicked every step" : ", free"));
}

}  // namespace

// items_per_second is body-steps per second; its inverse is the cost per body-step.
BENCHMARK(BM_UpdateObjects)
    ->ArgsProduct({{0, 1, 2}, {0, 1}})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
