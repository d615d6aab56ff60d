// rengine-bench --scaling: see scaling.h.
//
// Each scene file is read once (LoadScene, not timed). Then, --repeats times in turn, REngine
// runs the scene from its start on each of its settings, then Bullet, then Jolt on each
// thread count (REngine, Bullet, Jolt, REngine, Bullet, Jolt, ...: a drift of the shared
// machine falls on all alike), each in a world built afresh and timed around its step loop
// alone (std::chrono::steady_clock; building the world is not timed). The medians are
// reported. With several REngine settings (--broadphase both, --threads 1,2) or Jolt thread
// counts, their order is reversed in every other repeat.
//
//  * REngine: the scene's world as rengine-sim steps it (RSceneWorld, RIntegrator with the
//    scene's settings: solver.sleeping as the scene says, solver.broadphase on unless
//    --broadphase says otherwise). The final state's hash is rengine-sim's (FNV-1a over each
//    body's shape pose and velocities), so `rengine-sim SCENE --steps N` prints the same one;
//    every repeat must give the same hash.
//  * Bullet (where it was found at build time), one thread: the same bodies through
//    tools/bench/BulletWorld.h as bench_bullet builds them (restitution and friction mapped so
//    that Bullet's products equal REngine's combined values), deactivation on when the scene's
//    solver.sleeping is (Bullet's defaults) and off otherwise, stepSimulation(dt, 0).
//  * Jolt (where CMake was given REngine_JOLT_DIR), on each --threads count: the same bodies
//    through JoltScaling.cpp (which lists what is mapped and how), PhysicsSystem::Update(dt,
//    1) on a JobSystemThreadPool of threads - 1 workers and the calling thread.
//    After the first repeat, Jolt's world is summarised beside REngine's (bodies, awake,
//    mean and lowest height, kinetic energy), so a scene Jolt does not run as REngine does
//    shows.
//
// CSV, one row per scene and REngine setting (broad phase, threads):
//   scene,series,bodies,steps,sleeping,broadphase,threads,repeats,rengine_ms_per_step,
//   bullet_ms_per_step,jolt_ms_per_step,rengine_over_jolt,rengine_hash,rengine_awake,
//   jolt_awake,rengine_mean_height,jolt_mean_height,rengine_kinetic_energy,
//   jolt_kinetic_energy
// bodies counts the dynamic bodies (a pile also has its static ground); jolt_* is Jolt on the
// row's thread count, rengine_over_jolt = rengine / jolt ms per step (< 1: REngine faster);
// the state columns are after the first repeat's run, REngine's and Jolt's (m, J). The Bullet
// columns are empty without Bullet, the Jolt ones without Jolt.
#include "scaling.h"

#include "JoltScaling.h"
#include "report.h"
#include "scaling_scenes.h"
#include "thread_model.h"

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
#ifdef RENGINE_HAVE_JOLT
constexpr bool kHaveJolt = true;
#else
constexpr bool kHaveJolt = false;
#endif

struct ScalingRow {
  const ScalingScene* scene = nullptr;
  std::size_t bodies = 0;  // dynamic
  std::uint64_t steps = 0;
  bool sleeping = true, broadPhase = true;
  int threads = 1;
  int repeats = 0;
  double rengineMs = kNaN, bulletMs = kNaN, joltMs = kNaN;  // Jolt on this row's threads
  std::uint64_t hash = 0;
  // After the first repeat; `jolt` only where joltMs is.
  WorldSummary rengine, jolt;

  double VsJolt() const { return rengineMs / joltMs; }
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
  WorldSummary summary;
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
  run.summary = Summarize(world);
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

// The threads' label: "x2" (x0: the machine's count, REngine's and Jolt's default).
std::string ThreadsLabel(const char* engine, int threads) {
  return std::string(engine) + " x" + std::to_string(threads);
}

// One line per scene and broad-phase setting: REngine's and Jolt's times on each thread
// count side by side, their ratios, and Bullet's single-thread time.
void PrintTable(const std::vector<ScalingRow>& rows, const std::vector<int>& threads) {
  std::printf("\n%-17s %6s %5s %5s %6s", "scene", "bodies", "steps", "sleep", "bphase");
  for (int t : threads) std::printf(" %10s", ThreadsLabel("REngine", t).c_str());
  if (kHaveBullet) std::printf(" %10s", "Bullet x1");
  if (kHaveJolt) {
    for (int t : threads) std::printf(" %10s", ThreadsLabel("Jolt", t).c_str());
    for (int t : threads) std::printf(" %8s", ThreadsLabel("R/J", t).c_str());
  }
  std::printf("  %s\n", "hash");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ScalingRow& r = rows[i];
    const auto sameLine = [&](const ScalingRow& o) {
      return o.scene == r.scene && o.broadPhase == r.broadPhase;
    };
    if (std::any_of(rows.begin(), rows.begin() + static_cast<std::ptrdiff_t>(i), sameLine)) continue;
    std::vector<const ScalingRow*> byThreads;  // in --threads order
    for (int t : threads) {
      const auto it = std::find_if(rows.begin(), rows.end(), [&](const ScalingRow& o) {
        return sameLine(o) && o.threads == t;
      });
      byThreads.push_back(it == rows.end() ? nullptr : &*it);
    }
    std::printf("%-17s %6zu %5" PRIu64 " %5s %6s", r.scene->name, r.bodies, r.steps,
                OnOff(r.sleeping), OnOff(r.broadPhase));
    for (const ScalingRow* t : byThreads) std::printf(" %10s", Number(t ? t->rengineMs : kNaN, "%.4g").c_str());
    if (kHaveBullet) std::printf(" %10s", Number(r.bulletMs, "%.4g").c_str());
    if (kHaveJolt) {
      for (const ScalingRow* t : byThreads) std::printf(" %10s", Number(t ? t->joltMs : kNaN, "%.4g").c_str());
      for (const ScalingRow* t : byThreads) std::printf(" %8s", Number(t ? t->VsJolt() : kNaN, "%.3g").c_str());
    }
    std::printf("  %016" PRIx64 "\n", r.hash);
  }
}

bool WriteCsv(const std::string& path, const std::vector<ScalingRow>& rows) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) return false;
  std::fprintf(file,
               "scene,series,bodies,steps,sleeping,broadphase,threads,repeats,rengine_ms_per_step,"
               "bullet_ms_per_step,jolt_ms_per_step,rengine_over_jolt,rengine_hash,rengine_awake,"
               "jolt_awake,rengine_mean_height,jolt_mean_height,rengine_kinetic_energy,"
               "jolt_kinetic_energy\n");
  for (const ScalingRow& r : rows) {
    const ScalingScene& s = *r.scene;
    const bool jolt = !std::isnan(r.joltMs);
    std::fprintf(file, "%s,%s,%zu,%" PRIu64 ",%s,%s,%d,%d,%s,%s,%s,%s,%016" PRIx64 ",%zu,%s,%.6g,%s,%.6g,%s\n",
                 s.name, s.series, r.bodies, r.steps, OnOff(r.sleeping), OnOff(r.broadPhase), r.threads,
                 r.repeats, Number(r.rengineMs, "%.6g").c_str(), Number(r.bulletMs, "%.6g").c_str(),
                 Number(r.joltMs, "%.6g").c_str(), Number(r.VsJolt(), "%.4g").c_str(), r.hash,
                 r.rengine.awake, jolt ? std::to_string(r.jolt.awake).c_str() : "",
                 r.rengine.meanHeight, Number(jolt ? r.jolt.meanHeight : kNaN, "%.6g").c_str(),
                 r.rengine.kineticEnergy, Number(jolt ? r.jolt.kineticEnergy : kNaN, "%.6g").c_str());
  }
  const bool ok = !std::ferror(file);
  return std::fclose(file) == 0 && ok;
}

// "N bodies (D dynamic, A awake), mean height Y m (lowest Z m), kinetic energy K J".
void PrintSummary(const char* who, const WorldSummary& s) {
  std::printf("  after run 1, %-10s %6zu bodies (%zu dynamic, %zu awake), mean height %.4g m "
              "(lowest %.4g m), kinetic energy %.6g J\n",
              who, s.bodies, s.dynamic, s.awake, s.meanHeight, s.minHeight, s.kineticEnergy);
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
  // Jolt on each thread count; a scene Jolt cannot run (a shape it is not given) or ran with
  // contacts dropped is reported once and gets no Jolt figures.
  const std::vector<int>& joltThreads = opt.threads;
  std::vector<std::vector<double>> joltMs(joltThreads.size());
  std::vector<WorldSummary> joltSummary(joltThreads.size());
  bool joltOk = kHaveJolt;
  WorldSummary rengineSummary;
  bool ok = true;
  for (int r = 0; r < opt.repeats; ++r) {
    std::printf("  run %d:", r + 1);
    for (std::size_t i = 0; i < configs.size(); ++i) {
      // With several settings, each goes first in every other repeat.
      const std::size_t k = r % 2 ? configs.size() - 1 - i : i;
      RWorldSettings settings = scene.settings;
      settings.shortcuts.broadPhase = configs[k].broadPhase;
      settings.threads = configs[k].threads;
      const REngineRun run = RunREngine(scene, settings);
      std::printf("  REngine%s x%d %9.4f", configs[k].broadPhase ? "" : " (all pairs)",
                  configs[k].threads, run.ms);
      rengineMs[k].push_back(run.ms);
      if (r == 0 && k == 0) rengineSummary = run.summary;
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
    std::printf("  Bullet %9.4f", bulletMs.back());
#endif
#ifdef RENGINE_HAVE_JOLT
    for (std::size_t i = 0; i < joltThreads.size() && joltOk; ++i) {
      const std::size_t k = r % 2 ? joltThreads.size() - 1 - i : i;
      const JoltRun run = RunJolt(scene, joltThreads[k]);
      if (!run.error.empty()) {
        std::printf("\n  Jolt x%d: %s: no Jolt figures for this scene\n", joltThreads[k], run.error.c_str());
        joltOk = false;
        ok = ok && !run.ran;  // contacts dropped: a failed run, not a scene left out
        break;
      }
      std::printf("  Jolt x%d %9.4f", joltThreads[k], run.ms);
      joltMs[k].push_back(run.ms);
      if (r == 0) joltSummary[k] = run.summary;
    }
#endif
    std::printf("  ms/step\n");
    std::fflush(stdout);
  }
  if (joltOk) {
    PrintSummary("REngine", rengineSummary);
    for (std::size_t k = 0; k < joltThreads.size(); ++k) {
      PrintSummary(ThreadsLabel("Jolt", joltThreads[k]).c_str(), joltSummary[k]);
    }
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
    row.rengine = rengineSummary;
    const auto t = std::find(joltThreads.begin(), joltThreads.end(), configs[k].threads);
    const std::size_t j = static_cast<std::size_t>(t - joltThreads.begin());
    if (joltOk && !joltMs[j].empty()) {
      row.joltMs = Median(joltMs[j]);
      row.jolt = joltSummary[j];
    }
    rows.push_back(row);
  }
  return ok;
}

// --model-threads: this run's measured REngine rows of the scene (broad phase on), for the
// thread model (thread_model.h) to set beside its own.
std::vector<MeasuredRow> Measured(const ScalingScene& def, const std::vector<ScalingRow>& rows) {
  std::vector<MeasuredRow> measured;
  for (const ScalingRow& row : rows) {
    if (row.scene == &def && row.broadPhase) measured.push_back({row.threads, row.rengineMs, row.hash});
  }
  return measured;
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

  std::printf("scaling: REngine (double)");
#ifdef RENGINE_HAVE_BULLET
  std::printf(", Bullet %d.%02d (%s precision, btDbvtBroadphase, one thread, stepSimulation(dt, 0), "
              "deactivation as the scene's solver.sleeping)",
              btGetVersion() / 100, btGetVersion() % 100, sizeof(btScalar) == 8 ? "double" : "single");
#else
  std::printf(", no Bullet series (built without Bullet)");
#endif
#ifdef RENGINE_HAVE_JOLT
  std::printf(", Jolt %s (double precision, JobSystemThreadPool of threads - 1 workers, "
              "Update(dt, 1), sleeping as the scene's solver.sleeping)\n",
              JoltVersion().c_str());
#else
  std::printf("\nJolt not available (configure with -DREngine_JOLT_DIR=<Jolt 5.5 install prefix>)\n");
#endif
  const std::string engines = std::string("REngine") + (kHaveBullet ? ", Bullet" : "") + (kHaveJolt ? ", Jolt" : "");
  std::printf("timing: steady_clock around the step loop only; per scene %d run%s of each "
              "engine%s, medians; steps: %s\n",
              opt.repeats, opt.repeats == 1 ? "" : "s",
              kHaveBullet || kHaveJolt ? (", interleaved (" + engines + ", REngine, ...)").c_str() : "",
              opt.steps ? std::to_string(opt.steps).c_str() : "each scene's own");
  if (kHaveJolt) {
    std::printf("R/J xN = REngine ms / Jolt ms, both on N threads (< 1: REngine faster)\n");
  }

  std::vector<ScalingRow> rows;
  std::vector<ModelRow> modelRows;
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
      if (!opt.modelThreads.empty()) {
        ok = ModelScene(def->name, scene, opt.modelThreads, opt.repeats, Measured(*def, rows), StateHash, modelRows) && ok;
      }
    } catch (const RSceneError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return kExitBadInput;
    }
  }

  PrintTable(rows, opt.threads);
  if (!WriteCsv(opt.csvPath, rows)) {
    std::fprintf(stderr, "error: %s: write failed: %s\n", opt.csvPath.c_str(),
                 std::strerror(errno));
    return kExitBadInput;
  }
  std::printf("wrote %s (%zu rows)\n", opt.csvPath.c_str(), rows.size());
  if (!modelRows.empty()) {
    if (!PrintAndWriteModel(modelRows, opt.modelCsvPath)) {
      std::fprintf(stderr, "error: %s: write failed: %s\n", opt.modelCsvPath.c_str(), std::strerror(errno));
      return kExitBadInput;
    }
    std::printf("wrote %s (%zu rows)\n", opt.modelCsvPath.c_str(), modelRows.size());
  }
  return ok ? kExitOk : kExitRunFailed;
}

}  // namespace rbench
