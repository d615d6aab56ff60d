// rengine-bench: work-precision benchmark (issue #6, "benchmark run time against error").
//
//   rengine-bench [--scenes a,b,...] [--csv FILE] [--repeats N] [--quick]
//
// Runs reference scenes whose answer is known in closed form over a grid of step sizes
// (and, for contact scenes, solver iterations), and writes one CSV row per run:
//
//   scene,method,dt,iterations,ms_per_step,error,energy_drift,momentum_drift
//
// ms_per_step is the median over --repeats timed runs (after one untimed run) of the
// steady_clock time around the step loop only, divided by the step count. The errors come
// from the untimed run, which observes every step; the engine is deterministic, so the
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
//   sliding_box   unit box (1 kg) on a static floor (top at y = 0), mu = 0.5, v0 = 5 m/s,
//                 3 s. error = |d - v0^2/(2 mu g)| / (v0^2/(2 mu g)), d the distance slid.
//   stack10       ../shared/scenes/box_stack_10.json with the grid's dt and iterations, for
//                 the scene's duration (steps x dt). error = |x_top(T) - x_top(0)|, m: the
//                 top box's drift from its start (it should rest).
//
// Exit codes: 0 success; 2 bad input (options, the stack scene file, the CSV path).
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

using namespace REngine;

namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;
constexpr RScalar kG = RScalar(9.81);  // m/s^2

using Clock = std::chrono::steady_clock;

// A bad command line: reported like rengine-sim's, exit code 2.
struct UsageError {
  std::string message;
};

// A world ready to step: what a scene builds for one grid point.
struct World {
  RWorldSettings settings;
  std::vector<RRigidBody> bodies;
  RScalar dt = 0;           // s
  std::uint64_t steps = 0;
};

// A run's errors against the closed form; unset: not applicable to the scene (empty field).
struct Errors {
  std::optional<double> error, energyDrift, momentumDrift;
};

// Whole steps covering `duration` seconds: every duration and step size in the grid divide
// exactly, so this is the exact count, not a rounding of it.
std::uint64_t StepsFor(RScalar duration, RScalar dt) {
  return static_cast<std::uint64_t>(std::llround(duration / dt));
}

// Steps a world, calling afterStep(bodies, t) with the time at the end of each step. Time is
// a product, not a running sum, so the contact-time tests below carry no accumulated rounding.
template <class AfterStep>
void Simulate(World& world, AfterStep&& afterStep) {
  RIntegrator integrator(world.settings);
  for (std::uint64_t step = 1; step <= world.steps; ++step) {
    integrator.Update(world.bodies, world.dt);
    afterStep(world.bodies, static_cast<RScalar>(step) * world.dt);
  }
}

RBodyDef Sphere(const std::string& name, RScalar radius, RScalar mass) {
  RBodyDef def;
  def.name = name;
  def.shape.type = RShapeType::kSphere;
  def.shape.radius = radius;
  def.mass = mass;
  return def;
}

RBodyDef Box(const std::string& name, const RVec3& halfExtents, std::optional<RScalar> mass) {
  RBodyDef def;
  def.name = name;
  def.shape.type = RShapeType::kBox;
  def.shape.halfExtents = halfExtents;
  def.isStatic = !mass;
  def.mass = mass;
  return def;
}

// ---- tumbling ---------------------------------------------------------------------------
// Torque-free, so energy and world angular momentum are conserved exactly; near the
// intermediate axis the motion is unstable (Dzhanibekov flips), which is what makes a
// stepper that approximates the rotation drift.

World TumblingWorld(RScalar dt, int /*iterations*/) {
  World w;
  RBodyDef box = Box("box", RVec3(0.5, 0.3, 0.1), RScalar(1));
  box.angularVelocity_W = RVec3(0.01, 5.0, 0.01);
  w.bodies.emplace_back(box);
  w.dt = dt;
  w.steps = StepsFor(10, dt);
  return w;
}

Errors TumblingErrors(RScalar dt, int iterations) {
  World w = TumblingWorld(dt, iterations);
  const RRigidBody& b0 = w.bodies[0];
  const RScalar e0 = b0.RotationalKineticEnergy() + b0.LinearKineticEnergy();
  const RVec3 l0 = b0.AngularMomentum_W();
  double dE = 0, dL = 0;
  Simulate(w, [&](const std::vector<RRigidBody>& bodies, RScalar) {
    const RRigidBody& b = bodies[0];
    const RScalar e = b.RotationalKineticEnergy() + b.LinearKineticEnergy();
    dE = std::max(dE, double(std::abs(e - e0) / e0));
    dL = std::max(dL, double((b.AngularMomentum_W() - l0).norm() / l0.norm()));
  });
  return {dL, dE, dL};
}

// ---- projectile -------------------------------------------------------------------------

const RVec3 kGravity_W(0, -kG, 0);

RVec3 LaunchVelocity_W() {
  const RScalar angle = 40 * kPi / 180;
  return 30 * RVec3(std::cos(angle), std::sin(angle), 0);
}

World ProjectileWorld(RScalar dt, int /*iterations*/) {
  World w;
  w.settings.gravity_W = kGravity_W;
  RBodyDef ball = Sphere("ball", 0.1, 1);
  ball.velocity_W = LaunchVelocity_W();
  w.bodies.emplace_back(ball);
  w.dt = dt;
  w.steps = StepsFor(3, dt);
  return w;
}

Errors ProjectileErrors(RScalar dt, int iterations) {
  World w = ProjectileWorld(dt, iterations);
  const RVec3 x0 = w.bodies[0].Position_W();
  const RVec3 v0 = w.bodies[0].Velocity_W();
  // Energy with the potential of uniform gravity, m (-g . x).
  const auto energy = [](const RRigidBody& b) {
    return b.LinearKineticEnergy() + b.RotationalKineticEnergy() -
           b.Mass() * kGravity_W.dot(b.Position_W());
  };
  const RScalar e0 = energy(w.bodies[0]);
  double dE = 0;
  RScalar tEnd = 0;
  Simulate(w, [&](const std::vector<RRigidBody>& bodies, RScalar t) {
    dE = std::max(dE, double(std::abs(energy(bodies[0]) - e0) / e0));
    tEnd = t;
  });
  const RVec3 exact = x0 + v0 * tEnd + RScalar(0.5) * kGravity_W * tEnd * tEnd;
  return {double((w.bodies[0].Position_W() - exact).norm()), dE, std::nullopt};
}

// ---- elastic_pair -----------------------------------------------------------------------
// Radii 0.5 m, centres 4 m apart: they close at 4 m/s over a 3 m gap and touch at 0.75 s.

// Masses whose outcome is not exact in binary (1 and 3 kg give -3 and 1 m/s exactly, and
// every setting would show an error of 0).
constexpr RScalar kPairM1 = 1, kPairM2 = 3.7, kPairV1 = 3, kPairV2 = -1;
constexpr RScalar kPairContactTime = 0.75;  // s

World ElasticPairWorld(RScalar dt, int iterations) {
  World w;
  w.settings.solverIterations = iterations;
  RBodyDef a = Sphere("a", 0.5, kPairM1), b = Sphere("b", 0.5, kPairM2);
  a.position_W = RVec3(-2, 0, 0);
  b.position_W = RVec3(2, 0, 0);
  a.velocity_W = RVec3(kPairV1, 0, 0);
  b.velocity_W = RVec3(kPairV2, 0, 0);
  for (RBodyDef* def : {&a, &b}) {
    def->restitution = 1;
    def->friction = 0;
    w.bodies.emplace_back(*def);
  }
  w.dt = dt;
  w.steps = StepsFor(2, dt);
  return w;
}

Errors ElasticPairErrors(RScalar dt, int iterations) {
  World w = ElasticPairWorld(dt, iterations);
  // 1D elastic collision: v1' = ((m1 - m2) v1 + 2 m2 v2) / (m1 + m2), and symmetrically.
  const RScalar m = kPairM1 + kPairM2;
  const RVec3 after[2] = {
      RVec3(((kPairM1 - kPairM2) * kPairV1 + 2 * kPairM2 * kPairV2) / m, 0, 0),
      RVec3(((kPairM2 - kPairM1) * kPairV2 + 2 * kPairM1 * kPairV1) / m, 0, 0)};
  const auto energy = [](const std::vector<RRigidBody>& bodies) {
    RScalar e = 0;
    for (const RRigidBody& b : bodies) e += b.LinearKineticEnergy() + b.RotationalKineticEnergy();
    return e;
  };
  const auto momentum = [](const std::vector<RRigidBody>& bodies) {
    RVec3 p = RVec3::Zero();
    for (const RRigidBody& b : bodies) p += b.Mass() * b.Velocity_W();
    return p;
  };
  const RScalar e0 = energy(w.bodies);
  const RVec3 p0 = momentum(w.bodies);
  // Drift relative to the momentum the bodies carry (the total is small: 3 - 3.7 kg m/s).
  const RScalar pScale = kPairM1 * std::abs(kPairV1) + kPairM2 * std::abs(kPairV2);
  double dV = 0, dE = 0, dP = 0;
  Simulate(w, [&](const std::vector<RRigidBody>& bodies, RScalar t) {
    dE = std::max(dE, double(std::abs(energy(bodies) - e0) / e0));
    dP = std::max(dP, double((momentum(bodies) - p0).norm() / pScale));
    // A step ending exactly at the contact time may report either side of it; a full step
    // later the collision must have happened whatever the step size.
    if (t < kPairContactTime + dt) return;
    for (int i = 0; i < 2; ++i) {
      dV = std::max(dV, double((bodies[i].Velocity_W() - after[i]).norm() / after[i].norm()));
    }
  });
  return {dV, dE, dP};
}

// ---- sliding_box ------------------------------------------------------------------------

constexpr RScalar kSlideMu = 0.5, kSlideV0 = 5;  // -, m/s

World SlidingBoxWorld(RScalar dt, int iterations) {
  World w;
  w.settings.gravity_W = kGravity_W;
  w.settings.solverIterations = iterations;
  RBodyDef floor = Box("floor", RVec3(50, 0.5, 50), std::nullopt);
  floor.position_W = RVec3(0, -0.5, 0);
  RBodyDef box = Box("box", RVec3(0.5, 0.5, 0.5), RScalar(1));
  box.position_W = RVec3(0, 0.5, 0);
  box.velocity_W = RVec3(kSlideV0, 0, 0);
  // The default combine (geometric mean) of two equal coefficients is that coefficient.
  for (RBodyDef* def : {&floor, &box}) {
    def->friction = kSlideMu;
    def->restitution = 0;
    w.bodies.emplace_back(*def);
  }
  w.dt = dt;
  w.steps = StepsFor(3, dt);  // it stops after v0 / (mu g) = 1.02 s
  return w;
}

Errors SlidingBoxErrors(RScalar dt, int iterations) {
  World w = SlidingBoxWorld(dt, iterations);
  const RScalar x0 = w.bodies[1].Position_W().x();
  Simulate(w, [](const std::vector<RRigidBody>&, RScalar) {});
  const RScalar exact = kSlideV0 * kSlideV0 / (2 * kSlideMu * kG);
  const RScalar slid = w.bodies[1].Position_W().x() - x0;
  return {double(std::abs(slid - exact) / exact), std::nullopt, std::nullopt};
}

// ---- stack10 ----------------------------------------------------------------------------

const RScene& StackScene() {
  static const RScene scene = LoadScene(RENGINE_SHARED_SCENES "/box_stack_10.json");
  return scene;
}

World StackWorld(RScalar dt, int iterations) {
  const RScene& scene = StackScene();
  World w;
  w.settings = scene.settings;
  w.settings.solverIterations = iterations;
  w.bodies = CreateBodies(scene);
  w.dt = dt;
  w.steps = StepsFor(static_cast<RScalar>(scene.steps) * scene.dt, dt);
  return w;
}

Errors StackErrors(RScalar dt, int iterations) {
  World w = StackWorld(dt, iterations);
  // The top box: the dynamic body that starts highest.
  std::size_t top = 0;
  for (std::size_t i = 0; i < w.bodies.size(); ++i) {
    if (w.bodies[i].IsStatic()) continue;
    if (w.bodies[top].IsStatic() ||
        w.bodies[i].Position_W().y() > w.bodies[top].Position_W().y()) {
      top = i;
    }
  }
  const RVec3 start = w.bodies[top].Position_W();
  Simulate(w, [](const std::vector<RRigidBody>&, RScalar) {});
  return {double((w.bodies[top].Position_W() - start).norm()), std::nullopt, std::nullopt};
}

// ---- the scene table --------------------------------------------------------------------

struct Scene {
  const char* name;
  bool contacts;  // the solver runs: iterations is a grid axis
  World (*world)(RScalar dt, int iterations);
  Errors (*errors)(RScalar dt, int iterations);  // an observed run of the same world
};

const Scene kScenes[] = {
    {"tumbling", false, TumblingWorld, TumblingErrors},
    {"projectile", false, ProjectileWorld, ProjectileErrors},
    {"elastic_pair", true, ElasticPairWorld, ElasticPairErrors},
    {"sliding_box", true, SlidingBoxWorld, SlidingBoxErrors},
    {"stack10", true, StackWorld, StackErrors},
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
  sliding_box   unit box on a floor, mu = 0.5, v0 = 5 m/s, 3 s:
                |d - v0^2/(2 mu g)| / (v0^2/(2 mu g)), d the distance slid
  stack10       box_stack_10.json for its duration: top box drift |x(T) - x(0)| (m)
Grid: dt in {1/30, 1/60, 1/120, 1/240, 1/480}; iterations in {4, 10, 20} for the contact
scenes (empty for the others). ms_per_step: median of the timed repeats after one untimed
run, which measures the errors. Empty error fields: not applicable.)";

// ---- running and reporting --------------------------------------------------------------

struct Row {
  const char* scene;
  RScalar dt;
  std::optional<int> iterations;
  double msPerStep;
  Errors errors;
};

// One timed run: milliseconds per step of the step loop alone (building the world is not
// timed).
double TimeOneRun(const Scene& scene, RScalar dt, int iterations) {
  World w = scene.world(dt, iterations);
  RIntegrator integrator(w.settings);
  const Clock::time_point t0 = Clock::now();
  for (std::uint64_t step = 0; step < w.steps; ++step) integrator.Update(w.bodies, w.dt);
  const Clock::time_point t1 = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  return ms / static_cast<double>(w.steps);
}

double Median(std::vector<double> xs) {
  std::sort(xs.begin(), xs.end());
  const std::size_t n = xs.size();
  return n % 2 ? xs[n / 2] : 0.5 * (xs[n / 2 - 1] + xs[n / 2]);
}

std::string Number(const std::optional<double>& x, const char* format) {
  if (!x) return "";
  char text[32];
  std::snprintf(text, sizeof text, format, *x);
  return text;
}

std::string DtLabel(RScalar dt) {
  return "1/" + std::to_string(std::llround(1 / dt));
}

void PrintTable(const std::vector<Row>& rows) {
  std::printf("%-13s %-8s %-6s %5s %11s %11s %13s %15s\n", "scene", "method", "dt", "iter",
              "ms/step", "error", "energy_drift", "momentum_drift");
  for (const Row& r : rows) {
    std::printf("%-13s %-8s %-6s %5s %11.4g %11s %13s %15s\n", r.scene, "REngine",
                DtLabel(r.dt).c_str(),
                r.iterations ? std::to_string(*r.iterations).c_str() : "-", r.msPerStep,
                Number(r.errors.error, "%.3e").c_str(),
                Number(r.errors.energyDrift, "%.3e").c_str(),
                Number(r.errors.momentumDrift, "%.3e").c_str());
  }
}

bool WriteCsv(const std::string& path, const std::vector<Row>& rows) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) return false;
  std::fprintf(file,
               "scene,method,dt,iterations,ms_per_step,error,energy_drift,momentum_drift\n");
  for (const Row& r : rows) {
    std::fprintf(file, "%s,REngine,%.17g,%s,%.6g,%s,%s,%s\n", r.scene, r.dt,
                 r.iterations ? std::to_string(*r.iterations).c_str() : "", r.msPerStep,
                 Number(r.errors.error, "%.6e").c_str(),
                 Number(r.errors.energyDrift, "%.6e").c_str(),
                 Number(r.errors.momentumDrift, "%.6e").c_str());
  }
  const bool ok = !std::ferror(file);
  return std::fclose(file) == 0 && ok;
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

std::vector<const Scene*> ParseScenes(const std::string& list) {
  std::vector<const Scene*> chosen;
  if (list.empty()) {
    for (const Scene& s : kScenes) chosen.push_back(&s);
    return chosen;
  }
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    const Scene* found = nullptr;
    for (const Scene& s : kScenes) {
      if (name == s.name) found = &s;
    }
    if (!found) {
      std::string known;
      for (const Scene& s : kScenes) known += std::string(known.empty() ? "" : ", ") + s.name;
      throw UsageError{"--scenes: unknown scene \"" + name + "\" (known: " + known + ")"};
    }
    // Table order, not command-line order, and once each: the CSV is the same either way.
    if (std::find(chosen.begin(), chosen.end(), found) == chosen.end()) chosen.push_back(found);
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

int Run(int argc, char** argv) {
  CLI::App app{"Work-precision benchmark: REngine's ms/step against the error from a "
               "closed-form answer, over a grid of step sizes and solver iterations.",
               "rengine-bench"};
  std::string scenesText, csvPath = "build/bench/bench.csv", repeatsText = "5";
  bool quick = false;
  app.add_option("--scenes", scenesText,
                 "Comma-separated scenes (default all): tumbling, projectile, elastic_pair, "
                 "sliding_box, stack10");
  app.add_option("--csv", csvPath, "CSV output, one row per run")->capture_default_str();
  app.add_option("--repeats", repeatsText, "Timed runs per grid point (median reported)")
      ->capture_default_str();
  app.add_flag("--quick", quick,
               "Smoke test: dt in {1/30, 1/120}, 10 iterations, 1 timed run");
  app.footer(kErrorHelp);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints the help or the error
    return code == 0 ? kExitOk : kExitBadInput;
  }

  std::vector<const Scene*> scenes;
  int repeats = 0;
  try {
    scenes = ParseScenes(scenesText);
    repeats = quick ? 1 : ParseRepeats(repeatsText);
    // Loaded before any run: a missing scene file is an input error, reported at once.
    for (const Scene* s : scenes) {
      if (s->world == StackWorld) StackScene();
    }
  } catch (const UsageError& e) {
    std::fprintf(stderr, "error: %s\n", e.message.c_str());
    return kExitBadInput;
  } catch (const RSceneError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitBadInput;
  }
  // Created before the runs, so a bad path fails in a second rather than after minutes.
  const std::filesystem::path parent = std::filesystem::path(csvPath).parent_path();
  std::error_code ec;
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  if (std::FILE* probe = std::fopen(csvPath.c_str(), "ab")) {
    std::fclose(probe);
  } else {
    std::fprintf(stderr, "error: %s: cannot open for writing: %s\n", csvPath.c_str(),
                 std::strerror(errno));
    return kExitBadInput;
  }

  const std::vector<int> rates = quick ? std::vector<int>{30, 120}
                                       : std::vector<int>{30, 60, 120, 240, 480};
  const std::vector<int> iterationGrid = quick ? std::vector<int>{10} : std::vector<int>{4, 10, 20};
  const int kDefaultIterations = RWorldSettings{}.solverIterations;

  std::vector<Row> rows;
  for (const Scene* scene : scenes) {
    const std::vector<int> iterations =
        scene->contacts ? iterationGrid : std::vector<int>{kDefaultIterations};
    for (int it : iterations) {
      for (int rate : rates) {
        const RScalar dt = RScalar(1) / rate;
        // The untimed observed run doubles as the warm-up (caches, page faults, clocks).
        Row row{scene->name, dt, std::nullopt, 0, scene->errors(dt, it)};
        if (scene->contacts) row.iterations = it;
        std::vector<double> times;
        for (int r = 0; r < repeats; ++r) times.push_back(TimeOneRun(*scene, dt, it));
        row.msPerStep = Median(times);
        rows.push_back(row);
      }
    }
  }

  PrintTable(rows);
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
