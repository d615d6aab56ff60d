// Rollback netcode's costs beside Jolt Physics, in one run: a field of n rocks saved every
// frame, restored, and an 8-frame rollback (restore + 8 x (step + save)) as a fraction of a
// 16.7 ms frame. One thread in both engines.
//
// The field: n rocks (24 random points on a rough sphere, radius 1 to 5 m, density
// 2000 kg/m^3, restitution 0.5) uniform in a cube of side 25 n^(1/3) m (bench_queries'
// field), each moving (normal velocity, 1 m/s a component) and tumbling (0.5 rad/s a
// component) in zero gravity, so that no rock sleeps and some collide. dt = 1/60 s.
//
// REngine: SaveSnapshot / RestoreSnapshot (RSnapshot.h) into a ring of 9 snapshots, each
// sharing with the last; and, for reference, SaveState (RWorldState.h, the file format).
// Jolt (when built with -DREngine_JOLT_DIR): PhysicsSystem::SaveState / RestoreState
// (EStateRecorderState::All) into a ring of 9 StateRecorderImpl. Bytes/body: what one frame
// holds of its own (REngine: RSnapshot::FrameBytes; its shared layout is printed apart).
//
// Timings are medians over `--repeats` (default 41) repetitions, the engines interleaved
// (which goes first alternates). Each repetition: one frame stepped and saved (save timed),
// then a rollback to 8 frames back (restore timed alone, then the whole rollback).
//
//   build/bin/bench_rollback [--bodies 100,1000,5000] [--repeats 41]
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RSnapshot.h>
#include <REnginePhysics/RWorldState.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#ifdef RENGINE_HAVE_JOLT
#include "JoltRollback.h"
#endif

using namespace REngine;

namespace {

constexpr double kDt = 1.0 / 60;
constexpr double kFrameUs = 1e6 / 60;
constexpr int kDepth = 8;         // frames rolled back
constexpr int kRing = kDepth + 1;  // frames kept

struct Rock {
  std::vector<RVec3> points;
  RVec3 position, velocity, spin;
  RQuat rotation;
};

std::vector<Rock> Field(int n) {
  std::mt19937_64 rng(20261114u + static_cast<unsigned>(n));
  std::uniform_real_distribution<RScalar> u(0, 1);
  std::normal_distribution<RScalar> g(0, 1);
  const RScalar side = 25 * std::cbrt(static_cast<RScalar>(n));
  std::vector<Rock> rocks(n);
  for (Rock& r : rocks) {
    const RScalar radius = 1 + 4 * u(rng);
    for (int k = 0; k < 24; ++k) {
      const RScalar z = g(rng), y = g(rng), x = g(rng);
      const RVec3 v(x, y, z);
      r.points.push_back(v * (radius * (1 + 0.3 * (2 * u(rng) - 1)) / v.norm()));
    }
    const RScalar z = u(rng), y = u(rng), x = u(rng);
    r.position = side * (RVec3(x, y, z) - RVec3::Constant(0.5));
    const RScalar qz = g(rng), qy = g(rng), qx = g(rng), qw = g(rng);
    r.rotation = RQuat(qw, qx, qy, qz).normalized();
    const RScalar vz = g(rng), vy = g(rng), vx = g(rng);
    r.velocity = RVec3(vx, vy, vz);
    const RScalar wz = g(rng), wy = g(rng), wx = g(rng);
    r.spin = 0.5 * RVec3(wx, wy, wz);
  }
  return rocks;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

template <class F>
double TimeUs(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  const auto t1 = std::chrono::steady_clock::now();
  return std::chrono::duration<double, std::micro>(t1 - t0).count();
}

// One engine's world behind the bench's four operations.
struct Engine {
  const char* name;
  std::function<void()> step;
  std::function<void(int)> save;     // into ring slot k
  std::function<void(int)> restore;  // from ring slot k
  std::function<double()> bytesPerBody;
  std::vector<double> saveUs, restoreUs, rollbackUs;
};

struct REngineWorld {
  RBodies bodies;
  RIntegrator integrator;
  std::vector<RSnapshot> ring = std::vector<RSnapshot>(kRing);
  int last = -1;
  explicit REngineWorld(const std::vector<Rock>& rocks) : integrator(Settings()) {
    for (const Rock& r : rocks) {
      RBodyDef d;
      d.shape = RShape::Hull(r.points);
      d.position_W = r.position, d.q_WS = r.rotation;
      d.velocity_W = r.velocity, d.angularVelocity_W = r.spin;
      d.density = 2000, d.restitution = 0.5;
      bodies.Add(d);
    }
  }
  static RWorldSettings Settings() {
    RWorldSettings s;  // zero gravity
    s.threads = 1;
    return s;
  }
  void Save(int k) {
    RSnapshotOptions o;
    o.shareWith = last >= 0 && last != k ? &ring[last] : nullptr;
    SaveSnapshot(integrator, bodies, ring[k], o);
    last = k;
  }
  void Restore(int k) {
    RestoreSnapshot(integrator, bodies, ring[k]);
    last = k;
  }
};

void Run(int n, int repeats) {
  const std::vector<Rock> rocks = Field(n);
  std::vector<Engine> engines;

  REngineWorld rengine(rocks);
  engines.push_back({"REngine", [&] { rengine.integrator.Update(rengine.bodies, kDt); },
                     [&](int k) { rengine.Save(k); }, [&](int k) { rengine.Restore(k); },
                     [&] { return double(rengine.ring[rengine.last].FrameBytes()) / n; }, {}, {}, {}});
#ifdef RENGINE_HAVE_JOLT
  std::vector<bench::JoltRock> jrocks;
  for (const Rock& r : rocks) {
    bench::JoltRock j;
    for (const RVec3& p : r.points) j.points.emplace_back(float(p.x()), float(p.y()), float(p.z()));
    j.position = JPH::RVec3(r.position.x(), r.position.y(), r.position.z());
    j.rotation = JPH::Quat(float(r.rotation.x()), float(r.rotation.y()), float(r.rotation.z()), float(r.rotation.w()));
    j.velocity = JPH::Vec3(float(r.velocity.x()), float(r.velocity.y()), float(r.velocity.z()));
    j.spin = JPH::Vec3(float(r.spin.x()), float(r.spin.y()), float(r.spin.z()));
    j.density = 2000, j.restitution = 0.5f;
    jrocks.push_back(std::move(j));
  }
  bench::JoltWorld jolt(jrocks);
  std::vector<JPH::StateRecorderImpl> jring(kRing);
  int jlast = 0;
  engines.push_back({"Jolt", [&] { jolt.Step(float(kDt)); },
                     [&](int k) { jolt.Save(jring[k]), jlast = k; },
                     [&](int k) {
                       if (!jolt.Restore(jring[k])) std::fprintf(stderr, "Jolt: RestoreState failed\n"), std::exit(1);
                     },
                     [&] { return double(jring[jlast].GetData().size()) / n; }, {}, {}, {}});
#endif

  // Fill the rings: frames 0 .. kDepth.
  int frame = 0;
  for (Engine& e : engines) e.save(frame % kRing);
  for (; frame < kDepth;) {
    ++frame;
    for (Engine& e : engines) e.step(), e.save(frame % kRing);
  }
  for (int rep = 0; rep < repeats; ++rep) {
    ++frame;
    for (std::size_t o = 0; o < engines.size(); ++o) {
      Engine& e = engines[(o + rep) % engines.size()];
      e.step();
      e.saveUs.push_back(TimeUs([&] { e.save(frame % kRing); }));
    }
    for (std::size_t o = 0; o < engines.size(); ++o) {
      Engine& e = engines[(o + rep) % engines.size()];
      // The rollback: back to frame - 8, the 8 frames simulated and saved again.
      double restoreUs = 0;
      const double total = TimeUs([&] {
        restoreUs = TimeUs([&] { e.restore((frame - kDepth) % kRing); });
        for (int f = frame - kDepth + 1; f <= frame; ++f) e.step(), e.save(f % kRing);
      });
      e.restoreUs.push_back(restoreUs);
      e.rollbackUs.push_back(total);
    }
  }

  // SaveState, the file format, for reference.
  std::vector<double> fileUs;
  std::vector<std::uint8_t> file;
  for (int rep = 0; rep < std::min(repeats, 15); ++rep) {
    fileUs.push_back(TimeUs([&] { SaveState(rengine.integrator, rengine.bodies, file); }));
  }

  std::printf("\n%d rocks, %d repeats, medians (1 thread)\n", n, repeats);
  std::printf("%-8s %12s %10s %12s %14s\n", "engine", "bytes/body", "save us", "restore us", "8-frame rollback");
  for (Engine& e : engines) {
    const double rollback = Median(e.rollbackUs);
    std::printf("%-8s %12.1f %10.1f %12.1f %9.0f us = %.3f of a frame\n", e.name, e.bytesPerBody(), Median(e.saveUs),
                Median(e.restoreUs), rollback, rollback / kFrameUs);
  }
  std::printf("REngine snapshot's shared layout and rotation constants: %.0f bytes/body (once per layout)\n",
              double(rengine.ring[rengine.last].SharedBytes()) / n);
  std::printf("REngine SaveState (file format): %.1f bytes/body, save %.1f us\n", double(file.size()) / n,
              Median(fileUs));
#ifndef RENGINE_HAVE_JOLT
  std::printf("Jolt not available (configure with -DREngine_JOLT_DIR=<Jolt install prefix>)\n");
#endif
}

std::vector<int> ParseList(const char* text) {
  std::vector<int> out;
  for (const char* p = text; *p;) {
    char* end = nullptr;
    const long v = std::strtol(p, &end, 10);
    if (end == p || v <= 0) {
      std::fprintf(stderr, "bench_rollback: --bodies takes positive integers separated by commas (got \"%s\")\n", text);
      std::exit(2);
    }
    out.push_back(static_cast<int>(v));
    p = *end == ',' ? end + 1 : end;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> counts = {100, 1000, 5000};
  int repeats = 41;
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--bodies") == 0 && k + 1 < argc) {
      counts = ParseList(argv[++k]);
    } else if (std::strcmp(argv[k], "--repeats") == 0 && k + 1 < argc) {
      repeats = std::atoi(argv[++k]);
      if (repeats < 1) std::fprintf(stderr, "bench_rollback: --repeats must be >= 1\n"), std::exit(2);
    } else {
      std::fprintf(stderr, "usage: bench_rollback [--bodies 100,1000,5000] [--repeats 41]\n");
      return 2;
    }
  }
  for (int n : counts) Run(n, repeats);
  return 0;
}
