// rengine-bench: work-precision benchmark (run time against error).
//
//   rengine-bench [--scenes a,b,...] [--csv FILE] [--repeats N] [--quick]
//   rengine-bench --shortcuts [--csv FILE] [--repeats N] [--quick]   (see shortcuts.h)
//   rengine-bench --scaling [--scenes a,b,...] [--steps N] [--broadphase on|off|both]
//                 [--scene-dir DIR] [--generate-scenes] [--csv FILE] [--repeats N] [--quick]
//                 [--threads 1,2]
//                 (ms/step against body count, REngine, Bullet and Jolt: see scaling.h)
//
// Runs reference scenes whose answer is known in closed form (or whose conserved quantities
// are) over a grid of step sizes (and, for contact scenes, solver iterations), and writes one
// CSV row per run and engine:
//
//   scene,method,dt,iterations,ms_per_step,error,energy_drift,momentum_drift
//
// method is `REngine`, and `bullet` where Bullet was found at configure time
// (RENGINE_HAVE_BULLET): every scene is then also run on Bullet, in the same process, with
// the same bodies, step and solver iterations (btContactSolverInfo::m_numIterations), built by
// tools/bench/BulletWorld.h as bench_bullet builds its worlds (exact mass properties from
// REngine, static bodies as mass 0, restitution and friction mapped so that Bullet's product
// of the pair's values equals REngine's combined value, sleeping off), stepped with
// stepSimulation(dt, 0) (one internal step of dt per call). Its errors are computed from
// Bullet's state exactly as REngine's are.
//
// ms_per_step is the median over --repeats timed runs (after one untimed run) of the
// steady_clock time around the step loop only, divided by the step count. The errors come
// from the untimed run, which observes every step; both engines are deterministic, so the
// timed runs step exactly the same trajectory without paying for the observation.
// `iterations` is empty for scenes without contacts (the solver never runs), and an error
// column is empty where the quantity is not conserved or not defined for the scene.
//
// Scenes and their `error` (all dimensionless unless a unit is given):
//   tumbling      box, half extents (0.5, 0.3, 0.1), 1 kg, no gravity, spun about its
//                 intermediate axis, w = (0.01, 5, 0.01) rad/s (as in the shared
//                 dzhanibekov.json), 10 s. error = momentum_drift = max over steps of
//                 |L(t) - L(0)| / |L(0)| (world angular momentum); energy_drift = max over
//                 steps of |E(t) - E(0)| / E(0) (kinetic energy).
//   projectile    sphere under g = 9.81 m/s^2, launched at 30 m/s, 40 deg, 3 s, no contacts.
//                 error = |x(T) - (x0 + v0 T + g T^2/2)|, m; energy_drift = max over steps
//                 of |E(t) - E(0)| / E(0), E kinetic plus potential.
//   elastic_pair  two spheres head-on, e = 1, masses 1 and 3.7 kg at 3 and -1 m/s, 2 s.
//                 error = max over bodies and over the steps that end at least one step
//                 after the contact time of |v - v'| / |v'|, v' the closed-form velocity
//                 after the collision; energy_drift = max |dE| / E(0); momentum_drift =
//                 max |dP| / sum(m |v0|).
//   inelastic_pair  the same pair with e = 0.5: v1' = (m1 v1 + m2 v2 - m2 e (v1 - v2)) / M,
//                 v2' = (m1 v1 + m2 v2 + m1 e (v1 - v2)) / M, M = m1 + m2. error as for
//                 elastic_pair; energy_drift = max over the same steps of |E - E'| / E(0), E'
//                 the closed-form kinetic energy after the collision; momentum_drift as for
//                 elastic_pair.
//   sliding_box   unit box (1 kg) on a static floor (top at y = 0), mu = 0.5, v0 = 5 m/s,
//                 3 s. error = |d - v0^2/(2 mu g)| / (v0^2/(2 mu g)), d the distance slid.
//   incline       unit box (1 kg) at rest on a static 20 deg incline, mu = 0.2 on both
//                 bodies (the geometric combine gives 0.2), 2 s: it slides (tan 20 deg >
//                 0.2) 3.0 m of the 10 m left before the incline's end. error =
//                 |d - g (sin t - mu cos t) T^2 / 2| / (g (sin t - mu cos t) T^2 / 2), d the
//                 centre of mass's displacement down the slope.
//   stack10       scenes/box_stack_10.json with the grid's dt and iterations, for
//                 the scene's duration (steps x dt). error = |x_top(T) - x_top(0)|, m: the
//                 top box's drift from its start (it should rest).
//   debris_cloud  scenes/debris_cloud_1000.json (1000 unit boxes, zero g, e = 1, no
//                 friction) with the grid's dt and iterations, for 2 s (1 s in --quick). No
//                 closed form; what the exact motion conserves: error = |E(T) - E(0)| / E(0),
//                 the final relative change of kinetic energy (elastic and frictionless: the
//                 exact answer keeps E(0)); energy_drift = max over steps of
//                 (E(t) - E(0)) / E(0), SIGNED: > 0 is a gain, which must never happen;
//                 <= 0 means the energy never rose above its start; momentum_drift = max over
//                 steps of |P(t) - P(0)| / sum(m |v0|).
//   asteroid_field  150 random convex hulls (12 to 24 points on a rough ellipsoid, semi-axes
//                 0.5 to 1.2 m, 2500 kg/m^3) on a 5 x 5 x 6 grid 4 m apart, random
//                 orientations, velocities up to 1.5 m/s and spins up to 2 rad/s per axis
//                 (std::mt19937_64, fixed seed, our own uniform mapping: the same field on
//                 every platform), zero g, e = 1, no friction, 3 s (1 s in --quick); about a
//                 quarter collide (34 of 150 in REngine's run at 1/30 s, 38 in Bullet's).
//                 error = max over steps of |L(t) - L(0)| / sum(|x x m v| + |L_spin|)(0),
//                 L = sum(x x m v + L_spin) the angular momentum about the origin (conserved:
//                 contact forces are internal and act along one line between the bodies,
//                 friction or not); energy_drift and momentum_drift as for debris_cloud.
//
// Cost: debris_cloud and asteroid_field dominate the run (1000 and 150 bodies); they run the
// same grid as the other contact scenes. The full run takes under 2 minutes on the 2-core
// development machine, Bullet included; --quick under 1 s.
//
// Exit codes: 0 success; 2 bad input (options, a scene file, the CSV path).
//
// Files: scenes.cpp (the scenes above and their closed forms), engines.cpp (REngine and
// Bullet behind one interface), report.cpp (the table and the CSV), shortcuts.cpp
// (--shortcuts), scaling.cpp and scaling_scenes.cpp (--scaling), and this one (the command
// line and the grid).
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#ifdef RENGINE_HAVE_BULLET
#include "BulletWorld.h"
#endif

#include <CLI/CLI.hpp>

#include "engines.h"
#include "report.h"
#include "scaling.h"
#include "scenes.h"
#include "characters.h"
#include "shortcuts.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

using namespace REngine;
using namespace rbench;

namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;

using Clock = std::chrono::steady_clock;

// A bad command line: reported like rengine-sim's, exit code 2.
struct UsageError {
  std::string message;
};

constexpr const char* kErrorHelp = R"(Scenes and their `error` column (see also tools/rengine-bench/main.cpp):
  tumbling      box (0.5, 0.3, 0.1) spun near its intermediate axis, no gravity, 10 s:
                max |L(t) - L0| / |L0| (world angular momentum; also momentum_drift);
                energy_drift = max |E(t) - E0| / E0
  projectile    sphere, g = 9.81, 30 m/s at 40 deg, 3 s: |x(T) - closed form| (m);
                energy_drift = max |dE| / E0 (kinetic + potential)
  elastic_pair  spheres of 1 and 3.7 kg head-on at 3 and -1 m/s, e = 1, 2 s: max |v - v'| / |v'|
                over both bodies from one step after the contact; energy_drift = max |dE| / E0;
                momentum_drift = max |dP| / sum m|v0|
  inelastic_pair  the same with e = 0.5: v1' = (m1 v1 + m2 v2 - m2 e (v1 - v2)) / (m1 + m2),
                v2' = (m1 v1 + m2 v2 + m1 e (v1 - v2)) / (m1 + m2); error as elastic_pair;
                energy_drift = max |E - E'| / E0 from one step after the contact (E' closed
                form); momentum_drift = max |dP| / sum m|v0|
  sliding_box   unit box on a floor, mu = 0.5, v0 = 5 m/s, 3 s:
                |d - v0^2/(2 mu g)| / (v0^2/(2 mu g)), d the distance slid
  incline       unit box from rest on a static 20 deg incline, mu = 0.2, 2 s:
                |d - g (sin t - mu cos t) T^2/2| / (g (sin t - mu cos t) T^2/2), d slid
  stack10       box_stack_10.json for its duration: top box drift |x(T) - x(0)| (m)
  debris_cloud  debris_cloud_1000.json (zero g, e = 1, no friction), 2 s (1 s with --quick):
                |E(T) - E0| / E0 (kinetic; exact motion keeps E0); energy_drift = max over
                steps of (E(t) - E0) / E0, SIGNED (> 0: a gain); momentum_drift = max |dP| /
                sum m|v0|
  asteroid_field  150 random convex hulls (fixed seed), zero g, e = 1, no friction, 3 s (1 s
                with --quick): max |L(t) - L0| / sum(|x x m v| + |L_spin|)(0), L the angular
                momentum about the origin; energy_drift and momentum_drift as debris_cloud
Grid: dt in {1/30, 1/60, 1/120, 1/240, 1/480}; iterations in {4, 10, 20} for the contact
scenes (empty for the others). --quick: dt in {1/30, 1/120} (debris_cloud and
asteroid_field: 1/30 only), 10 iterations, 1 timed run. ms_per_step: median of the timed
repeats after one untimed run, which measures the errors. Empty error fields: not
applicable. Methods: REngine, and bullet when built with Bullet (same bodies, step and
iterations; see tools/bench/BulletWorld.h).)";


// One timed run: milliseconds per step of the step loop alone (building the world is not
// timed).
double TimeOneRun(const Scene& scene, Method method, const GridPoint& point) {
  const std::unique_ptr<Engine> engine = MakeEngine(method, scene.world(point));
  const Clock::time_point t0 = Clock::now();
  engine->Step(engine->Steps());
  const Clock::time_point t1 = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  return ms / static_cast<double>(engine->Steps());
}

// Options are read as text and converted here: CLI11's integer parsing (strtoull, base 0)
// takes "-1" as 2^64 - 1 and "010" as 8 (the same reason as in rengine-sim).
int ParseRepeats(const std::string& text) {
  int n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || end != text.data() + text.size() || n < 1) {
    throw UsageError{"--repeats: must be an integer >= 1 (got \"" + text + "\")"};
  }
  return n;
}

// --steps for --scaling: a whole number >= 1.
std::uint64_t ParseSteps(const std::string& text) {
  std::uint64_t n = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
  if (ec != std::errc() || end != text.data() + text.size() || n < 1) {
    throw UsageError{"--steps: must be an integer >= 1 (got \"" + text + "\")"};
  }
  return n;
}

ScalingOptions::BroadPhase ParseBroadPhase(const std::string& text) {
  if (text == "on") return ScalingOptions::BroadPhase::kOn;
  if (text == "off") return ScalingOptions::BroadPhase::kOff;
  if (text == "both") return ScalingOptions::BroadPhase::kBoth;
  throw UsageError{"--broadphase: must be on, off or both (got \"" + text + "\")"};
}

std::vector<std::string> SplitList(const std::string& list) {
  std::vector<std::string> items;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) items.push_back(item);
  return items;
}

// --threads and --model-threads: comma-separated counts from `least` to 1024.
std::vector<int> ParseThreadCounts(const char* option, const std::string& text, long least) {
  std::vector<int> counts;
  for (const std::string& t : SplitList(text)) {
    char* end = nullptr;
    const long value = std::strtol(t.c_str(), &end, 10);
    if (t.empty() || *end != '\0' || value < least || value > 1024) {
      throw UsageError{std::string(option) + ": a comma-separated list of counts " + std::to_string(least) +
                       " to 1024 (got \"" + text + "\")"};
    }
    counts.push_back(static_cast<int>(value));
  }
  return counts;
}

// The CSV's directory is created and the file opened before any run, so a bad path fails in
// a second rather than after minutes.
bool ProbeCsv(const std::string& csvPath) {
  const std::filesystem::path parent = std::filesystem::path(csvPath).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (std::FILE* probe = std::fopen(csvPath.c_str(), "ab")) {
    std::fclose(probe);
    return true;
  }
  std::fprintf(stderr, "error: %s: cannot open for writing: %s\n", csvPath.c_str(),
               std::strerror(errno));
  return false;
}

std::string KnownScenes() {
  std::string known;
  for (const Scene& s : AllScenes()) known += std::string(known.empty() ? "" : ", ") + s.name;
  return known;
}

std::vector<const Scene*> ParseScenes(const std::string& list) {
  std::vector<const Scene*> chosen;
  if (list.empty()) {
    for (const Scene& s : AllScenes()) chosen.push_back(&s);
    return chosen;
  }
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    const Scene* found = nullptr;
    for (const Scene& s : AllScenes()) {
      if (name == s.name) found = &s;
    }
    if (!found) {
      throw UsageError{"--scenes: unknown scene \"" + name + "\" (known: " + KnownScenes() + ")"};
    }
    // Table order, not command-line order, and once each: the CSV is the same either way.
    if (std::find(chosen.begin(), chosen.end(), found) == chosen.end()) chosen.push_back(found);
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

#ifdef RENGINE_HAVE_BULLET
// Bullet multiplies a pair's coefficients; the mapping in BulletWorld.h matches REngine's
// combine for every scene here. Said once per scene if it ever does not.
void WarnCombineMismatch(const Scene& scene, const GridPoint& point) {
  const World w = scene.world(point);
  const bench::BulletCoefficients c = bench::ChooseCoefficients(w.settings, w.bodies, true);
  if (c.restitutionError > 1e-12) {
    std::printf("note: %s: Bullet's restitution differs from REngine's by up to %.3g (%s)\n",
                scene.name, c.restitutionError, c.restitutionExample.c_str());
  }
  if (c.frictionError > 1e-12) {
    std::printf("note: %s: Bullet's friction differs from REngine's by up to %.3g (%s)\n",
                scene.name, c.frictionError, c.frictionExample.c_str());
  }
}
#endif

int Run(int argc, char** argv) {
  CLI::App app{"Work-precision benchmark: ms/step against the error from a closed-form answer "
               "(or a conserved quantity), over a grid of step sizes and solver iterations; "
               "REngine, and Bullet where it was found at build time.",
               "rengine-bench"};
  std::string scenesText, csvPath = "build/bench/bench.csv", repeatsText = "5";
  std::string stepsText, broadPhaseText = "on", sceneDir = RENGINE_SCALING_SCENES;
  bool quick = false, shortcuts = false, scaling = false, generateScenes = false, characters = false;
  app.add_option("--scenes", scenesText,
                 "Comma-separated scenes (default all): " + KnownScenes() +
                     "; with --scaling: " + ScalingSceneNames());
  app.add_option("--csv", csvPath, "CSV output, one row per run")->capture_default_str();
  app.add_option("--repeats", repeatsText, "Timed runs per grid point (median reported)")
      ->capture_default_str();
  app.add_flag("--quick", quick,
               "Smoke test: dt in {1/30, 1/120} (debris_cloud, asteroid_field: 1/30, 1 s), "
               "10 iterations, 1 timed run");
  CLI::Option* shortcutsFlag = app.add_flag(
      "--shortcuts", shortcuts,
      "Instead of the grid: each shortcut's scene with and without it (time per step "
      "and error; CSV default build/bench/shortcuts.csv)");
  CLI::Option* scalingFlag = app.add_flag(
      "--scaling", scaling,
      "Instead of the grid: ms/step against body count on the scaling scenes, REngine, Bullet "
      "and Jolt interleaved, Bullet and Jolt where built with them (CSV default "
      "build/bench/scaling.csv, repeats default 3; --quick: the 1000-body scenes, 10 steps)");
  scalingFlag->excludes(shortcutsFlag);
  app.add_option("--steps", stepsText, "--scaling: steps per run (default each scene's own, 300)")
      ->needs(scalingFlag);
  std::string threadsText = "1";
  app.add_option("--threads", threadsText,
                 "--scaling: REngine's and Jolt's thread counts, comma-separated (default 1; 0: "
                 "what the machine has)");
  app.add_option("--broadphase", broadPhaseText,
                 "--scaling: REngine's broad phase on, off (the all-pairs reference loop) or both")
      ->needs(scalingFlag)
      ->capture_default_str();
  app.add_option("--scene-dir", sceneDir,
                 "--scaling: the scene files, generated there by "
                 "tools/make_scaling_scenes.py when missing")
      ->needs(scalingFlag)
      ->capture_default_str();
  std::string modelThreadsText, modelCsvPath = "build/bench/thread_model.csv";
  app.add_option("--model-threads", modelThreadsText,
                 "--scaling: also model REngine's step on these thread counts (comma-separated, 1 to "
                 "1024) from one thread's task times: tools/rengine-bench/thread_model.h")
      ->needs(scalingFlag);
  app.add_option("--model-csv", modelCsvPath, "--scaling --model-threads: its CSV")
      ->needs(scalingFlag)
      ->capture_default_str();
  app.add_flag("--characters", characters,
               "The character controller: microseconds per character update and its error "
               "against closed forms (tiles, a turning deck, stairs, crates)");
  app.add_flag("--generate-scenes", generateScenes,
               "--scaling: make the missing scene files, then exit")
      ->needs(scalingFlag);
  app.footer(kErrorHelp);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints the help or the error
    return code == 0 ? kExitOk : kExitBadInput;
  }

  if (characters) {
    int repeats = 5;
    try {
      if (app.count("--repeats")) repeats = ParseRepeats(repeatsText);
    } catch (const UsageError& e) {
      std::fprintf(stderr, "error: %s\n", e.message.c_str());
      return kExitBadInput;
    }
    const std::string path = app.count("--csv") ? csvPath : "build/bench/characters.csv";
    if (!ProbeCsv(path)) return kExitBadInput;
    const std::vector<rbench::CharacterRow> rows = rbench::RunCharacters(quick, quick ? 1 : repeats);
    rbench::PrintCharacterTable(rows);
    if (!rbench::WriteCharacterCsv(path, rows)) {
      std::fprintf(stderr, "error: %s: write failed: %s\n", path.c_str(), std::strerror(errno));
      return kExitBadInput;
    }
    return kExitOk;
  }
  if (scaling) {
    ScalingOptions opt;
    try {
      if (!scenesText.empty()) opt.scenes = SplitList(scenesText);
      if (app.count("--repeats")) opt.repeats = ParseRepeats(repeatsText);
      if (!stepsText.empty()) opt.steps = ParseSteps(stepsText);
      opt.broadPhase = ParseBroadPhase(broadPhaseText);
      opt.threads = ParseThreadCounts("--threads", threadsText, 0);
      if (!modelThreadsText.empty()) opt.modelThreads = ParseThreadCounts("--model-threads", modelThreadsText, 1);
    } catch (const UsageError& e) {
      std::fprintf(stderr, "error: %s\n", e.message.c_str());
      return kExitBadInput;
    }
    opt.sceneDir = sceneDir;
    opt.csvPath = app.count("--csv") ? csvPath : "build/bench/scaling.csv";
    opt.quick = quick;
    opt.generateOnly = generateScenes;
    opt.modelCsvPath = modelCsvPath;
    if (!opt.generateOnly && !ProbeCsv(opt.csvPath)) return kExitBadInput;
    if (!opt.generateOnly && !opt.modelThreads.empty() && !ProbeCsv(opt.modelCsvPath)) return kExitBadInput;
    return RunScaling(opt);
  }
  if (shortcuts && app.count("--csv") == 0) csvPath = "build/bench/shortcuts.csv";
  std::vector<const Scene*> scenes;
  int repeats = 0;
  try {
    scenes = ParseScenes(scenesText);
    repeats = quick ? 1 : ParseRepeats(repeatsText);
    // Loaded before any run: a missing scene file is an input error, reported at once.
    for (const Scene* s : scenes) LoadSceneFiles(*s);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "error: %s\n", e.message.c_str());
    return kExitBadInput;
  } catch (const RSceneError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  if (!ProbeCsv(csvPath)) return kExitBadInput;

  if (shortcuts) {
    std::vector<rbench::ShortcutRow> rows;
    try {
      rows = rbench::RunShortcuts(quick, repeats);
    } catch (const RSceneError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return kExitBadInput;
    }
    rbench::PrintShortcutTable(rows);
    if (!rbench::WriteShortcutCsv(csvPath, rows)) {
      std::fprintf(stderr, "error: %s: write failed: %s\n", csvPath.c_str(), std::strerror(errno));
      return kExitBadInput;
    }
    std::printf("wrote %s (%zu rows, %d timed run%s per point)\n", csvPath.c_str(), rows.size(),
                repeats, repeats == 1 ? "" : "s");
    return kExitOk;
  }

  std::vector<Method> methods{Method::kREngine};
#ifdef RENGINE_HAVE_BULLET
  methods.push_back(Method::kBullet);
  std::printf("methods: REngine (double), bullet: Bullet %d.%02d (%s precision), "
              "stepSimulation(dt, 0), sleeping off\n",
              btGetVersion() / 100, btGetVersion() % 100,
              sizeof(btScalar) == 8 ? "double" : "single");
#else
  std::printf("methods: REngine (built without Bullet: no bullet series)\n");
#endif

  const std::vector<int> rates = quick ? std::vector<int>{30, 120}
                                       : std::vector<int>{30, 60, 120, 240, 480};
  const std::vector<int> iterationGrid = quick ? std::vector<int>{10} : std::vector<int>{4, 10, 20};
  const int kDefaultIterations = RWorldSettings{}.solverIterations;

  PrintTableHeader();
  std::vector<Row> rows;
  for (const Scene* scene : scenes) {
    const std::vector<int> iterations =
        scene->contacts ? iterationGrid : std::vector<int>{kDefaultIterations};
    const std::vector<int> sceneRates =
        quick && scene->expensive ? std::vector<int>{rates.front()} : rates;
#ifdef RENGINE_HAVE_BULLET
    WarnCombineMismatch(*scene, {RScalar(1) / sceneRates.front(), iterations.front(), quick});
#endif
    for (int it : iterations) {
      for (int rate : sceneRates) {
        const GridPoint point{RScalar(1) / rate, it, quick};
        for (Method method : methods) {
          // The untimed observed run doubles as the warm-up (caches, page faults, clocks).
          const std::unique_ptr<Engine> observed = MakeEngine(method, scene->world(point));
          Row row{scene->name, method, point.dt, std::nullopt, 0, scene->errors(*observed)};
          if (scene->contacts) row.iterations = it;
          std::vector<double> times;
          for (int r = 0; r < repeats; ++r) times.push_back(TimeOneRun(*scene, method, point));
          row.msPerStep = Median(times);
          PrintRow(row);
          rows.push_back(row);
        }
      }
    }
  }

  if (!WriteCsv(csvPath, rows)) {
    std::fprintf(stderr, "error: %s: write failed: %s\n", csvPath.c_str(), std::strerror(errno));
    return kExitBadInput;
  }
  std::printf("wrote %s (%zu rows, %d timed run%s per point)\n", csvPath.c_str(), rows.size(),
              repeats, repeats == 1 ? "" : "s");
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) { return Run(argc, argv); }
