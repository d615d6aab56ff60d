// Triangle meshes: what a 100k-triangle mesh costs to build and to hold, and what
// its contacts cost in a step against the same scene on one flat box.
//
// The mesh: a flat square floor of 224 x 224 quads of 0.5 m, two triangles a quad (100 352
// triangles, 112 m across). BM_MeshBuild builds RTriangleMesh from its vertices and triangles
// (checks, the tree, active edges); counters: the bytes it holds, per triangle.
// BM_StepOnFloor: 1024 boxes (half extents 0.4, 0.25, 0.3, each turned about y) resting on the
// floor in a 32 x 32 grid, sleeping off, one step per iteration; Arg 0 is the mesh floor, 1
// one static box. The boxes settle for 60 steps before timing. Counters: contacts and contact
// points per step, and the step's cost per body.
//
// Run (medians of interleaved repetitions):
//   build/bin/bench_mesh --benchmark_repetitions=5
//       --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RTriangleMesh.h>

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

using namespace REngine;

namespace {

constexpr int kQuads = 224;
constexpr RScalar kQuad = 0.5;  // m

RShape Floor() {
  RShape s;
  s.type = RShapeType::kMesh;
  const RScalar x0 = -kQuads * kQuad / 2;
  for (int j = 0; j <= kQuads; ++j) {
    for (int i = 0; i <= kQuads; ++i) s.points.emplace_back(x0 + i * kQuad, 0, x0 + j * kQuad);
  }
  const auto at = [](int i, int j) { return static_cast<std::uint32_t>(j * (kQuads + 1) + i); };
  for (int j = 0; j < kQuads; ++j) {
    for (int i = 0; i < kQuads; ++i) {
      s.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      s.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  return s;
}

void BM_MeshBuild(benchmark::State& state) {
  const RShape s = Floor();
  std::size_t bytes = 0;
  for (auto _ : state) {
    const RTriangleMesh mesh(s.points, s.triangles);
    bytes = mesh.MemoryBytes();
    benchmark::DoNotOptimize(bytes);
  }
  state.counters["triangles"] = static_cast<double>(s.triangles.size());
  state.counters["MB"] = static_cast<double>(bytes) / (1 << 20);
  state.counters["bytes_per_triangle"] = static_cast<double>(bytes) / static_cast<double>(s.triangles.size());
}
BENCHMARK(BM_MeshBuild)->Unit(benchmark::kMillisecond);

struct World {
  std::vector<RRigidBody> bodies;
  RIntegrator integrator;
};

World& WorldOf(int boxFloor) {
  static std::map<int, std::unique_ptr<World>> worlds;
  std::unique_ptr<World>& w = worlds[boxFloor];
  if (w) return *w;
  w = std::make_unique<World>();
  RBodyDef floor;
  floor.restitution = 0.5;
  floor.name = "floor";
  floor.kind = RBodyKind::kStatic;
  if (boxFloor) {
    floor.shape = RShape::Box(RVec3(kQuads * kQuad / 2, 0.5, kQuads * kQuad / 2));
    floor.position_W = RVec3(0, -0.5, 0);
  } else {
    floor.shape = Floor();
  }
  w->bodies.emplace_back(floor);
  for (int k = 0; k < 1024; ++k) {
    RBodyDef box;
    box.restitution = 0.5;
    box.shape = RShape::Box(RVec3(0.4, 0.25, 0.3));
    box.position_W = RVec3(-24.3 + 1.6 * (k % 32), 0.25, -24.7 + 1.6 * (k / 32));
    box.q_WS = RQuat(Eigen::AngleAxisd(0.1 * (k % 7), RVec3::UnitY()));
    box.friction = 0.5;
    w->bodies.emplace_back(box);
  }
  w->integrator.Settings().gravity_W = RVec3(0, -9.81, 0);
  w->integrator.Settings().shortcuts.sleeping = false;
  for (int k = 0; k < 60; ++k) w->integrator.Update(w->bodies, 1.0 / 60);
  return *w;
}

void BM_StepOnFloor(benchmark::State& state) {
  World& w = WorldOf(static_cast<int>(state.range(0)));
  std::size_t contacts = 0, points = 0;
  for (auto _ : state) {
    w.integrator.Update(w.bodies, 1.0 / 60);
    contacts = w.integrator.Contacts().size();
  }
  for (const RContact& c : w.integrator.Contacts()) points += static_cast<std::size_t>(c.manifold.pointCount);
  state.counters["contacts"] = static_cast<double>(contacts);
  state.counters["points"] = static_cast<double>(points);
  state.counters["us_per_body"] = benchmark::Counter(1e-6 * 1024, benchmark::Counter::kIsIterationInvariantRate |
                                                                      benchmark::Counter::kInvert);
}
BENCHMARK(BM_StepOnFloor)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
