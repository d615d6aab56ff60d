// rengine-bench --scaling: see scaling.h.
//
// Each scene file is read once (LoadScene, not timed). Then, --repeats times in turn, REngine
// runs the scene from its start and Bullet does (REngine, Bullet, REngine, Bullet, ...: a
// drift of the shared machine falls on both alike), each in a world built afresh and timed
// around its step loop alone (std::chrono::steady_clock; building the world is not timed).
// The medians are reported. With --broadphase both, REngine's two settings both run before
// each Bullet run, in turn first and second.
//
//  * REngine: the scene's world as rengine-sim steps it (RSceneWorld, RIntegrator with the
//    scene's settings: solver.sleeping as the scene says, solver.broadphase on unless
//    --broadphase says otherwise). The final state's hash is rengine-sim's (FNV-1a over each
//    body's shape pose and velocities), so `rengine-sim SCENE --steps N` prints the same one;
//    every repeat must give the same hash.
//  * Bullet (where it was found at build time): the same bodies through
//    tools/bench/BulletWorld.h as bench_bullet builds them (restitution and friction mapped so
//    that Bullet's products equal REngine's combined values), deactivation on when the scene's
//    solver.sleeping is (Bullet's defaults) and off otherwise, stepSimulation(dt, 0).
//  * Jolt: not in Debian. The reference table (ScalingScenes, scaling_scenes.cpp) gives Jolt
//    5.5 and Bullet 3.24 measured together on one thread in another run;
//    jolt_estimate = this run's Bullet ms/step x (Jolt / Bullet) of the scene's row, and
//    vs_jolt = REngine / jolt_estimate (<= 1: at or under Jolt).
//
// CSV, one row per scene and REngine setting (broad phase, threads):
//   scene,series,bodies,steps,sleeping,broadphase,threads,repeats,rengine_ms_per_step,
//   bullet_ms_per_step,jolt_estimate_ms_per_step,vs_jolt,rengine_table_ms_per_step,
//   bullet_table_ms_per_step,jolt_table_ms_per_step,rengine_hash
// bodies counts the dynamic bodies (a pile also has its static ground); the *_table columns
// are the reference table's figures (empty where it has no row; so are the estimate and
// vs_jolt, and the Bullet columns without Bullet).
#include "scaling.h"

#include "report.h"
#include "scaling_scenes.h"

#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#ifdef RENGINE_HAVE_BULLET
#include "BulletWorld.h"
#endif

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

using namespace REngine;

namespace rbench {

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kExitOk = 0, kExitRunFailed = 1, kExitBadInput = 2;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::uint64_t kQuickSteps = 10;
#ifdef RENGINE_HAVE_BULLET
constexpr bool kHaveBullet = true;
#else
constexpr bool kHaveBullet = false;
#endif

struct ScalingRow {
  const ScalingScene* scene = nullptr;
  std::size_t bodies = 0;  // dynamic
  std::uint64_t steps = 0;
  bool sleeping = true, broadPhase = true;
  int threads = 1;
  int repeats = 0;
  double rengineMs = kNaN, bulletMs = kNaN;
  std::uint64_t hash = 0;

  double JoltEstimate() const { return bulletMs * scene->joltTable / scene->bulletTable; }
  double VsJolt() const { return rengineMs / JoltEstimate(); }
};

// FNV-1a, 64 bit, over each body's shape position and orientation, velocity and angular
// velocity (13 doubles, native byte order), in scene order: rengine-sim's hash= (StateHash
// in tools/rengine-sim/main.cpp), so the two can be compared.
std::uint64_t StateHash(const RSceneWorld& world) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (RBodyHandle handle : world.Live()) {
    const RRigidBody& b = world.Bodies()[handle];
    const RVec3 x = b.ShapePosition_W();
    const RQuat q = b.ShapeOrientation_WS();
    const RVec3& v = b.Velocity_W();
    const RVec3 w = b.AngularVelocity_W();
    const std::array<RScalar, 13> state{x.x(), x.y(), x.z(), q.w(), q.x(), q.y(), q.z(),
                                        v.x(), v.y(), v.z(), w.x(), w.y(), w.z()};
    unsigned char bytes[sizeof state];
    std::memcpy(bytes, state.data(), sizeof state);
    for (unsigned char byte : bytes) h = (h ^ byte) * 0x100000001b3ULL;
  }
  return h;
}

struct REngineRun {
  double ms = 0;  // per step
  std::uint64_t hash = 0;
  std::string failure;  // a body that became non-finite
};

REngineRun RunREngine(const RScene& scene, const RWorldSettings& settings) {
  RSceneWorld world(scene);
  RIntegrator integrator(settings);
  const Clock::time_point t0 = Clock::now();
  for (std::uint64_t s = 0; s < scene.steps; ++s) integrator.Update(world.Bodies(), scene.dt);
  const Clock::time_point t1 = Clock::now();
  REngineRun run;
  run.ms = std::chrono::duration<double, std::milli>(t1 - t0).count() /
           static_cast<double>(scene.steps);
  run.hash = StateHash(world);
  if (const auto& bad = integrator.NonFinite()) {
    run.failure =
        "body " + bad->bodyName + " became non-finite at step " + std::to_string(bad->step);
  }
  return run;
}

#ifdef RENGINE_HAVE_BULLET
double RunBullet(const RScene& scene) {
  const std::vector<RRigidBody> reference = CreateBodies(scene);
  const bench::BulletCoefficients coeffs =
      bench::ChooseCoefficients(scene.settings, reference, /*match=*/true);
  const std::unique_ptr<bench::BulletWorld> w = bench::BuildBullet(
      scene.settings, reference, coeffs, scene.settings.shortcuts.sleeping, scene.ignore);
  const btScalar dt = bench::Bt(scene.dt);
  const Clock::time_point t0 = Clock::now();
  for (std::uint64_t s = 0; s < scene.steps; ++s) w->world.stepSimulation(dt, 0);
  const Clock::time_point t1 = Clock::now();
  return std::chrono::duration<double, std::milli>(t1 - t0).count() /
         static_cast<double>(scene.steps);
}

// Said once per scene if Bullet's products cannot match REngine's combined coefficients.
void WarnCombineMismatch(const RScene& scene) {
  const bench::BulletCoefficients c =
      bench::ChooseCoefficients(scene.settings, CreateBodies(scene), true);
  if (c.restitutionError > 1e-12) {
    std::printf("  note: Bullet's restitution differs from REngine's by up to %.3g (%s)\n",
                c.restitutionError, c.restitutionExample.c_str());
  }
  if (c.frictionError > 1e-12) {
    std::printf("  note: Bullet's friction differs from REngine's by up to %.3g (%s)\n",
                c.frictionError, c.frictionExample.c_str());
  }
}
#endif

const char* OnOff(bool on) { return on ? "on" : "off"; }

std::string Number(double x, const char* format) {
  if (std::isnan(x)) return "";
  char text[32];
  std::snprintf(text, sizeof text, format, x);
  return text;
}

void PrintTable(const std::vector<ScalingRow>& rows) {
  std::printf("\n%-17s %6s %5s %5s %6s %7s %11s %11s %11s %8s  %s\n", "scene", "bodies", "steps",
              "sleep", "bphase", "threads", "REngine ms", "Bullet ms", "Jolt est.", "vs Jolt", "hash");
  for (const ScalingRow& r : rows) {
    std::printf("%-17s %6zu %5" PRIu64 " %5s %6s %7d %11.4g %11s %11s %8s  %016" PRIx64 "\n",
                r.scene->name, r.bodies, r.steps, OnOff(r.sleeping), OnOff(r.broadPhase), r.threads,
                r.rengineMs, Number(r.bulletMs, "%.4g").c_str(),
                Number(r.JoltEstimate(), "%.4g").c_str(), Number(r.VsJolt(), "%.3g").c_str(),
                r.hash);
  }
}

bool WriteCsv(const std::string& path, const std::vector<ScalingRow>& rows) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) return false;
  std::fprintf(file,
               "scene,series,bodies,steps,sleeping,broadphase,threads,repeats,rengine_ms_per_step,"
               "bullet_ms_per_step,jolt_estimate_ms_per_step,vs_jolt,rengine_table_ms_per_step,"
               "bullet_table_ms_per_step,jolt_table_ms_per_step,rengine_hash\n");
  for (const ScalingRow& r : rows) {
    const ScalingScene& s = *r.scene;
    std::fprintf(file, "%s,%s,%zu,%" PRIu64 ",%s,%s,%d,%d,%s,%s,%s,%s,%s,%s,%s,%016" PRIx64 "\n",
                 s.name, s.series, r.bodies, r.steps, OnOff(r.sleeping), OnOff(r.broadPhase), r.threads,
                 r.repeats, Number(r.rengineMs, "%.6g").c_str(), Number(r.bulletMs, "%.6g").c_str(),
                 Number(r.JoltEstimate(), "%.6g").c_str(), Number(r.VsJolt(), "%.4g").c_str(),
                 Number(s.rengineTable, "%g").c_str(), Number(s.bulletTable, "%g").c_str(),
                 Number(s.joltTable, "%g").c_str(), r.hash);
  }
  const bool ok = !std::ferror(file);
  return std::fclose(file) == 0 && ok;
}

// The scenes asked for, in table order, once each; throws a message for an unknown name.
std::vector<const ScalingScene*> ChooseScenes(const ScalingOptions& opt) {
  std::vector<const ScalingScene*> chosen;
  for (const ScalingScene& s : ScalingScenes()) {
    const bool asked = std::find(opt.scenes.begin(), opt.scenes.end(), s.name) != opt.scenes.end();
    if (opt.scenes.empty() ? (!opt.quick || s.quick) : asked) chosen.push_back(&s);
  }
  for (const std::string& name : opt.scenes) {
    const auto& all = ScalingScenes();
    const auto named = [&](const ScalingScene& s) { return name == s.name; };
    if (std::none_of(all.begin(), all.end(), named)) {
      throw std::string("--scenes: unknown scaling scene \"" + name + "\" (known: " +
                        ScalingSceneNames() + ")");
    }
  }
  return chosen;
}

// One scene: the interleaved runs, one row per REngine setting. Returns false when a run
// failed (reported).
bool RunScene(const ScalingScene& def, const RScene& scene, const ScalingOptions& opt,
              std::vector<ScalingRow>& rows) {
  // REngine's settings: each broad-phase setting on each thread count.
  struct Config {
    bool broadPhase;
    int threads;
  };
  std::vector<Config> configs;
  for (int t : opt.threads) {
    if (opt.broadPhase != ScalingOptions::BroadPhase::kOff) configs.push_back({true, t});
    if (opt.broadPhase != ScalingOptions::BroadPhase::kOn) configs.push_back({false, t});
  }

  std::size_t dynamic = 0;
  for (const RBodyDef& d : scene.bodies) dynamic += d.kind == RBodyKind::kStatic ? 0 : 1;
  std::printf("\n%s: %zu bodies (%zu dynamic), %" PRIu64 " steps of %.6g s, sleeping %s\n",
              def.name, scene.bodies.size(), dynamic, scene.steps, scene.dt,
              OnOff(scene.settings.shortcuts.sleeping));
#ifdef RENGINE_HAVE_BULLET
  WarnCombineMismatch(scene);
#endif

  std::vector<std::vector<double>> rengineMs(configs.size());
  std::vector<std::uint64_t> hashes(configs.size());
  std::vector<double> bulletMs;
  bool ok = true;
  for (int r = 0; r < opt.repeats; ++r) {
    std::printf("  run %d:", r + 1);
    for (std::size_t i = 0; i < configs.size(); ++i) {
      // With both settings, each goes first in every other repeat.
      const std::size_t k = r % 2 ? configs.size() - 1 - i : i;
      RWorldSettings settings = scene.settings;
      settings.shortcuts.broadPhase = configs[k].broadPhase;
      settings.threads = configs[k].threads;
      const REngineRun run = RunREngine(scene, settings);
      std::printf("  REngine%s x%d %9.4f ms/step", configs[k].broadPhase ? "" : " (all pairs)",
                  configs[k].threads, run.ms);
      rengineMs[k].push_back(run.ms);
      if (!run.failure.empty()) {
        std::printf("\n  error: REngine: %s\n", run.failure.c_str());
        ok = false;
      }
      if (r == 0) {
        hashes[k] = run.hash;
      } else if (run.hash != hashes[k]) {
        std::printf("\n  error: REngine's final state differs between runs (hash %016" PRIx64
                    ", then %016" PRIx64 ")\n",
                    hashes[k], run.hash);
        ok = false;
      }
    }
#ifdef RENGINE_HAVE_BULLET
    bulletMs.push_back(RunBullet(scene));
    std::printf("  Bullet %9.4f ms/step", bulletMs.back());
#endif
    std::printf("\n");
    std::fflush(stdout);
  }
  for (std::size_t k = 1; k < hashes.size(); ++k) {
    if (hashes[k] != hashes[0]) {
      std::printf("  error: the broad phase or the thread count changed the final state (hash %016" PRIx64
                  ", then %016" PRIx64 ")\n",
                  hashes[0], hashes[k]);
      ok = false;
    }
  }
  for (std::size_t k = 0; k < configs.size(); ++k) {
    ScalingRow row;
    row.scene = &def;
    row.bodies = dynamic;
    row.steps = scene.steps;
    row.sleeping = scene.settings.shortcuts.sleeping;
    row.broadPhase = configs[k].broadPhase;
    row.threads = configs[k].threads;
    row.repeats = opt.repeats;
    row.rengineMs = Median(rengineMs[k]);
    if (!bulletMs.empty()) row.bulletMs = Median(bulletMs);
    row.hash = hashes[k];
    rows.push_back(row);
  }
  return ok;
}

}  // namespace

std::string ScalingSceneNames() {
  std::string names;
  for (const ScalingScene& s : ScalingScenes()) {
    names += std::string(names.empty() ? "" : ",") + s.name;
  }
  return names;
}

int RunScaling(const ScalingOptions& options) {
  ScalingOptions opt = options;
  std::vector<const ScalingScene*> scenes;
  try {
    scenes = ChooseScenes(opt);
  } catch (const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return kExitBadInput;
  }
  if (opt.quick) {
    opt.repeats = 1;
    if (opt.steps == 0) opt.steps = kQuickSteps;
  }
  if (const std::string error = EnsureScalingScenes(opt.sceneDir, scenes); !error.empty()) {
    std::fprintf(stderr, "error: %s\n", error.c_str());
    return kExitBadInput;
  }
  if (opt.generateOnly) {
    std::printf("scaling scenes ready in %s\n", opt.sceneDir.c_str());
    return kExitOk;
  }

#ifdef RENGINE_HAVE_BULLET
  std::printf("scaling: REngine (double) and Bullet %d.%02d (%s precision, btDbvtBroadphase, "
              "stepSimulation(dt, 0), deactivation as the scene's solver.sleeping)\n",
              btGetVersion() / 100, btGetVersion() % 100,
              sizeof(btScalar) == 8 ? "double" : "single");
#else
  std::printf("scaling: REngine only (built without Bullet: no Bullet series, no Jolt estimate)\n");
#endif
  std::printf("timing: steady_clock around the step loop only; per scene %d run%s of each "
              "engine%s, medians; steps: %s\n",
              opt.repeats, opt.repeats == 1 ? "" : "s",
              kHaveBullet ? ", interleaved (REngine, Bullet, REngine, ...)" : "",
              opt.steps ? std::to_string(opt.steps).c_str() : "each scene's own");
  if (kHaveBullet) {
    std::printf("jolt estimate = Bullet ms/step of this run x Jolt / Bullet of the reference "
                "table; vs Jolt = REngine / jolt estimate (<= 1: at or under Jolt)\n");
  }

  std::vector<ScalingRow> rows;
  bool ok = true;
  for (const ScalingScene* def : scenes) {
    RScene scene;
    try {
      scene = LoadScene(ScalingScenePath(opt.sceneDir, *def).string());
      if (opt.steps) scene.steps = opt.steps;
      CheckSceneLimits(scene, RSceneLimits{});
      if (!scene.actions.empty()) {
        throw RSceneError(scene.fileName, "actions", "--scaling times scenes without actions");
      }
      ok = RunScene(*def, scene, opt, rows) && ok;
    } catch (const RSceneError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return kExitBadInput;
    }
  }

  PrintTable(rows);
  if (!WriteCsv(opt.csvPath, rows)) {
    std::fprintf(stderr, "error: %s: write failed: %s\n", opt.csvPath.c_str(),
                 std::strerror(errno));
    return kExitBadInput;
  }
  std::printf("wrote %s (%zu rows)\n", opt.csvPath.c_str(), rows.size());
  return ok ? kExitOk : kExitRunFailed;
}

}  // namespace rbench
