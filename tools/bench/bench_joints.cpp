// bench_joints: REngine's joints against Bullet's on the closed-form scenes of
// tests/joints/joints_test.cpp, in the same process (that suite asserts REngine's side of each).
//
//   bench_joints [--repeats N] [--csv FILE] [--quick]
//
// Six scenes at 60 Hz, 10 solver iterations in both engines, gravity 9.81 m/s^2 (zero for the
// weld): a pendulum on a ball joint, a hinge motor spinning a wheel up, a 10-link chain holding
// a 100 kg weight, a rope stopping a falling weight, a slider's limit stopping a falling car,
// and a welded pair tumbling in zero g. Each scene is built once in REngine (RBodies, AddJoint)
// and its Bullet twin is built from those same bodies and joints: the same masses, principal
// moments, poses and velocities (tools/bench/BulletWorld.h: Bullet's body frame is REngine's,
// centre of mass and principal axes) and the joints' anchors and axes in those frames.
// The figures are computed the same way for both engines from the bodies' states (position,
// orientation, velocity, angular velocity of the centre of mass) and REngine's mass properties.
//
// Bullet's joints (Bullet's default ERP and CFM everywhere; its bodies never sleep):
//   ball     btPoint2PointConstraint
//   hinge    btHingeConstraint, enableAngularMotor(true, speed, maxImpulse = maxForce dt)
//            (Bullet drives A's speed relative to B; a joint to the world is A alone)
//   slider   btSliderConstraint (x of its frames along the axis), setLower/UpperLinLimit,
//            rotation locked (its default); Bullet's defaults for the limit's softness (1),
//            damping (1: no restitution) and ERP
//   fixed    btFixedConstraint, both frames at the anchor
//   distance Bullet has no distance joint: btPoint2PointConstraint holds the anchors together,
//            it cannot be slack. The rope is a btGeneric6DofSpring2Constraint whose frames'
//            x axis is the rope's direction at the start, x limited to the rope's length, y,
//            z and every rotation free: a plane the weight cannot pass, the same as the rope
//            for a weight that falls straight along it (this scene), not in general.
// Joined bodies do not collide in either engine (collideConnected false; Bullet's
// addConstraint(c, true)). REngine runs on one thread (Bullet's is single-threaded), sleeping
// off in both, so both step every body every step.
//
// Timing: each scene runs --repeats times in each engine, interleaved (REngine, Bullet,
// REngine, ...); the clock (steady_clock) is read around each step call alone, setup and the
// figures excluded. us_per_step is the median over the repeats. Both engines are
// deterministic: the figures come from the first repeat.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include "BulletWorld.h"
#include "JointScenes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

using namespace REngine;
using namespace REngine::bench;

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kIterations = 10;

// ---- the engines -------------------------------------------------------------------------

struct Run {
  std::vector<Figure> figures;
  double seconds = 0;  // in the step calls
};

RWorldSettings Settings(const Scene& scene) {
  RWorldSettings s;
  s.gravity_W = scene.gravity;
  s.solverIterations = kIterations;
  s.threads = 1;
  s.shortcuts.sleeping = false;
  return s;
}

std::vector<State> Masses(const RBodies& bodies) {
  std::vector<State> s(bodies.Size());
  for (std::size_t i = 0; i < s.size(); ++i) s[i].m = bodies.At(i).Mass(), s[i].I_B = bodies.At(i).Inertia_B();
  return s;
}

void Read(const RBodies& bodies, std::vector<State>& s) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    const RRigidBody& b = bodies.At(i);
    s[i].x = b.Position_W(), s[i].q = b.Orientation_WB();
    s[i].v = b.Velocity_W(), s[i].w = b.AngularVelocity_W();
  }
}

Run RunREngine(Scene& scene) {
  RBodies bodies;
  scene.Build(bodies);
  RIntegrator integrator(Settings(scene));
  std::vector<State> s = Masses(bodies);
  Read(bodies, s);
  scene.Begin(s);
  Run run;
  for (int step = 1; step <= scene.steps; ++step) {
    const auto t0 = Clock::now();
    integrator.Update(bodies, kDt);
    run.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    Read(bodies, s);
    scene.Observe(step, s);
  }
  run.figures = scene.Figures();
  return run;
}

// A rotation whose x axis is `axis` (unit): a joint frame's basis.
RQuat FrameWithX(const RVec3& axis) {
  RVec3 y = std::abs(axis.x()) < 0.9 ? RVec3::UnitX() : RVec3::UnitY();
  y = (y - axis * axis.dot(y)).normalized();
  RMat3 m;
  m.col(0) = axis, m.col(1) = y, m.col(2) = axis.cross(y);
  return RQuat(m);
}

btTransform BtFrame(const RQuat& q, const RVec3& p) { return btTransform(Bt(q), Bt(p)); }

// Bullet's twin of an REngine joint (see the file's comment), added to the world.
std::unique_ptr<btTypedConstraint> BulletJoint(BulletWorld& w, const RBodies& bodies, const RJoint& j) {
  const std::size_t ia = DenseOf(bodies, j.def.a);
  btRigidBody& A = *w.bodies[ia];
  const bool world = !j.def.b.IsValid();
  btRigidBody* B = world ? nullptr : w.bodies[DenseOf(bodies, j.def.b)].get();
  const RRigidBody& ra = bodies.At(ia);
  const RQuat qA = ra.Orientation_WB();
  const RQuat qB = world ? RQuat::Identity() : bodies[j.def.b].Orientation_WB();
  // anchorB_B is a world point for a joint to the world.
  const RVec3 pivotA = j.anchorA_B, pivotB = j.anchorB_B;
  std::unique_ptr<btTypedConstraint> c;
  switch (j.def.type) {
    case RJointType::kBall:
      if (world) c = std::make_unique<btPoint2PointConstraint>(A, Bt(pivotA));
      else c = std::make_unique<btPoint2PointConstraint>(A, *B, Bt(pivotA), Bt(pivotB));
      break;
    case RJointType::kHinge: {
      if (j.def.hasLimits) {
        std::fprintf(stderr, "bench_joints: hinge limits are not translated to Bullet\n");
        std::exit(2);
      }
      const RVec3 axis_W = j.def.axis_W.normalized();
      std::unique_ptr<btHingeConstraint> h;
      if (world) {
        h = std::make_unique<btHingeConstraint>(A, Bt(pivotA), Bt(RVec3(qA.conjugate() * axis_W)), false);
      } else {
        h = std::make_unique<btHingeConstraint>(A, *B, Bt(pivotA), Bt(pivotB), Bt(RVec3(qA.conjugate() * axis_W)),
                                                Bt(RVec3(qB.conjugate() * axis_W)), false);
      }
      if (j.def.motor.enabled) {
        // REngine's speed is b's relative to a (a's to the world for a joint to the world);
        // Bullet's is A's relative to B.
        const RScalar speed = world ? j.def.motor.speed : -j.def.motor.speed;
        h->enableAngularMotor(true, Bt(speed), Bt(j.def.motor.maxForce * kDt));
      }
      c = std::move(h);
      break;
    }
    case RJointType::kSlider: {
      if (!world || j.def.motor.enabled) {
        std::fprintf(stderr, "bench_joints: only a slider to the world without a motor is translated\n");
        std::exit(2);
      }
      // Bullet's one-body slider holds its body as B; its travel is B's along the axis, as
      // REngine's is a's relative to the world.
      const RQuat frame_W = FrameWithX(j.def.axis_W.normalized());
      auto s = std::make_unique<btSliderConstraint>(A, BtFrame(qA.conjugate() * frame_W, pivotA), true);
      if (j.def.hasLimits) {
        s->setLowerLinLimit(Bt(j.def.lower));
        s->setUpperLinLimit(Bt(j.def.upper));
      }
      c = std::move(s);
      break;
    }
    case RJointType::kFixed: {
      if (world) {
        std::fprintf(stderr, "bench_joints: a weld to the world is not translated\n");
        std::exit(2);
      }
      c = std::make_unique<btFixedConstraint>(A, *B, BtFrame(qA.conjugate(), pivotA),
                                              BtFrame(qB.conjugate(), pivotB));
      break;
    }
    case RJointType::kDistance: {
      if (!world || j.minDistance > 0) {
        std::fprintf(stderr, "bench_joints: only a rope (min 0) to the world is translated\n");
        std::exit(2);
      }
      // The rope's direction at the start, from the world point to the body's anchor: x of
      // both frames. Bullet's one-body constraint holds its body as B; x is B's travel.
      const RVec3 onBody_W = ra.Position_W() + qA * pivotA;
      const RVec3 along = onBody_W - pivotB;
      const RScalar d0 = along.norm();
      const RQuat frame_W = FrameWithX(along / d0);
      auto g = std::make_unique<btGeneric6DofSpring2Constraint>(A, BtFrame(qA.conjugate() * frame_W, pivotA));
      g->setLinearLowerLimit(btVector3(Bt(-1e3), 1, 1));  // lower > upper: free
      g->setLinearUpperLimit(btVector3(Bt(j.maxDistance - d0), -1, -1));
      g->setAngularLowerLimit(btVector3(1, 1, 1));
      g->setAngularUpperLimit(btVector3(-1, -1, -1));
      c = std::move(g);
      break;
    }
  }
  w.world.addConstraint(c.get(), !j.def.collideConnected);
  return c;
}

Run RunBullet(Scene& scene) {
  RBodies bodies;
  scene.Build(bodies);
  const RWorldSettings settings = Settings(scene);
  const std::vector<RRigidBody> reference(bodies.begin(), bodies.end());
  const BulletCoefficients coeffs = ChooseCoefficients(settings, reference, false);
  std::unique_ptr<BulletWorld> w = BuildBullet(settings, reference, coeffs, /*sleep=*/false);
  std::vector<std::unique_ptr<btTypedConstraint>> joints;
  for (std::size_t k = 0; k < bodies.JointCount(); ++k) joints.push_back(BulletJoint(*w, bodies, bodies.JointAt(k)));
  std::vector<State> s = Masses(bodies);
  auto read = [&] {
    for (std::size_t i = 0; i < s.size(); ++i) {
      const btRigidBody& b = *w->bodies[i];
      s[i].x = R(b.getCenterOfMassPosition()), s[i].q = R(b.getOrientation());
      s[i].v = R(b.getLinearVelocity()), s[i].w = R(b.getAngularVelocity());
    }
  };
  read();
  scene.Begin(s);
  Run run;
  for (int step = 1; step <= scene.steps; ++step) {
    const auto t0 = Clock::now();
    w->world.stepSimulation(Bt(kDt), 0);
    run.seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    read();
    scene.Observe(step, s);
  }
  run.figures = scene.Figures();
  for (auto& c : joints) w->world.removeConstraint(c.get());
  return run;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 7;
  std::string csvPath;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repeats" && i + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "--csv" && i + 1 < argc) {
      csvPath = argv[++i];
    } else if (arg == "--quick") {
      repeats = 1;
    } else {
      std::fprintf(stderr,
                   "usage: bench_joints [--repeats N (default 7)] [--csv FILE] [--quick (one repeat)]\n"
                   "REngine's joints against Bullet's on joints_test's closed-form scenes, 60 Hz,\n"
                   "%d iterations; see the source's comment for the scenes and Bullet's joints.\n",
                   kIterations);
      return arg == "--help" || arg == "-h" ? 0 : 2;
    }
  }
  std::vector<std::unique_ptr<Scene>> scenes = JointScenes();

  std::FILE* csv = nullptr;
  if (!csvPath.empty()) {
    csv = std::fopen(csvPath.c_str(), "w");
    if (!csv) {
      std::fprintf(stderr, "bench_joints: cannot write %s\n", csvPath.c_str());
      return 1;
    }
    std::fprintf(csv, "scene,engine,steps,dt,iterations,repeats,us_per_step");
    for (int k = 1; k <= 5; ++k) std::fprintf(csv, ",figure%d,value%d", k, k);
    std::fprintf(csv, "\n");
  }
  std::printf("bench_joints: 60 Hz, %d iterations, %d interleaved repeats; Bullet %d (%s precision)\n",
              kIterations, repeats, btGetVersion(), sizeof(btScalar) == 8 ? "double" : "single");
  bool finite = true;
  for (auto& scene : scenes) {
    std::vector<double> times[2];
    std::vector<Figure> figures[2];
    for (int r = 0; r < repeats; ++r) {
      for (int e = 0; e < 2; ++e) {
        const Run run = e == 0 ? RunREngine(*scene) : RunBullet(*scene);
        times[e].push_back(run.seconds / scene->steps * 1e6);
        if (r == 0) figures[e] = run.figures;
      }
    }
    std::printf("\n%s: %s, %d steps\n", scene->name.c_str(), scene->title.c_str(), scene->steps);
    std::printf("  %-40s %12s %12s\n", "", "REngine", "Bullet");
    std::printf("  %-40s %12.3f %12.3f\n", "us/step (median)", Median(times[0]), Median(times[1]));
    for (std::size_t k = 0; k < figures[0].size(); ++k) {
      std::printf("  %-40s %12.3e %12.3e\n", figures[0][k].name.c_str(), figures[0][k].value, figures[1][k].value);
      finite = finite && std::isfinite(figures[0][k].value);
    }
    if (csv) {
      for (int e = 0; e < 2; ++e) {
        std::fprintf(csv, "%s,%s,%d,%.17g,%d,%d,%.4f", scene->name.c_str(), e == 0 ? "rengine" : "bullet",
                     scene->steps, kDt, kIterations, repeats, Median(times[e]));
        for (std::size_t k = 0; k < 5; ++k) {
          if (k < figures[e].size()) std::fprintf(csv, ",\"%s\",%.6e", figures[e][k].name.c_str(), figures[e][k].value);
          else std::fprintf(csv, ",,");
        }
        std::fprintf(csv, "\n");
      }
    }
  }
  if (csv) std::fclose(csv);
  // REngine's figures are always finite; a NaN is a broken run (the smoke test's check).
  return finite ? 0 : 1;
}
