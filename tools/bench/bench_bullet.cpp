// bench_bullet: REngine against Bullet Physics on the same scene files, in the same process.
//
//   bench_bullet [SCENE.json ...] [--steps N] [--runs N] [--match-combine] [--sleep]
//
// Default scenes: box_pile_1000.json and debris_cloud_1000.json from the reference scenes
// directory (scenes/). Each scene is loaded once with REngine's loader; every run builds
// both worlds afresh from those definitions, then steps REngine, then Bullet, and times the
// step loop alone (std::chrono::steady_clock, setup excluded). The pair is repeated --runs
// times (default 3) and the medians are compared: ratio = Bullet / REngine, > 1 means
// REngine is faster. The physics figures come from the first run (both engines are
// deterministic).
//
// The Bullet world is what a Bullet user would build for the scene (tools/bench/BulletWorld.h,
// shared with rengine-bench): btDbvtBroadphase, btSequentialImpulseConstraintSolver with the
// scene's solver iterations, the scene's gravity, one internal step of dt per step
// (stepSimulation(dt, 0)), no motion states. Each body gets REngine's mass and principal
// moments (exact for every shape; Bullet's own hull inertia is a bounding-box estimate) and
// its pose in REngine's body frame (centre of mass, principal axes), which is what Bullet's
// rigid-body frame is.
//
// What still differs, and is printed:
//  * Combine modes: Bullet multiplies the two bodies' restitutions and frictions; a scene
//    asks for min restitution and geometric friction by default. --match-combine gives
//    Bullet per-body values whose products are the scene's combined values when one map
//    does it for every pair (sqrt(mu) for geometric friction; the values themselves for a
//    product, or for min over values in {0, 1}).
//  * Sleeping: off in both engines by default (every body simulated every step: the
//    solvers compared); --sleep turns on both, each with its own defaults (REngine:
//    RWorldSettings::RShortcuts::sleeping; Bullet: deactivation).
//  * Bullet's collision margin (0.04 m, inside a box, outside a hull) and its restitution
//    threshold (0.2 m/s; REngine's is 0.5 m/s).
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#include "BulletWorld.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

using namespace REngine;
using namespace REngine::bench;

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  std::vector<std::string> scenes;
  std::uint64_t steps = 0;  // 0: the scene's
  int runs = 3;
  bool matchCombine = false;
  bool sleep = false;  // both engines' sleeping
};

// What the engines are compared on, computed the same way for both from the bodies' state
// (centre-of-mass velocity and angular velocity, world) and the definitions' mass properties.
struct Totals {
  RScalar kinetic = 0;                 // J, translational + rotational
  RVec3 momentum = RVec3::Zero();      // kg m/s
  RScalar momentumScale = 0;           // sum of m |v|, kg m/s: what a drift is relative to
  RScalar meanHeight = 0;              // shape-frame origin along -gravity (y in zero g), m
  RScalar minHeight = 0;
  bool finite = true;
};

struct Accumulator {
  Totals t;
  std::size_t count = 0;
  RVec3 up = RVec3::UnitY();
  void Add(RScalar mass, const RVec3& inertia_B, const RQuat& q_WB, const RVec3& v_W,
           const RVec3& w_W, const RVec3& shapeOrigin_W) {
    const RVec3 w_B = q_WB.conjugate() * w_W;
    t.kinetic += RScalar(0.5) * mass * v_W.squaredNorm() +
                 RScalar(0.5) * w_B.dot(inertia_B.cwiseProduct(w_B));
    t.momentum += mass * v_W;
    t.momentumScale += mass * v_W.norm();
    const RScalar h = shapeOrigin_W.dot(up);
    t.minHeight = count == 0 ? h : std::min(t.minHeight, h);
    t.meanHeight += h;
    t.finite = t.finite && AllFinite(v_W) && AllFinite(w_W) && AllFinite(shapeOrigin_W);
    ++count;
  }
  Totals Done() {
    if (count > 0) t.meanHeight /= static_cast<RScalar>(count);
    return t;
  }
};

RVec3 Up(const RScene& scene) {
  const RVec3& g = scene.settings.gravity_W;
  return g.norm() > 0 ? RVec3(-g / g.norm()) : RVec3(RVec3::UnitY());
}

Totals Measure(const RScene& scene, const std::vector<RRigidBody>& bodies) {
  Accumulator acc;
  acc.up = Up(scene);
  for (const RRigidBody& b : bodies) {
    if (b.IsStatic()) continue;
    acc.Add(b.Mass(), b.Inertia_B(), b.Orientation_WB(), b.Velocity_W(), b.AngularVelocity_W(),
            b.ShapePosition_W());
  }
  return acc.Done();
}

struct RunResult {
  double msPerStep = 0;
  Totals start, end;
  std::string failure;  // REngine's report of a body that became non-finite, if any
};

RunResult RunREngine(const RScene& scene, std::uint64_t steps, bool sleep) {
  std::vector<RRigidBody> bodies = CreateBodies(scene);
  RWorldSettings settings = scene.settings;
  settings.shortcuts.sleeping = sleep;
  RIntegrator integrator(settings);
  RunResult r;
  r.start = Measure(scene, bodies);
  const Clock::time_point t0 = Clock::now();
  for (std::uint64_t s = 0; s < steps; ++s) integrator.Update(bodies, scene.dt);
  const Clock::time_point t1 = Clock::now();
  r.msPerStep = std::chrono::duration<double, std::milli>(t1 - t0).count() /
                static_cast<double>(steps);
  r.end = Measure(scene, bodies);
  if (const auto& bad = integrator.NonFinite()) {
    r.end.finite = false;
    r.failure = "REngine: body " + bad->bodyName + " became non-finite at step " +
                std::to_string(bad->step) + " (left at its last finite state)";
  }
  return r;
}

Totals Measure(const RScene& scene, const BulletWorld& w) {
  Accumulator acc;
  acc.up = Up(scene);
  for (std::size_t i = 0; i < w.bodies.size(); ++i) {
    const RRigidBody& ref = *w.reference[i];
    if (ref.IsStatic()) continue;
    const btRigidBody& b = *w.bodies[i];
    const btTransform& X_WB = b.getCenterOfMassTransform();
    const RQuat q_WB = R(X_WB.getRotation());
    const RVec3 x_W = R(X_WB.getOrigin());
    acc.Add(ref.Mass(), ref.Inertia_B(), q_WB, R(b.getLinearVelocity()),
            R(b.getAngularVelocity()), x_W + q_WB * ref.ShapeOffset_B());
  }
  return acc.Done();
}

RunResult RunBullet(const RScene& scene, std::uint64_t steps, const BulletCoefficients& coeffs,
                    bool sleep) {
  const std::vector<RRigidBody> reference = CreateBodies(scene);
  std::unique_ptr<BulletWorld> w = BuildBullet(scene.settings, reference, coeffs, sleep,
                                               scene.ignore);
  RunResult r;
  r.start = Measure(scene, *w);
  const btScalar dt = Bt(scene.dt);
  const Clock::time_point t0 = Clock::now();
  for (std::uint64_t s = 0; s < steps; ++s) w->world.stepSimulation(dt, 0);
  const Clock::time_point t1 = Clock::now();
  r.msPerStep = std::chrono::duration<double, std::milli>(t1 - t0).count() /
                static_cast<double>(steps);
  r.end = Measure(scene, *w);
  return r;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

const char* CombineName(RCombineMode m) {
  switch (m) {
    case RCombineMode::kMin: return "min";
    case RCombineMode::kMax: return "max";
    case RCombineMode::kProduct: return "product";
    case RCombineMode::kAverage: return "average";
    case RCombineMode::kGeometric: return "geometric";
  }
  return "?";
}

std::string BaseName(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

void PrintConservation(const char* engine, const RunResult& r) {
  const RScalar dE = (r.end.kinetic - r.start.kinetic) / r.start.kinetic;
  const RScalar dP = (r.end.momentum - r.start.momentum).norm() /
                     std::max(r.start.momentumScale, RScalar(1e-300));
  std::printf("  %-8s kinetic energy %.6g J -> %.6g J: relative change %+.3e; "
              "momentum drift |P_end - P_0| / sum(m|v_0|) = %.3e%s\n",
              engine, r.start.kinetic, r.end.kinetic, dE, dP, r.end.finite ? "" : " (NON-FINITE)");
}

void PrintHeights(const char* engine, const RunResult& r) {
  std::printf("  %-8s mean height %.4f m -> %.4f m (lowest %.4f m)%s\n", engine,
              r.start.meanHeight, r.end.meanHeight, r.end.minHeight,
              r.end.finite ? "" : " (NON-FINITE)");
}

// Returns false when the scene cannot be run.
bool RunScene(const std::string& path, const Options& opt) {
  RScene scene;
  try {
    scene = LoadScene(path);
    (void)CreateBodies(scene);  // mass properties valid: fail here, not half-way through
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_bullet: %s\n", e.what());
    return false;
  }
  const std::uint64_t steps = opt.steps > 0 ? opt.steps : scene.steps;
  std::size_t dynamic = 0;
  for (const RBodyDef& d : scene.bodies) dynamic += d.kind == RBodyKind::kStatic ? 0 : 1;
  const RVec3& g = scene.settings.gravity_W;
  std::printf("\n%s: %zu bodies (%zu dynamic), dt %.6g s, %llu steps, gravity (%g, %g, %g), "
              "solver iterations %d\n",
              BaseName(path).c_str(), scene.bodies.size(), dynamic, scene.dt,
              static_cast<unsigned long long>(steps), g.x(), g.y(), g.z(),
              scene.settings.solverIterations);

  const BulletCoefficients coeffs =
      ChooseCoefficients(scene.settings, CreateBodies(scene), opt.matchCombine);
  std::printf("  combine: REngine restitution %s, friction %s; Bullet multiplies both "
              "(%s)\n",
              CombineName(scene.settings.restitutionCombine),
              CombineName(scene.settings.frictionCombine),
              opt.matchCombine ? "per-body values mapped to match where possible"
                               : "per-body values as in the scene");
  auto report = [](const char* what, RScalar err, const std::string& ex) {
    if (err <= 1e-12) {
      std::printf("  %s: every pair's combined value is the same in both engines\n", what);
    } else {
      std::printf("  %s: pair values DIFFER by up to %.3g (%s)\n", what, err, ex.c_str());
    }
  };
  report("restitution", coeffs.restitutionError, coeffs.restitutionExample);
  report("friction", coeffs.frictionError, coeffs.frictionExample);

  std::vector<double> rengineMs, bulletMs;
  RunResult rengineFirst, bulletFirst;
  for (int run = 0; run < opt.runs; ++run) {
    const RunResult re = RunREngine(scene, steps, opt.sleep);
    const RunResult bt = RunBullet(scene, steps, coeffs, opt.sleep);
    rengineMs.push_back(re.msPerStep);
    bulletMs.push_back(bt.msPerStep);
    if (run == 0) rengineFirst = re, bulletFirst = bt;
    std::printf("  run %d: REngine %9.4f ms/step   Bullet %9.4f ms/step\n", run + 1,
                re.msPerStep, bt.msPerStep);
    std::fflush(stdout);
  }
  const double mr = Median(rengineMs), mb = Median(bulletMs);
  std::printf("  median of %d: REngine %.4f ms/step, Bullet %.4f ms/step, "
              "ratio Bullet/REngine %.3f (%s)\n",
              opt.runs, mr, mb, mb / mr, mb / mr > 1 ? "REngine faster" : "Bullet faster");

  if (g.norm() == 0) {
    std::printf("  zero gravity: kinetic energy and momentum over the run (first run)\n");
    PrintConservation("REngine", rengineFirst);
    PrintConservation("Bullet", bulletFirst);
  } else {
    std::printf("  height of the %zu dynamic bodies' shape origins along -gravity, start -> "
                "end (first run)\n",
                dynamic);
    PrintHeights("REngine", rengineFirst);
    PrintHeights("Bullet", bulletFirst);
  }
  if (!rengineFirst.failure.empty()) std::printf("  %s\n", rengineFirst.failure.c_str());
  return true;
}

void Usage() {
  std::fprintf(stderr,
               "usage: bench_bullet [SCENE.json ...] [--steps N] [--runs N] [--match-combine] "
               "[--sleep]\n"
               "default scenes: %s/{box_pile_1000,debris_cloud_1000}.json\n",
               RENGINE_SCENES);
}

bool ParsePositive(const std::string& text, std::uint64_t& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size() && out > 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options opt;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--steps" || arg == "--runs") {
      std::uint64_t n = 0;
      if (i + 1 >= argc || !ParsePositive(argv[i + 1], n) || (arg == "--runs" && n > 1000)) {
        std::fprintf(stderr, "bench_bullet: %s needs an integer >= 1\n", arg.c_str());
        Usage();
        return 2;
      }
      ++i;
      if (arg == "--steps") {
        opt.steps = n;
      } else {
        opt.runs = static_cast<int>(n);
      }
    } else if (arg == "--match-combine") {
      opt.matchCombine = true;
    } else if (arg == "--sleep") {
      opt.sleep = true;
    } else if (arg == "--help" || arg == "-h") {
      Usage();
      return 0;
    } else if (!arg.empty() && arg[0] == '-') {
      std::fprintf(stderr, "bench_bullet: unknown option %s\n", arg.c_str());
      Usage();
      return 2;
    } else {
      opt.scenes.push_back(arg);
    }
  }
  if (opt.scenes.empty()) {
    opt.scenes = {RENGINE_SCENES "/box_pile_1000.json",
                  RENGINE_SCENES "/debris_cloud_1000.json"};
  }

  std::printf("bench_bullet: REngine (double) vs Bullet %d.%02d (%s precision: "
              "BT_USE_DOUBLE_PRECISION %s), same scenes, same process, single thread\n",
              btGetVersion() / 100, btGetVersion() % 100,
              sizeof(btScalar) == 8 ? "double" : "single",
              btIsDoublePrecision() ? "defined" : "not defined");
  std::printf("Bullet world: btDbvtBroadphase, btSequentialImpulseConstraintSolver (scene's "
              "solver iterations), stepSimulation(dt, 0): one internal step per step, no "
              "motion states; sleeping %s\n",
              opt.sleep ? "on in both engines (--sleep)" : "off in both engines");
  std::printf("timing: steady_clock around the step loop only; REngine then Bullet, %d "
              "runs; ratio = Bullet / REngine median ms/step (> 1: REngine faster)\n",
              opt.runs);
  std::printf("note: combine modes differ: Bullet multiplies the two bodies' restitutions and "
              "frictions; REngine combines them as the scene says (see each scene)\n");

  bool ok = true;
  for (const std::string& path : opt.scenes) ok = RunScene(path, opt) && ok;
  return ok ? 0 : 2;
}
