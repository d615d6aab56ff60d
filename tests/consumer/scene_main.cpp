// Reads a scene from memory through an installed REngine::Scene and runs it: one ball falling
// for one second; exits 0 when it fell g t^2 / 2.
#include <REnginePhysics/RScene.h>

#include <cmath>
#include <cstdio>

int main() {
  using namespace REngine;
  const RScene scene = ParseScene(R"({"gravity": [0, -9.81, 0], "dt": 0.0166666666666666667,
      "steps": 60, "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.5}}]})",
                                  "ball.json");
  RSceneWorld world(scene);
  RIntegrator integrator(scene.settings);
  for (std::uint64_t i = 0; i < scene.steps; ++i) integrator.Update(world.Bodies(), scene.dt);
  const double y = world.Bodies()[world.Live()[0]].Position_W().y();
  std::printf("y after 1 s: %.17g\n", y);
  return std::abs(y + 9.81 / 2) < 1e-12 ? 0 : 1;
}
