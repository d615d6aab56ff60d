// Drops a ball for one second through an installed REngine; exits 0 when it fell g t^2 / 2.
#include <REnginePhysics/RIntegrator.h>

#include <cmath>
#include <cstdio>

int main() {
  using namespace REngine;
  RBodyDef def;
  def.name = "ball";
  def.shape.type = RShapeType::kSphere;
  def.shape.radius = 0.5;
  def.mass = 1.0;
  std::vector<RRigidBody> bodies{RRigidBody(def)};
  RWorldSettings settings;
  settings.gravity_W = RVec3(0, -9.81, 0);
  RIntegrator integrator(settings);
  for (int i = 0; i < 60; ++i) integrator.Update(bodies, 1.0 / 60);
  const double y = bodies[0].Position_W().y();
  std::printf("y after 1 s: %.17g\n", y);
  return std::abs(y + 9.81 / 2) < 1e-12 ? 0 : 1;
}
