// rengine-bench --shortcuts: see shortcuts.h. Each scene is built for one shortcut, run with
// and without it, and timed around the step loop only.
//
//   resting_stacks  sleeping. 100 stacks of 10 unit boxes (restitution 0) on a static floor,
//                   10 s at 60 Hz; a box dropped from 120 m lands on stack 0 near t = 5 s and
//                   wakes it. Error: the largest displacement of a box of the other stacks
//                   from where it started, m (physics: they rest, 0).
//   box_pile_1000   sleeping. scenes/box_pile_1000.json as given (1000 boxes
//                   dropped on the floor, 5 s). Error: the largest speed of a body at the
//                   end, m/s (how far from rest the pile still is; no closed form).
//   awake_pile      contactReuse. box_pile_1000 with sleeping off, 5 s. Error: the
//                   largest position difference between the runs at the end.
//   sparse_field    boundsRejection. 1000 tumbling boxes drifting at up to 10 m/s in a 2 km
//                   cube in zero g. Error: the largest position difference between the
//                   runs with and without, after the steps the run without can afford, m
//                   (exact: 0).
//   symmetric       equal principal moments (a body property, not a switch): 200 free
//                   bodies, cubes (three equal moments: omega constant) and square prisms
//                   (two equal: uniform precession), spinning at 1-5 rad/s, 10 s. Without:
//                   the same bodies with their half extents made 1e-6 and 2e-6 apart,
//                   which takes the general (Jacobi elliptic) path. Error: the largest
//                   |dL|/|L| of a body's world angular momentum over the run.
//   static_terrain  staticForms. 400 static blocks and a floor, 200 boxes falling on them,
//                   5 s, sleeping off. Error: the largest position difference between the
//                   runs, m (exact: 0).
//   static_hulls    staticForms. 4 static hulls of 2000 random points on ellipsoids (their
//                   vertices: asteroid surfaces), 100 boxes falling on them, 5 s, sleeping
//                   off. Error: as static_terrain (exact: 0).
#include "shortcuts.h"

#include "report.h"

#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#ifdef RENGINE_HAVE_BULLET
#include "BulletWorld.h"
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include "support/ReferenceScenes.h"
#include "support/TestBodies.h"

using namespace REngine;
using test::BodyDef;
using test::BoxDef;
using test::HullDef;
using test::LoadReferenceScene;
using test::UniformIn;

namespace rbench {

namespace {

using Clock = std::chrono::steady_clock;
constexpr RScalar kDt = RScalar(1) / 60;

struct Setup {
  std::vector<RRigidBody> bodies;
  RWorldSettings settings;
};
using Make = std::function<Setup(bool shortcutOn)>;

// Deterministic uniform numbers from a seed (UniformIn: the same on every platform).
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : m_rng(seed) {}
  RScalar operator()(RScalar lo, RScalar hi) { return UniformIn(m_rng, lo, hi); }

 private:
  std::mt19937_64 m_rng;
};

// A box, 1 kg unless static. (One call with every value as an argument: the scenes below
// draw their random sizes and positions inside the call, in the order the compiler evaluates
// arguments, which a chain of setters would change.)
RBodyDef Box(const std::string& name, const RVec3& halfExtents, const RVec3& x, bool isStatic) {
  BodyDef d = BoxDef(halfExtents).At(x).Named(name);
  return isStatic ? d.Static() : d.Mass(1);
}

double TimeOneRun(const Make& make, bool on, int steps) {
  Setup s = make(on);
  RIntegrator integrator(s.settings);
  const auto t0 = Clock::now();
  for (int k = 0; k < steps; ++k) integrator.Update(s.bodies, kDt);
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / steps;
}

// Median ms per step with and without the shortcut, over `repeats` timed runs of each on a
// fresh world, alternating with and without so that the machine's drifts (a shared, noisy
// machine) fall on both alike.
void TimeRuns(ShortcutRow& row, const Make& make, int stepsOn, int stepsOff, int repeats) {
  std::vector<double> on, off;
  for (int r = 0; r < repeats; ++r) {
    on.push_back(TimeOneRun(make, true, stepsOn));
    off.push_back(TimeOneRun(make, false, stepsOff));
  }
  row.onMs = Median(on), row.offMs = Median(off);
}

std::vector<RRigidBody> Run(const Make& make, bool on, int steps,
                            const std::function<void(const std::vector<RRigidBody>&)>& each = {}) {
  Setup s = make(on);
  RIntegrator integrator(s.settings);
  for (int k = 0; k < steps; ++k) {
    integrator.Update(s.bodies, kDt);
    if (each) each(s.bodies);
  }
  return s.bodies;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

ShortcutRow NewRow(const char* scene, const char* shortcut, const char* unit) {
  return ShortcutRow{scene, shortcut, 0, 0, 0, 0, unit, kNaN, kNaN, kNaN, kNaN};
}

// Bullet on the same world (built from the shortcut-on setup), with its deactivation on or
// off: `each` sees the centre-of-mass positions and velocities after every step.
using BulletObserver = std::function<void(const std::vector<RVec3>& x, const std::vector<RVec3>& v)>;
#ifdef RENGINE_HAVE_BULLET
double RunBullet(const Make& make, bool sleep, int steps, int repeats, const BulletObserver& each) {
  std::vector<double> ms;
  std::vector<RVec3> x, v;
  for (int r = 0; r < repeats + 1; ++r) {  // run 0 observes (untimed), the others are timed
    const Setup s = make(true);
    const bench::BulletCoefficients coeffs = bench::ChooseCoefficients(s.settings, s.bodies, true);
    const std::unique_ptr<bench::BulletWorld> w = bench::BuildBullet(s.settings, s.bodies, coeffs, sleep);
    const btScalar dt = bench::Bt(kDt);
    const auto t0 = Clock::now();
    for (int k = 0; k < steps; ++k) {
      w->world.stepSimulation(dt, 0);
      if (r == 0 && each) {
        x.resize(w->bodies.size()), v.resize(w->bodies.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
          x[i] = bench::R(w->bodies[i]->getCenterOfMassPosition());
          v[i] = bench::R(w->bodies[i]->getLinearVelocity());
        }
        each(x, v);
      }
    }
    if (r > 0) ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / steps);
  }
  return Median(ms);
}
#endif

RScalar MaxDifference(const std::vector<RRigidBody>& a, const std::vector<RRigidBody>& b) {
  RScalar worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    worst = std::max(worst, (a[i].Position_W() - b[i].Position_W()).norm());
  }
  return worst;
}

// The row's error is the largest position difference between the runs with and without
// the shortcut, after the steps the run without can afford: 0 for one that claims to be
// exact.
ShortcutRow DifferenceRow(const char* scene, const char* shortcut, const Make& make, int stepsOn,
                     int stepsOff, int repeats) {
  ShortcutRow row = NewRow(scene, shortcut, "m: position difference between the runs");
  row.errorOn = MaxDifference(Run(make, true, stepsOff), Run(make, false, stepsOff));
  TimeRuns(row, make, stepsOn, stepsOff, repeats);
  return row;
}

// Fills the row's Bullet columns where Bullet is built in: error(sleep) observes a run.
template <class ErrorOf>
void AddBullet(ShortcutRow& row, const Make& make, int steps, int repeats, ErrorOf&& errorOf) {
#ifdef RENGINE_HAVE_BULLET
  for (int sleep = 1; sleep >= 0; --sleep) {
    double error = 0;
    const double ms = RunBullet(make, sleep != 0, steps, repeats, errorOf(error));
    (sleep ? row.bulletOnMs : row.bulletOffMs) = ms;
    (sleep ? row.bulletErrorOn : row.bulletErrorOff) = error;
  }
#else
  (void)row, (void)make, (void)steps, (void)repeats, (void)errorOf;
#endif
}


// ---- resting_stacks -------------------------------------------------------------------
ShortcutRow RestingStacks(bool quick, int repeats) {
  const int side = quick ? 2 : 10, height = quick ? 5 : 10;
  const int steps = quick ? 60 : 600;
  const RScalar dropHeight = quick ? 2 : 120;  // m above the top of stack 0
  auto make = [=](bool on) {
    Setup s;
    s.settings.gravity_W = RVec3(0, -9.81, 0);
    s.settings.shortcuts.sleeping = on;
    s.bodies.emplace_back(Box("floor", RVec3(3 * side + 10, 0.5, 3 * side + 10), RVec3(0, -0.5, 0), true));
    for (int i = 0; i < side; ++i) {
      for (int j = 0; j < side; ++j) {
        for (int k = 0; k < height; ++k) {
          RBodyDef d = Box("s" + std::to_string(i * side + j) + "_" + std::to_string(k),
                           RVec3::Constant(0.5), RVec3(3 * i, 0.5 + k, 3 * j), false);
          d.restitution = 0;
          s.bodies.emplace_back(d);
        }
      }
    }
    RBodyDef drop = Box("dropped", RVec3::Constant(0.5), RVec3(0, height + 0.5 + dropHeight, 0), false);
    drop.restitution = 0;
    s.bodies.emplace_back(drop);
    return s;
  };
  ShortcutRow row = NewRow("resting_stacks", "sleeping",
                          "m: largest displacement of a box of the stacks not hit");
  const Setup start = make(true);
  for (int on = 1; on >= 0; --on) {
    RScalar worst = 0;
    Run(make, on != 0, steps, [&](const std::vector<RRigidBody>& bodies) {
      for (std::size_t b = 1 + height; b + 1 < bodies.size(); ++b) {
        worst = std::max(worst, (bodies[b].Position_W() - start.bodies[b].Position_W()).norm());
      }
    });
    (on ? row.errorOn : row.errorOff) = worst;
  }
  TimeRuns(row, make, steps, steps, repeats);
  AddBullet(row, make, steps, repeats, [&](double& worst) -> BulletObserver {
    return [&worst, &start, height](const std::vector<RVec3>& x, const std::vector<RVec3>&) {
      for (std::size_t b = 1 + height; b + 1 < x.size(); ++b) {
        worst = std::max(worst, (x[b] - start.bodies[b].Position_W()).norm());
      }
    };
  });
  return row;
}

// ---- box_pile_1000 --------------------------------------------------------------------
ShortcutRow BoxPile(bool quick, int repeats) {
  const RScene scene = LoadReferenceScene("box_pile_1000");
  const int steps = quick ? 30 : static_cast<int>(scene.steps);
  auto make = [&scene](bool on) {
    Setup s{CreateBodies(scene), scene.settings};
    s.settings.shortcuts.sleeping = on;
    return s;
  };
  ShortcutRow row = NewRow("box_pile_1000", "sleeping", "m/s: largest speed at the end");
  for (int on = 1; on >= 0; --on) {
    RScalar worst = 0;
    for (const RRigidBody& b : Run(make, on != 0, steps)) {
      worst = std::max(worst, b.Velocity_W().norm() + b.AngularVelocity_W().norm() * b.BoundingRadius());
    }
    (on ? row.errorOn : row.errorOff) = worst;
  }
  TimeRuns(row, make, steps, steps, repeats);
  // Bullet reports linear speed only here (its angular velocity is not converted): the
  // largest centre-of-mass speed at the end.
  AddBullet(row, make, steps, repeats, [&](double& worst) -> BulletObserver {
    return [&worst](const std::vector<RVec3>&, const std::vector<RVec3>& v) {
      worst = 0;
      for (const RVec3& vi : v) worst = std::max(worst, vi.norm());
    };
  });
  return row;
}

// ---- awake_pile -----------------------------------------------------------------------
// contactReuse on box_pile_1000 with sleeping off (every contact awake for the whole run):
// not exact, each reused point is off by at most the touching band; the error is the
// largest position difference between the runs at the end.
ShortcutRow AwakePile(bool quick, int repeats) {
  const RScene scene = LoadReferenceScene("box_pile_1000");
  const int steps = quick ? 30 : static_cast<int>(scene.steps);
  auto make = [&scene](bool on) {
    Setup s{CreateBodies(scene), scene.settings};
    s.settings.shortcuts.sleeping = false;
    s.settings.shortcuts.contactReuse = on;
    return s;
  };
  return DifferenceRow("awake_pile", "contactReuse", make, steps, steps, repeats);
}

// ---- sparse_field ---------------------------------------------------------------------
ShortcutRow SparseField(bool quick, int repeats) {
  const int n = quick ? 100 : 1000;
  const int stepsOn = quick ? 10 : 60, stepsOff = quick ? 2 : 3;
  auto make = [n](bool on) {
    Setup s;
    s.settings.shortcuts.boundsRejection = on;
    Uniform u(20261122);
    for (int i = 0; i < n; ++i) {
      RBodyDef d = Box("rock" + std::to_string(i), RVec3(u(0.5, 3), u(0.5, 3), u(0.5, 3)),
                       RVec3(u(-1000, 1000), u(-1000, 1000), u(-1000, 1000)), false);
      d.velocity_W = RVec3(u(-10, 10), u(-10, 10), u(-10, 10)) / std::sqrt(RScalar(3));
      d.angularVelocity_W = RVec3(u(-2, 2), u(-2, 2), u(-2, 2));
      s.bodies.push_back(RRigidBody(d));
    }
    return s;
  };
  return DifferenceRow("sparse_field", "boundsRejection", make, stepsOn, stepsOff, repeats);
}

// ---- symmetric ------------------------------------------------------------------------
ShortcutRow Symmetric(bool quick, int repeats) {
  const int n = quick ? 20 : 200;
  const int steps = quick ? 60 : 600;
  auto make = [n](bool on) {
    Setup s;
    Uniform u(7);
    const RVec3 skew = on ? RVec3::Ones() : RVec3(1, 1 + 1e-6, 1 + 2e-6);
    for (int i = 0; i < n; ++i) {
      const RVec3 half = (i % 2 ? RVec3(0.5, 0.5, 1) : RVec3::Constant(0.5)).cwiseProduct(skew);
      RBodyDef d = Box("b" + std::to_string(i), half, RVec3(10 * (i % 15), 10 * (i / 15), 0), false);
      const RVec3 axis = RVec3(u(-1, 1), u(-1, 1), u(-1, 1)).normalized();
      d.angularVelocity_W = u(1, 5) * axis;
      s.bodies.push_back(RRigidBody(d));
    }
    return s;
  };
  ShortcutRow row = NewRow("symmetric", "equal moments",
                          "|dL|/|L|: largest world angular momentum drift of a body");
  for (int on = 1; on >= 0; --on) {
    const Setup start = make(on != 0);
    RScalar worst = 0;
    Run(make, on != 0, steps, [&](const std::vector<RRigidBody>& bodies) {
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        const RVec3 l0 = start.bodies[b].AngularMomentum_W();
        worst = std::max(worst, (bodies[b].AngularMomentum_W() - l0).norm() / l0.norm());
      }
    });
    (on ? row.errorOn : row.errorOff) = worst;
  }
  TimeRuns(row, make, steps, steps, repeats);
  return row;
}

// ---- static_terrain -------------------------------------------------------------------
ShortcutRow StaticTerrain(bool quick, int repeats) {
  const int side = quick ? 5 : 20, falling = quick ? 20 : 200;
  const int steps = quick ? 30 : 300;
  auto make = [=](bool on) {
    Setup s;
    s.settings.gravity_W = RVec3(0, -9.81, 0);
    s.settings.shortcuts.sleeping = false;
    s.settings.shortcuts.staticForms = on;
    Uniform u(99);
    const RScalar extent = 4 * side;
    s.bodies.emplace_back(Box("floor", RVec3(extent, 0.5, extent), RVec3(extent / 2, -0.5, extent / 2), true));
    for (int i = 0; i < side; ++i) {
      for (int j = 0; j < side; ++j) {
        const RScalar h = u(0.5, 2.5);
        s.bodies.emplace_back(Box("block" + std::to_string(i * side + j), RVec3(1, h, 1),
                                  RVec3(4 * i + 2, h, 4 * j + 2), true));
      }
    }
    for (int i = 0; i < falling; ++i) {
      RBodyDef d = Box("crate" + std::to_string(i), RVec3(u(0.3, 0.8), u(0.3, 0.8), u(0.3, 0.8)),
                       RVec3(u(0, extent), u(8, 20), u(0, extent)), false);
      d.angularVelocity_W = RVec3(u(-2, 2), u(-2, 2), u(-2, 2));
      s.bodies.emplace_back(d);
    }
    return s;
  };
  return DifferenceRow("static_terrain", "staticForms", make, steps, steps, repeats);
}

// ---- static_hulls ---------------------------------------------------------------------
ShortcutRow StaticHulls(bool quick, int repeats) {
  const int hulls = 4, points = quick ? 200 : 2000, falling = quick ? 10 : 100;
  const int steps = quick ? 30 : 300;
  // The hulls' point clouds, drawn once: every world (with and without) gets the same.
  std::vector<std::vector<RVec3>> clouds(hulls);
  Uniform u(4242);
  for (auto& cloud : clouds) {
    for (int k = 0; k < points; ++k) {
      RVec3 p(u(-1, 1), u(-1, 1), u(-1, 1));
      if (p.norm() < 1e-3) continue;
      cloud.push_back(p.normalized().cwiseProduct(RVec3(6, 3, 5)));
    }
  }
  auto make = [=](bool on) {
    Setup s;
    s.settings.gravity_W = RVec3(0, -9.81, 0);
    s.settings.shortcuts.sleeping = false;
    s.settings.shortcuts.staticForms = on;
    for (int h = 0; h < hulls; ++h) {
      s.bodies.emplace_back(HullDef(clouds[h])
                                .Static()
                                .At(RVec3(14 * (h % 2), 0, 12 * (h / 2)))
                                .Named("rock" + std::to_string(h)));
    }
    Uniform v(17);
    for (int i = 0; i < falling; ++i) {
      RBodyDef d = Box("crate" + std::to_string(i), RVec3(v(0.3, 0.8), v(0.3, 0.8), v(0.3, 0.8)),
                       RVec3(v(-5, 19), v(5, 15), v(-4, 16)), false);
      s.bodies.emplace_back(d);
    }
    return s;
  };
  return DifferenceRow("static_hulls", "staticForms", make, steps, steps, repeats);
}

}  // namespace

std::vector<ShortcutRow> RunShortcuts(bool quick, int repeats) {
  std::vector<ShortcutRow> rows;
  for (auto scene : {RestingStacks, BoxPile, AwakePile, SparseField, Symmetric, StaticTerrain, StaticHulls}) {
    rows.push_back(scene(quick, repeats));
    std::fprintf(stderr, "shortcuts: %s done\n", rows.back().scene.c_str());
  }
  return rows;
}

void PrintShortcutTable(const std::vector<ShortcutRow>& rows) {
  std::printf("%-15s %-16s %12s %12s %8s %11s %11s  %s\n", "scene", "shortcut", "on ms/step",
              "off ms/step", "speedup", "error on", "error off", "error");
  for (const ShortcutRow& r : rows) {
    std::printf("%-15s %-16s %12.4g %12.4g %7.3gx %11.3g %11.3g  %s\n", r.scene.c_str(),
                r.shortcut.c_str(), r.onMs, r.offMs, r.offMs / r.onMs, r.errorOn, r.errorOff,
                r.unit.c_str());
    if (!std::isnan(r.bulletOnMs)) {
      std::printf("%-15s %-16s %12.4g %12.4g %7.3gx %11.3g %11.3g  (Bullet, deactivation on/off)\n",
                  "", "bullet", r.bulletOnMs, r.bulletOffMs, r.bulletOffMs / r.bulletOnMs,
                  r.bulletErrorOn, r.bulletErrorOff);
    }
  }
}

bool WriteShortcutCsv(const std::string& path, const std::vector<ShortcutRow>& rows) {
  std::ofstream out(path);
  if (!out) return false;
  out << "scene,shortcut,on_ms_per_step,off_ms_per_step,speedup,error_on,error_off,error_unit,"
         "bullet_on_ms_per_step,bullet_off_ms_per_step,bullet_error_on,bullet_error_off\n";
  auto number = [](double x) {
    char text[32] = "";
    if (!std::isnan(x)) std::snprintf(text, sizeof text, "%.6g", x);
    return std::string(text);
  };
  for (const ShortcutRow& r : rows) {
    out << r.scene << ',' << r.shortcut << ',' << number(r.onMs) << ',' << number(r.offMs) << ','
        << number(r.offMs / r.onMs) << ',' << number(r.errorOn) << ',' << number(r.errorOff)
        << ",\"" << r.unit << "\"," << number(r.bulletOnMs) << ',' << number(r.bulletOffMs) << ','
        << number(r.bulletErrorOn) << ',' << number(r.bulletErrorOff) << '\n';
  }
  return static_cast<bool>(out);
}

}  // namespace rbench
