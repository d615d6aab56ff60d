// A game's use of an installed (or embedded) REngine, built by run_consumer_test.cmake with
// the game's own SIMD flags: a ball falls, a compound and a hull are made with their closed-form
// masses and fall, and a pendulum swings on a ball joint. Exits 0 when every figure holds.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <cmath>
#include <cstdio>

namespace {
int failures = 0;
void Check(bool ok, const char* what, double got, double want) {
  std::printf("%s: %.17g (want %.17g)%s\n", what, got, want, ok ? "" : "  FAILED");
  if (!ok) ++failures;
}
}  // namespace

int main() {
  using namespace REngine;
  const double g = 9.81, dt = 1.0 / 60;
  RWorldSettings settings;
  settings.gravity_W = RVec3(0, -g, 0);

  // A ball in a plain vector of bodies: y = -g t^2 / 2 after 1 s.
  {
    RBodyDef def;
    def.restitution = 0.5;
    def.name = "ball";
    def.shape = RShape::Sphere(0.5);
    def.mass = 1.0;
    std::vector<RRigidBody> bodies{RRigidBody(def)};
    RIntegrator integrator(settings);
    for (int i = 0; i < 60; ++i) integrator.Update(bodies, dt);
    const double y = bodies[0].Position_W().y();
    Check(std::abs(y + g / 2) < 1e-12, "ball y after 1 s", y, -g / 2);
  }

  RBodies bodies;
  // A compound of two boxes side by side, densities 1 and 3 kg/m^3: mass 1 + 3 kg. Its
  // children carry quaternions (RQuat), the type whose alignment depends on SIMD flags.
  RBodyDef compound;
  compound.restitution = 0.5;
  compound.name = "compound";
  std::vector<RCompoundChild> children;
  for (int k = 0; k < 2; ++k) {
    RCompoundChild child;
    child.shape = RShape::Box(RVec3(0.5, 0.5, 0.5));
    child.position_S = RVec3(k == 0 ? -0.5 : 0.5, 0, 0);
    child.q_SC = RQuat(Eigen::AngleAxisd(0.25 * kPi, RVec3::UnitY()));
    child.density = k == 0 ? 1.0 : 3.0;
    children.push_back(child);
  }
  compound.shape = RShape::Compound(children);
  compound.position_W = RVec3(0, 10, 0);
  const RBodyHandle hc = bodies.Add(compound);

  // A hull: the cube of side 2 from its eight corners, density 2 kg/m^3: mass 16 kg.
  RBodyDef hull;
  hull.restitution = 0.5;
  hull.name = "hull";
  std::vector<RVec3> corners;
  for (int i = 0; i < 8; ++i) corners.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  hull.shape = RShape::Hull(corners);
  hull.density = 2;
  hull.position_W = RVec3(10, 10, 0);
  const RBodyHandle hh = bodies.Add(hull);

  // A pendulum: a 1 kg ball on a ball joint to the world, 2 m from its anchor, released
  // horizontally. The joint holds the distance; the ball swings down.
  RBodyDef bob;
  bob.restitution = 0.5;
  bob.name = "bob";
  bob.shape = RShape::Sphere(0.1);
  bob.mass = 1.0;
  bob.position_W = RVec3(22, 10, 0);
  const RBodyHandle hb = bodies.Add(bob);
  RJointDef joint;
  joint.type = RJointType::kBall;
  joint.a = hb;
  joint.anchor_W = RVec3(20, 10, 0);
  bodies.AddJoint(joint);

  Check(std::abs(bodies[hc].Mass() - 4) < 1e-12, "compound mass", bodies[hc].Mass(), 4);
  Check(std::abs(bodies[hh].Mass() - 16) < 1e-12, "hull mass", bodies[hh].Mass(), 16);
  RIntegrator integrator(settings);
  for (int i = 0; i < 60; ++i) integrator.Update(bodies, dt);
  const double yc = bodies[hc].Position_W().y(), yh = bodies[hh].Position_W().y();
  Check(std::abs(yc - (10 - g / 2)) < 1e-11, "compound y after 1 s", yc, 10 - g / 2);
  Check(std::abs(yh - (10 - g / 2)) < 1e-11, "hull y after 1 s", yh, 10 - g / 2);
  const double r = (bodies[hb].Position_W() - RVec3(20, 10, 0)).norm();
  // The joint solver closes each step with the anchors within 1e-10 m of each other.
  Check(std::abs(r - 2) < 1e-9, "pendulum length after 1 s", r, 2);
  Check(bodies[hb].Position_W().y() < 9, "pendulum bob height after 1 s (swung down)",
        bodies[hb].Position_W().y(), 9);
  return failures == 0 ? 0 : 1;
}
