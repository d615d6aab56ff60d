// A few steps of RIntegrator::Update on a small fuzzed world (up to 8 boxes, spheres and
// hulls, static or dynamic, with fuzzed masses, velocities, gravity and step), with fuzzed
// API calls between the steps (forces, torques, impulses, velocities, poses; any bit
// pattern, so NaN and infinities too). Invariants: invalid arguments are refused with an
// exception derived from RError; after every step each body is finite, or
// listed by NonFiniteInLastStep() (and then put back, finite); nothing crashes.
#include <REnginePhysics/RIntegrator.h>

#include "FuzzInput.h"

#include <stdexcept>
#include <vector>

using namespace REngine;
using namespace REngine::fuzz;

namespace {

double Value(FuzzInput& in) {
  // Mostly game-sized values, sometimes any bit pattern.
  return in.Byte() % 8 == 0 ? in.RawDouble() : in.Range(-1, 1) * in.Decades(-3, 4);
}
RVec3 Vector(FuzzInput& in) {
  const double x = Value(in), y = Value(in), z = Value(in);  // in this order
  return RVec3(x, y, z);
}

bool Finite(const RRigidBody& b) {
  return AllFinite(b.Position_W()) && AllFinite(b.Orientation_WB()) && AllFinite(b.Velocity_W()) &&
         AllFinite(b.AngularVelocity_B());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  RWorldSettings settings;
  settings.gravity_W = in.Byte() % 2 ? RVec3(0, -9.81, 0) : RVec3::Zero();
  settings.solverIterations = 1 + in.Byte() % 12;
  settings.shortcuts.sleeping = in.Byte() % 2;
  const double dt = in.Decades(-4, -1);
  std::vector<RRigidBody> bodies;
  const int count = 1 + in.Byte() % 8;
  for (int i = 0; i < count; ++i) {
    RBodyDef d;
    const std::uint8_t kind = in.Byte();
    // (a capsule on 255, a cylinder on 254, a compound on 253: the other values keep the
    // corpus's meaning)
    switch (kind == 255 ? 3 : kind == 254 ? 4 : kind == 253 ? 5 : kind % 3) {
      case 5: {  // two or three children: boxes, spheres, capsules and cylinders, anywhere near
        d.shape.type = RShapeType::kCompound;
        const int children = 2 + in.Byte() % 2;
        for (int k = 0; k < children; ++k) {
          RCompoundChild c;
          const std::uint8_t t = in.Byte() % 4;
          // Every size is read whatever the type (the corpus's bytes keep their meaning); the
          // shape takes those its type reads.
          const RVec3 e(in.Decades(-2, 1), in.Decades(-2, 1), in.Decades(-2, 1));
          const double r = in.Decades(-2, 1), h = in.Decades(-2, 1);
          c.shape = t == 0 ? RShape::Box(e) : t == 1 ? RShape::Sphere(r) : t == 2 ? RShape::Capsule(r, h) : RShape::Cylinder(r, h);
          c.position_S = in.Vec(-2, 2);
          c.q_SC = in.Rotation();
          c.density = in.Decades(-1, 1);
          d.shape.children.push_back(c);
        }
        break;
      }
      case 3: {
        const double r = in.Decades(-2, 1);  // read before the half height
        d.shape = RShape::Capsule(r, in.Decades(-2, 1));
        break;
      }
      case 4: {
        const double r = in.Decades(-2, 1);  // read before the half height
        d.shape = RShape::Cylinder(r, in.Decades(-2, 1));
        break;
      }
      case 0: {
        const double x = in.Decades(-2, 1), y = in.Decades(-2, 1), z = in.Decades(-2, 1);  // in this order
        d.shape = RShape::Box(RVec3(x, y, z));
        break;
      }
      case 1:
        d.shape = RShape::Sphere(in.Decades(-2, 1));
        break;
      default: {
        d.shape.type = RShapeType::kHull;
        const double s = in.Decades(-2, 1);
        const int points = 4 + in.Byte() % 8;
        for (int k = 0; k < points; ++k) d.shape.points.push_back(s * in.Vec(-1, 1));
      }
    }
    d.kind = in.Byte() % 4 == 0 ? RBodyKind::kStatic : RBodyKind::kDynamic;
    d.mass = in.Decades(-3, 4);
    d.position_W = in.Vec(-3, 3) + (in.Byte() % 8 == 0 ? RVec3::Constant(1e7) : RVec3::Zero());
    d.q_WS = in.Rotation();
    d.velocity_W = in.Vec(-20, 20);
    d.angularVelocity_W = in.Vec(-20, 20);
    d.restitution = in.Range(0, 1);
    d.friction = in.Range(0, 1.5);
    d.responds = in.Byte() % 6 != 0;
    try {
      bodies.emplace_back(d);
    } catch (const RBodyError&) {
    }
  }
  RIntegrator integrator(settings);
  const int steps = 1 + in.Byte() % 8;
  for (int s = 0; s < steps; ++s) {
    // API calls before this step: at most 8 (and none once the input is used up, where
    // every read is 0).
    for (int call = 0; call < 8 && !bodies.empty() && !in.Empty() && in.Byte() % 3 == 0; ++call) {
      RRigidBody& b = bodies[in.Byte() % bodies.size()];
      try {
        switch (in.Byte() % 7) {
          case 0: b.AddForce_W(Vector(in)); break;
          case 1: b.AddTorque_W(Vector(in)); break;
          case 2: {
            const RVec3 j = Vector(in), p = Vector(in);
            b.AddImpulseAtPoint_W(j, p);
            break;
          }
          case 3: {
            const RVec3 f = Vector(in), p = Vector(in);
            b.AddForceAtPoint_W(f, p);
            break;
          }
          case 4: b.SetVelocity_W(Vector(in)); break;
          case 5: b.SetAngularVelocity_W(Vector(in)); break;
          default: {
            const RVec3 x = Vector(in);
            const double qw = Value(in), qx = Value(in), qy = Value(in), qz = Value(in);
            b.SetShapePose(x, RQuat(qw, qx, qy, qz));
          }
        }
      } catch (const RError&) {
      }
    }
    integrator.Update(bodies, dt);
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      RENGINE_FUZZ_CHECK(Finite(bodies[i]), "body %zu not finite after step %d", i, s);
    }
  }
  return 0;
}
