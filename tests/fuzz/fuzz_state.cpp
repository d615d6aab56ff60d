// LoadState (RWorldState.h) on damaged states: a small world (a stack on the ground, a
// tumbling general-inertia box, a sphere, a kinematic platform, a removed body) stepped a
// fuzzed number of steps and saved; then the fuzzer's edits to the bytes (bits flipped, a
// cut, any length), resealed (header and checksum made right, so the edits reach every
// record's checks) or not, loaded into a fresh integrator and container built the same way.
// Invariants: the load succeeds or throws RStateError, never anything else; a refused load
// leaves the world as it was (it saves to the same bytes); a loaded world steps without
// crashing, every body finite or reported by NonFiniteInLastStep. (Solver iterations are a
// setting the state carries like any other, and a state may ask for 2^31 of them as a scene
// may: they are capped before stepping, as rengine-sim's --max-seconds would.)
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RWorldState.h>

#include "FuzzInput.h"
#include "RStateFormat.h"  // the header, to reseal edited states

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

using namespace REngine;
using namespace REngine::fuzz;

namespace {

void Build(RBodies& bodies) {
  RBodyDef ground;
  ground.name = "ground", ground.isStatic = true;
  ground.shape.type = RShapeType::kBox, ground.shape.halfExtents = RVec3(10, 0.5, 10);
  ground.position_W = RVec3(0, -0.5, 0);
  bodies.Add(ground);
  for (int i = 0; i < 3; ++i) {
    RBodyDef box;
    box.name = "box" + std::to_string(i);
    box.shape.type = RShapeType::kBox, box.shape.halfExtents = RVec3::Constant(0.5);
    box.position_W = RVec3(0.05 * i, 0.5 + 1.01 * i, 0);
    bodies.Add(box);
  }
  RBodyDef tumbler;
  tumbler.name = "tumbler", tumbler.gravityScale = 0;
  tumbler.shape.type = RShapeType::kBox, tumbler.shape.halfExtents = RVec3(0.2, 0.5, 0.9);
  tumbler.position_W = RVec3(0, 8, 4), tumbler.angularVelocity_W = RVec3(0.01, 3, 0.02);
  bodies.Add(tumbler);
  RBodyDef ball;
  ball.name = "ball", ball.shape.radius = 0.3, ball.position_W = RVec3(0.1, 5, 0.1);
  bodies.Add(ball);
  RBodyDef platform;
  platform.name = "platform", platform.kind = RBodyKind::kKinematic;
  platform.shape.type = RShapeType::kBox, platform.shape.halfExtents = RVec3(1, 0.1, 1);
  platform.position_W = RVec3(4, 0.1, 0), platform.angularVelocity_W = RVec3(0, 1, 0);
  bodies.Add(platform);
  RBodyDef gone = ball;
  gone.name = "gone", gone.position_W = RVec3(-4, 0.3, 0);
  bodies.Remove(bodies.Add(gone));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const int steps = in.Byte() % 48;
  const std::uint8_t mode = in.Byte();
  RBodies source;
  Build(source);
  RIntegrator integrator(RWorldSettings{});
  integrator.Settings().gravity_W = RVec3(0, -9.81, 0);
  integrator.Settings().threads = 1;
  for (int s = 0; s < steps; ++s) integrator.Update(source, 1.0 / 60);
  std::vector<std::uint8_t> state = SaveState(integrator, source);
  // The edits: (offset, xor) pairs, then perhaps a cut.
  const int edits = in.Byte() % 8;
  for (int e = 0; e < edits; ++e) {
    const std::size_t at = (in.Byte() | (std::size_t(in.Byte()) << 8) | (std::size_t(in.Byte()) << 16)) % state.size();
    state[at] ^= in.Byte();
  }
  if (mode & 1) state.resize((in.Byte() | (std::size_t(in.Byte()) << 8) | (std::size_t(in.Byte()) << 16)) % (state.size() + 1));
  if ((mode & 2) && state.size() >= state::kHeaderBytes) state::Seal(state);

  RBodies target;
  Build(target);
  RIntegrator loaded(RWorldSettings{});
  loaded.Settings().threads = 1;
  const std::vector<std::uint8_t> before = SaveState(loaded, target);
  try {
    LoadState(loaded, target, state);
  } catch (const RStateError&) {
    RENGINE_FUZZ_CHECK(SaveState(loaded, target) == before, "a refused load changed the world");
    return 0;
  }
  loaded.Settings().solverIterations = std::min(loaded.Settings().solverIterations, 20);
  for (int s = 0; s < 5; ++s) {
    loaded.Update(target, 1.0 / 60);
    for (std::size_t i = 0; i < target.EnabledCount(); ++i) {
      const RRigidBody& b = target.At(i);
      bool reported = false;
      for (const RNonFiniteBody& nf : loaded.NonFiniteInLastStep()) reported = reported || nf.bodyIndex == i;
      RENGINE_FUZZ_CHECK(reported || (AllFinite(b.Position_W()) && AllFinite(b.Velocity_W()) &&
                                      AllFinite(b.Orientation_WB()) && AllFinite(b.AngularVelocity_B())),
                         "body %zu not finite after step %d of a loaded world", i, s);
    }
  }
  return 0;
}
