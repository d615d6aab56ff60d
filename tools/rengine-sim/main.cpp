// rengine-sim: runs a scene file and writes its trajectory (docs/scene-format.md).
//
//   rengine-sim SCENE.json [--out TRAJ.csv] [--steps N] [--dt S] [--every K] [--quiet]
//               [--max-seconds S] [--rays RAYS.csv] [--events EVENTS.csv]
//               [--save-state N:FILE] [--load-state FILE]
//   rengine-sim SCENE.json --describe
//
// Exit codes: 0 success; 2 bad input (scene, options, files); 1 a failure during the run.
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJobSystem.h>
#include <REnginePhysics/RScene.h>

#include "csv.h"
#include "events.h"
#include "rays.h"
#include "state.h"
#include "trajectory.h"
#include "watchdog.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#ifdef _WIN32
#include <io.h>
#else
#include <unistd.h>
#endif

using namespace REngine;
using REngine::sim::CsvField;
using REngine::sim::StateHash;
using REngine::sim::TrajectoryWriter;

namespace {

constexpr int kExitOk = 0;
constexpr int kExitRunFailed = 1;
constexpr int kExitBadInput = 2;

using Clock = std::chrono::steady_clock;

bool StderrIsTerminal() {
#ifdef _WIN32
  return _isatty(_fileno(stderr)) != 0;
#else
  return isatty(fileno(stderr)) != 0;
#endif
}

// A bad command line: reported like a bad scene, exit code 2.
struct UsageError {
  std::string message;
};

// Options are read as text and converted here rather than by CLI11, whose integer parsing
// (strtoull, base 0) takes "-1" as 2^64 - 1 and "010" as 8.
std::uint64_t ParseCount(const std::string& text, const char* option, std::uint64_t min) {
  std::uint64_t n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || end != text.data() + text.size() || n < min) {
    throw UsageError{std::string(option) + ": must be an integer >= " + std::to_string(min) +
                     " (got \"" + text + "\")"};
  }
  return n;
}

// A number > 0 of seconds; --dt's at most RIntegrator::kMaxDt, the longest step there is.
double ParseSeconds(const std::string& text, const char* option, bool step) {
  double x = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(x) || !(x > 0) ||
      (step && x > RIntegrator::kMaxDt)) {
    throw UsageError{std::string(option) + (step ? ": must be a finite number > 0 and at most 1 (s)"
                                                 : ": must be a finite number > 0") +
                     " (got \"" + text + "\")"};
  }
  return x;
}

// An output file opened for writing, or null after saying why (the caller exits 2).
std::FILE* OpenOutput(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::fprintf(stderr, "error: %s: cannot open for writing: %s\n", path.c_str(), std::strerror(errno));
  return f;
}

// "step 1234/36000 (3%)" on a terminal, redrawn at most 10 times a second.
class Progress {
 public:
  Progress(bool enabled, std::uint64_t total) : m_enabled(enabled), m_total(total) {}

  void Show(std::uint64_t step, Clock::time_point now) {
    if (!m_enabled || now < m_next) return;
    m_next = now + std::chrono::milliseconds(100);
    std::fprintf(stderr, "\rstep %" PRIu64 "/%" PRIu64 " (%.0f%%)", step, m_total,
                 100.0 * static_cast<double>(step) / static_cast<double>(m_total));
    m_shown = true;
  }

  void Clear() {
    if (m_shown) std::fputs("\r\x1b[K", stderr);
    m_shown = false;
  }

 private:
  bool m_enabled;
  bool m_shown = false;
  std::uint64_t m_total;
  Clock::time_point m_next = Clock::now() + std::chrono::milliseconds(100);
};

// Mass properties in world terms. Moments ascend, and the axes are permuted to match: the
// body frame's own order is an implementation choice, the sorted order is not.
void Describe(const RSceneWorld& world) {
  using ojson = nlohmann::ordered_json;
  const auto vec = [](const RVec3& v) { return ojson::array({v.x(), v.y(), v.z()}); };
  ojson list = ojson::array();
  for (RBodyHandle h : world.Live()) {
    const RRigidBody& b = world.Bodies()[h];
    const RMat3 R_WB = b.Orientation_WB().toRotationMatrix();
    const RVec3& I = b.Inertia_B();
    std::array<int, 3> order{0, 1, 2};
    std::stable_sort(order.begin(), order.end(), [&](int a, int c) { return I[a] < I[c]; });
    ojson moments = ojson::array(), axes = ojson::array();
    for (int k : order) {
      moments.push_back(I[k]);
      axes.push_back(vec(R_WB.col(k)));
    }
    list.push_back({{"name", b.Name()},
                    {"mass", b.Mass()},
                    {"com", vec(b.Position_W())},
                    {"principal_moments", moments},
                    {"principal_axes", axes}});
  }
  std::cout << list.dump(2) << '\n';
}

int Run(int argc, char** argv) {
  CLI::App app{"Runs a REngine scene (rengine-scene/1) and writes its trajectory as CSV.",
               "rengine-sim"};
  std::string scenePath, outPath, stepsText, dtText, everyText, maxSecondsText, raysPath, eventsPath;
  std::string saveStateText, loadStatePath;
  int threads = 0;
  bool quiet = false, describe = false, profile = false;
  app.add_option("scene", scenePath, "Scene file (JSON)")->required();
  auto* out = app.add_option("--out", outPath, "Trajectory CSV (default: standard output)");
  auto* steps = app.add_option("--steps", stepsText, "Number of steps (overrides the scene)");
  auto* dt = app.add_option("--dt", dtText, "Step size, s (overrides the scene)");
  auto* every = app.add_option("--every", everyText,
                               "Write every K-th step (the first and last always), default 1");
  auto* maxSeconds = app.add_option(
      "--max-seconds", maxSecondsText,
      "Stop with exit code 1 when stepping has taken this long (wall clock), rows so far kept; a step still "
      "running 1 s after is stopped inside");
  auto* rays = app.add_option("--rays", raysPath,
                              "Answer the scene's rays into this CSV (step,ray,body,distance,x,y,z,"
                              "nx,ny,nz)");
  auto* events = app.add_option("--events", eventsPath,
                                "Write the contact events into this CSV (step,time,event,body_a,body_b,"
                                "x,y,z,nx,ny,nz,normal_impulse,tangent_impulse)");
  auto* saveState = app.add_option("--save-state", saveStateText,
                                   "Write the whole world state after step N (and its actions) to FILE: N:FILE");
  auto* loadState = app.add_option("--load-state", loadStatePath,
                                   "Start from a state written by --save-state for this scene instead of step 0");
  app.add_flag("--quiet", quiet, "No progress display");
  app.add_option("--threads", threads,
                 "Threads the step runs on (default 0: what the machine has); the hash does not "
                 "depend on it")
      ->check(CLI::Range(0, 1024));
  app.add_flag("--profile", profile,
               "Also print the mean time per step of each stage (RStepProfile), ms");
  app.add_flag("--describe", describe,
               "Print each body's mass, centre of mass and principal axes as JSON, then exit")
      ->excludes(out, steps, dt, every, rays, events, saveState, loadState);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints the help or the error
    return code == 0 ? kExitOk : kExitBadInput;
  }

  RScene scene;
  std::optional<RSceneWorld> world;
  std::optional<RThreadPool> pool;  // the integrator's threads: it must outlive the integrator
  RIntegrator integrator;
  std::uint64_t startStep = 0;  // the loaded state's, or 0
  std::optional<sim::StateSave> stateSave;
  std::uint64_t sceneTag = 0;
  std::uint64_t everyK = 1;
  double budget = std::numeric_limits<double>::infinity();  // s of stepping
  try {
    // Options are checked before the scene is read: they are cheap, and the first error
    // reported should not depend on how large the scene is.
    const std::optional<std::uint64_t> stepsOverride =
        steps->count() ? std::optional(ParseCount(stepsText, "--steps", 0)) : std::nullopt;
    const std::optional<double> dtOverride =
        dt->count() ? std::optional(ParseSeconds(dtText, "--dt", true)) : std::nullopt;
    if (every->count()) everyK = ParseCount(everyText, "--every", 1);
    if (maxSeconds->count()) budget = ParseSeconds(maxSecondsText, "--max-seconds", false);
    if (saveState->count()) stateSave = sim::ParseSaveState(saveStateText);
    scene = LoadScene(scenePath);
    if (stepsOverride) scene.steps = *stepsOverride;
    if (dtOverride) scene.dt = *dtOverride;
    try {
      CheckSceneLimits(scene, RSceneLimits{});  // --steps may have raised the work
    } catch (const RSceneError& e) {
      // The scene passed the same check with its own steps: a limit on them is --steps' now.
      if (stepsOverride && e.JsonPath() == "steps") throw UsageError{"--steps: " + e.Problem()};
      throw;
    }
    world.emplace(scene);
    scene.settings.threads = threads;
    // Contact events cost only when asked for: by --events, or by --save-state, whose state
    // must hold the pairs touching at its step for a run loaded from it to write the same
    // events as the run that never stopped (they change nothing else).
    const bool contactEvents = events->count() > 0 || stateSave.has_value();
    scene.settings.contactEvents = contactEvents;
    integrator = RIntegrator(scene.settings);
    if (stateSave || loadState->count()) sceneTag = sim::SceneTag(scenePath, scene.dt);
    if (loadState->count()) {
      // The state holds the world after its step's actions; the run goes on from there.
      startStep = sim::LoadSceneState(loadStatePath, scene, sceneTag, *world, integrator);
      integrator.Settings().threads = threads;
      integrator.Settings().contactEvents = contactEvents;
    } else {
      // The actions of step 0 come before the first row: the state the first step starts from.
      world->ApplyActions(0);
    }
    if (stateSave && (stateSave->step < startStep || stateSave->step > scene.steps)) {
      throw UsageError{"--save-state: step " + std::to_string(stateSave->step) + " is not among the steps this run " +
                       "has (" + std::to_string(startStep) + " to " + std::to_string(scene.steps) + ")"};
    }
  } catch (const sim::StateError& e) {
    std::fprintf(stderr, "error: %s\n", e.message.c_str());
    return kExitBadInput;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "error: %s\n", e.message.c_str());
    return kExitBadInput;
  } catch (const RSceneError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }

  if (describe) {
    Describe(*world);
    return kExitOk;
  }

  // The step's threads are started here, before any output file is opened: a machine that
  // cannot start as many as --threads asks for (an address-space or thread limit) is told
  // so at the door, as for an output file that cannot be opened, and no trajectory is cut
  // short. The integrator runs on them as on its own (the results are the same bits).
  const int poolThreads = threads > 0 ? threads : RThreadPool::MachineThreads();
  if (poolThreads > 1) {
    try {
      pool.emplace(poolThreads);
    } catch (const std::system_error& e) {
      std::fprintf(stderr, "error: --threads %d%s: %s\n", threads,
                   threads > 0 ? "" : (" (every hardware thread, " + std::to_string(poolThreads) + ")").c_str(),
                   e.what());
      return kExitBadInput;
    }
    integrator.SetJobSystem(&*pool);
  }

  // Opened only now, so that a bad scene never truncates an existing trajectory.
  // (On a failure, the files opened before it are closed.)
  std::FILE* file = out->count() ? OpenOutput(outPath) : stdout;
  std::FILE* raysFile = file && rays->count() ? OpenOutput(raysPath) : nullptr;
  const bool raysOpen = !rays->count() || raysFile;
  std::FILE* eventsFile = file && raysOpen && events->count() ? OpenOutput(eventsPath) : nullptr;
  const bool eventsOpen = !events->count() || eventsFile;
  std::FILE* stateFile = file && raysOpen && eventsOpen && stateSave ? OpenOutput(stateSave->path) : nullptr;
  if (!file || !raysOpen || !eventsOpen || (stateSave && !stateFile)) {
    if (file && file != stdout) std::fclose(file);
    if (raysFile) std::fclose(raysFile);
    if (eventsFile) std::fclose(eventsFile);
    return kExitBadInput;
  }
  TrajectoryWriter writer(file);
  std::optional<sim::RayWriter> rayWriter;
  if (raysFile) rayWriter.emplace(scene, raysFile);
  std::optional<sim::EventWriter> eventWriter;
  if (eventsFile) eventWriter.emplace(eventsFile), eventWriter->Know(world->Bodies());
  bool stateReached = false, stateWritten = false;
  const auto finishOutput = [&] {
    bool ok = writer.Flush();
    if (file != stdout) ok = std::fclose(file) == 0 && ok;
    if (!ok) {
      std::fprintf(stderr, "error: %s: write failed: %s\n",
                   out->count() ? outPath.c_str() : "standard output", std::strerror(errno));
    }
    if (raysFile) {
      const bool raysOk = rayWriter->Flush() && std::fclose(raysFile) == 0;
      if (!raysOk) {
        std::fprintf(stderr, "error: %s: write failed: %s\n", raysPath.c_str(), std::strerror(errno));
      }
      ok = ok && raysOk;
    }
    if (eventsFile) {
      const bool eventsOk = eventWriter->Flush() && std::fclose(eventsFile) == 0;
      if (!eventsOk) {
        std::fprintf(stderr, "error: %s: write failed: %s\n", eventsPath.c_str(), std::strerror(errno));
      }
      ok = ok && eventsOk;
    }
    if (stateFile) {
      const bool closed = std::fclose(stateFile) == 0;
      if (!stateReached) {
        // The run stopped before the step (exit 1 either way): no state, not an empty one.
        std::remove(stateSave->path.c_str());
        std::fprintf(stderr, "error: %s: no state written: the run stopped before step %" PRIu64 "\n",
                     stateSave->path.c_str(), stateSave->step);
      } else if (!(closed && stateWritten)) {
        std::fprintf(stderr, "error: %s: write failed: %s\n", stateSave->path.c_str(), std::strerror(errno));
      }
      ok = ok && closed && stateWritten;
    }
    return ok;
  };
  // --save-state: the world after step k and its actions, as the trajectory's row k shows it.
  const auto saveAt = [&](std::uint64_t step) {
    if (stateFile && step == stateSave->step) {
      stateReached = true;
      stateWritten = sim::WriteSceneState(stateFile, integrator, *world, sceneTag);
    }
  };

  writer.Rows(startStep, scene.dt, *world);
  if (rayWriter) rayWriter->Answer(startStep, *world);
  saveAt(startStep);
  Progress progress(!quiet && StderrIsTerminal(), scene.steps);
  Clock::duration stepping{};
  RStepProfile profileSum;
  // --max-seconds inside a step that runs on past it (see watchdog.h): the rows written so
  // far are kept, the step's own are not (its world is half stepped).
  std::atomic<std::uint64_t> running{0};
  std::optional<sim::StepWatchdog> watchdog;
  if (std::isfinite(budget)) {
    watchdog.emplace(budget, [&] {
      finishOutput();
      std::fprintf(stderr, "error: stopped during step %" PRIu64 " of %" PRIu64 ": --max-seconds %s reached and the "
                   "step still running %lld s after\n", running.load(), scene.steps, maxSecondsText.c_str(),
                   static_cast<long long>(sim::StepWatchdog::kGrace.count()));
      std::fflush(stderr);
      std::_Exit(kExitRunFailed);
    });
  }
  for (std::uint64_t step = startStep + 1; step <= scene.steps; ++step) {
    const Clock::time_point t0 = Clock::now();
    running = step;
    if (watchdog) watchdog->BeginStep();
    integrator.Update(world->Bodies(), scene.dt);
    try {
      world->UpdateCharacters(scene.dt, integrator.Settings().gravity_W);
    } catch (const RSceneError& e) {
      progress.Clear();
      finishOutput();
      std::fprintf(stderr, "error: %s\n", e.what());
      return kExitBadInput;
    }
    if (watchdog) watchdog->EndStep();
    const Clock::time_point t1 = Clock::now();
    stepping += t1 - t0;
    const RStepProfile& p = integrator.Profile();
    profileSum.collisionDetection += p.collisionDetection, profileSum.findImpulses += p.findImpulses;
    profileSum.updateObjects += p.updateObjects, profileSum.contactEvents += p.contactEvents;
    profileSum.total += p.total;
    // The events of step k, before its actions (a body removed after it is still named).
    if (eventWriter) {
      eventWriter->Write(step, scene.dt, integrator.Events(), world->Bodies());
      eventWriter->WriteCharacters(step, scene.dt, world->Characters(), world->Bodies());
    }
    // What the game does after step k, before step k + 1; the rows of step k show it (a body
    // added has its first row, a body removed had its last in step k - 1).
    try {
      world->ApplyActions(step);
    } catch (const RSceneError& e) {
      progress.Clear();
      finishOutput();
      std::fprintf(stderr, "error: %s\n", e.what());
      return kExitBadInput;
    }
    if (const auto& bad = integrator.NonFinite()) {
      progress.Clear();
      finishOutput();  // the rows up to the failure help find its cause
      std::fprintf(stderr, "error: body '%s' became non-finite or left the world (1e15 m) at step %" PRIu64 "\n",
                   bad->bodyName.c_str(), bad->step);
      return kExitRunFailed;
    }
    saveAt(step);
    if (step % everyK == 0 || step == scene.steps) writer.Rows(step, scene.dt, *world);
    if (rayWriter) rayWriter->Answer(step, *world);
    progress.Show(step, t1);
    if (std::chrono::duration<double>(stepping).count() > budget && step < scene.steps) {
      progress.Clear();
      if (step % everyK != 0) writer.Rows(step, scene.dt, *world);
      finishOutput();
      std::fprintf(stderr, "error: stopped after step %" PRIu64 " of %" PRIu64
                           ": --max-seconds %s reached\n", step, scene.steps, maxSecondsText.c_str());
      return kExitRunFailed;
    }
  }
  progress.Clear();
  if (!finishOutput()) return kExitRunFailed;

  const std::uint64_t stepsRun = scene.steps - startStep;
  const double msPerStep =
      stepsRun == 0 ? 0.0
                    : std::chrono::duration<double, std::milli>(stepping).count() /
                          static_cast<double>(stepsRun);
  if (profile && stepsRun > 0) {
    const double n = static_cast<double>(stepsRun);
    std::fprintf(stderr, "profile_ms: collision_detection=%.4g find_impulses=%.4g update_objects=%.4g "
                 "contact_events=%.4g total=%.4g\n", profileSum.collisionDetection / n, profileSum.findImpulses / n,
                 profileSum.updateObjects / n, profileSum.contactEvents / n, profileSum.total / n);
    const RPairStats& st = integrator.PairStats();
    std::fprintf(stderr,
                 "last_step: sphere_tests=%" PRIu64 " broad_phase=%d rejected_boxes=%" PRIu64
                 " narrow_phase=%" PRIu64 " reused=%" PRIu64 " reused_inverses=%" PRIu64 " contacts=%" PRIu64 " contact_points=%" PRIu64
                 " warm_started=%" PRIu64 " sleeping=%" PRIu64 "\n",
                 st.sphereTests, st.broadPhase ? 1 : 0, st.rejectedBoxes, st.narrowPhase, st.reusedManifolds, st.reusedInverses,
                 st.contacts, st.contactPoints, st.warmStarted, st.sleepingBodies);
  }
  std::fprintf(stderr, "steps=%" PRIu64 " bodies=%zu ms_per_step=%.6g hash=%016" PRIx64 "\n",
               scene.steps, world->Live().size(), msPerStep, StateHash(*world));
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "error: unknown exception\n");
  }
  return kExitRunFailed;
}
