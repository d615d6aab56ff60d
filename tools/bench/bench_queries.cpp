// Ray casts per second against asteroid fields of 1000 and 10000 hulls: REngine's
// RQueries::CastRay beside Bullet's btCollisionWorld::rayTest (ClosestRayResultCallback) on
// the same world, in the same run (the target: at least 2x Bullet's rays per second).
//
// The field: n rocks (24 random points on a rough sphere, as tools/make_scaling_scenes.py's sparse
// field, radius 1 to 5 m), uniform in a cube of side 25 n^(1/3) m (one rock per 15600 m^3
// at every n), at rest. The rays: 4096 from uniform points of the cube in uniform
// directions, 100 m long (a laser's range), fixed seed; one benchmark iteration casts all
// of them, nearest hit only. Counters: hit fraction, and, against Bullet (where found), the
// fraction of rays on which the two engines agree (the same body, or both missing), of rays
// that start inside a rock (REngine: a hit at 0; Bullet's rayTest ignores a convex shape the
// ray starts in), and the largest distance difference where they agree (with the fraction of
// rays on which it exceeds 1 um: Bullet's convex cast stops at a tolerance).
//
// Bullet's world is bench/BulletWorld.h's (what rengine-bench and bench_bullet step: the
// bodies' REngine mass properties and body frames, btDbvtBroadphase), its hull margins set
// to 0 so both engines answer for the same solid; stepped by nothing, its AABBs updated once.
// REngine's RQueries builds its tree at the first query, before timing.
//
// Run (medians of interleaved repetitions):
//   build/bin/bench_queries --benchmark_repetitions=10
//       --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RQueries.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <vector>

#ifdef RENGINE_HAVE_BULLET
#include "BulletWorld.h"
#endif

using namespace REngine;

namespace {

constexpr int kRays = 4096;
constexpr RScalar kRange = 100;  // m

std::vector<RVec3> RockPoints(std::mt19937_64& rng, RScalar radius) {
  std::normal_distribution<RScalar> g(0, 1);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  std::vector<RVec3> points;
  for (int k = 0; k < 24; ++k) {
    const RScalar z = g(rng), y = g(rng), x = g(rng);
    const RVec3 v(x, y, z);
    points.push_back(v * (radius * (1 + 0.3 * u(rng)) / v.norm()));
  }
  return points;
}

struct Field {
  RScalar side = 0;
  std::vector<RRigidBody> bodies;  // for Bullet's builder
  RBodies world;
  std::vector<RRay> rays;
  RQueries queries;
#ifdef RENGINE_HAVE_BULLET
  std::unique_ptr<bench::BulletWorld> bullet;
#endif
};

Field& FieldOf(int n) {
  static std::map<int, std::unique_ptr<Field>> fields;
  std::unique_ptr<Field>& f = fields[n];
  if (f) return *f;
  f = std::make_unique<Field>();
  std::mt19937_64 rng(20261114u + static_cast<unsigned>(n));
  std::uniform_real_distribution<RScalar> u(0, 1);
  f->side = 25 * std::cbrt(static_cast<RScalar>(n));
  for (int i = 0; i < n; ++i) {
    RBodyDef d;
    d.restitution = 0.5;
    d.shape = RShape::Hull(RockPoints(rng, 1 + 4 * u(rng)));
    const RScalar z = u(rng), y = u(rng), x = u(rng);
    d.position_W = f->side * (RVec3(x, y, z) - RVec3::Constant(0.5));
    std::normal_distribution<RScalar> g(0, 1);
    const RScalar qz = g(rng), qy = g(rng), qx = g(rng), qw = g(rng);
    d.q_WS = RQuat(qw, qx, qy, qz).normalized();
    d.density = 2000;
    f->bodies.emplace_back(d);
    f->world.Add(f->bodies.back());
  }
  std::normal_distribution<RScalar> g(0, 1);
  for (int k = 0; k < kRays; ++k) {
    const RScalar z = u(rng), y = u(rng), x = u(rng);
    const RScalar dz = g(rng), dy = g(rng), dx = g(rng);
    f->rays.push_back({f->side * (RVec3(x, y, z) - RVec3::Constant(0.5)),
                       RVec3(dx, dy, dz).normalized(), kRange});
  }
  f->queries.CastRay(f->world, f->rays[0]);  // builds the tree
#ifdef RENGINE_HAVE_BULLET
  RWorldSettings settings;
  f->bullet = bench::BuildBullet(settings, f->bodies,
                                 bench::ChooseCoefficients(settings, f->bodies, false), false);
  for (auto& shape : f->bullet->shapes) shape->setMargin(0);
  f->bullet->world.updateAabbs();
#endif
  return *f;
}

void BM_REngineRays(benchmark::State& state) {
  Field& f = FieldOf(static_cast<int>(state.range(0)));
  std::size_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (const RRay& ray : f.rays) {
      const std::optional<RRayHit> hit = f.queries.CastRay(f.world, ray);
      hits += hit.has_value();
      benchmark::DoNotOptimize(hit);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kRays);
  state.counters["hit_fraction"] = static_cast<double>(hits) / kRays;
}
BENCHMARK(BM_REngineRays)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);

#ifdef RENGINE_HAVE_BULLET
void BM_BulletRays(benchmark::State& state) {
  Field& f = FieldOf(static_cast<int>(state.range(0)));
  std::size_t hits = 0;
  for (auto _ : state) {
    hits = 0;
    for (const RRay& ray : f.rays) {
      const btVector3 from = bench::Bt(ray.origin_W);
      const btVector3 to = bench::Bt(ray.origin_W + ray.maxDistance * ray.direction_W);
      btCollisionWorld::ClosestRayResultCallback cb(from, to);
      f.bullet->world.rayTest(from, to, cb);
      hits += cb.hasHit();
      benchmark::DoNotOptimize(cb.m_closestHitFraction);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kRays);
  state.counters["hit_fraction"] = static_cast<double>(hits) / kRays;
  // Agreement with REngine on the same rays (outside the timing).
  std::size_t agree = 0, startInside = 0, beyondMicron = 0;
  double worst = 0;
  for (const RRay& ray : f.rays) {
    const btVector3 from = bench::Bt(ray.origin_W);
    const btVector3 to = bench::Bt(ray.origin_W + ray.maxDistance * ray.direction_W);
    btCollisionWorld::ClosestRayResultCallback cb(from, to);
    f.bullet->world.rayTest(from, to, cb);
    const std::optional<RRayHit> hit = f.queries.CastRay(f.world, ray);
    if (!hit && !cb.hasHit()) {
      ++agree;
    } else if (hit && hit->distance == 0) {
      ++startInside;  // REngine: a hit at 0; Bullet ignores a convex the ray starts inside
    } else if (hit && cb.hasHit() &&
               // Bodies were added in order and never removed: slot i is Bullet's body i.
               cb.m_collisionObject == f.bullet->bodies[hit->body.index].get()) {
      ++agree;
      const double diff =
          std::abs(static_cast<double>(cb.m_closestHitFraction) * kRange - hit->distance);
      worst = std::max(worst, diff);
      beyondMicron += diff > 1e-6;
    }
  }
  state.counters["agree_fraction"] = static_cast<double>(agree) / kRays;
  state.counters["max_distance_diff_m"] = worst;
  state.counters["start_inside_fraction"] = static_cast<double>(startInside) / kRays;
  state.counters["diff_beyond_1um_fraction"] = static_cast<double>(beyondMicron) / kRays;
}
BENCHMARK(BM_BulletRays)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
#endif

}  // namespace

BENCHMARK_MAIN();
