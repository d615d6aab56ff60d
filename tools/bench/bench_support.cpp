// Where hill climbing beats the plain loop for the support function: both over the same
// hulls (points on a sphere, so every point is a vertex) and the same random directions.
// "cold" climbs start at vertex 0; "warm" start at the previous answer, as GJK's next
// iteration does. Run: build/bin/bench_support
#include <REnginePhysics/RConvexPolyhedron.h>

#include <benchmark/benchmark.h>

#include <random>

using namespace REngine;

namespace {

struct Fixture {
  RConvexPolyhedron hull;
  std::vector<RVec3> dirs;
};

Fixture Make(int n) {
  std::mt19937_64 rng(3);
  std::normal_distribution<RScalar> g;
  std::vector<RVec3> pts;
  for (int i = 0; i < n; ++i) pts.push_back(RVec3(g(rng), g(rng), g(rng)).normalized());
  Fixture f{RConvexPolyhedron::Hull(pts), {}};
  // Directions that drift slowly, like GJK's search direction between iterations.
  RVec3 d(1, 0, 0);
  for (int i = 0; i < 1024; ++i) {
    d = (d + 0.3 * RVec3(g(rng), g(rng), g(rng))).normalized();
    f.dirs.push_back(d);
  }
  return f;
}

void BM_SupportLinear(benchmark::State& state) {
  const Fixture f = Make(static_cast<int>(state.range(0)));
  const auto& v = f.hull.Vertices();
  const auto n = static_cast<std::uint32_t>(v.size());
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(RConvexPolyhedron::SupportLinear(v.data(), n, f.dirs[k++ & 1023]));
  }
  state.counters["vertices"] = n;
}

void BM_SupportHillClimb(benchmark::State& state) {
  const Fixture f = Make(static_cast<int>(state.range(0)));
  const bool warm = state.range(1) != 0;
  const auto& v = f.hull.Vertices();
  std::uint32_t last = 0;
  std::size_t k = 0;
  for (auto _ : state) {
    last = f.hull.SupportHillClimb(v.data(), f.dirs[k++ & 1023], warm ? last : 0);
    benchmark::DoNotOptimize(last);
  }
  state.counters["vertices"] = static_cast<double>(v.size());
  state.SetLabel(warm ? "warm" : "cold");
}

}  // namespace

BENCHMARK(BM_SupportLinear)->Arg(8)->Arg(16)->Arg(32)->Arg(48)->Arg(64)->Arg(128)->Arg(256)->Arg(1024);
BENCHMARK(BM_SupportHillClimb)
    ->ArgsProduct({{8, 16, 32, 48, 64, 128, 256, 1024}, {0, 1}});

BENCHMARK_MAIN();
