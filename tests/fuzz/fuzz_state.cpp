// LoadState (RWorldState.h) on damaged states. A world of every shape kind (box, sphere,
// capsule, cylinder, hull, a static triangle mesh, a compound), every joint kind (ball, a
// hinge and a slider with limits and motors, fixed, a distance joint with two anchors), a
// kinematic platform, a removed body (its slot free) and a disabled one, with a sleep time
// short enough that its stack falls asleep within a few steps: stepped a fuzzed number of
// steps and saved. Then the fuzzer's edits to the bytes: bits flipped, and field-aware
// overwrites (a double at any offset made NaN, an infinity, 1e300, -0 or 2e15; a 32-bit
// integer made 0xFFFFFFFF, 0, 1000 or 2^31: an index, a count, a handle or an iteration
// count), a cut; resealed (header and checksum made right, so the edits reach every record's
// checks) or not; loaded into a fresh integrator and container built the same way.
// Invariants: the state as saved loads, and saves again to the same bytes; an edited one
// loads or throws RStateError, never anything else; a refused load leaves the world as it
// was (it saves to the same bytes); a loaded world steps without crashing or touching memory
// it does not own, every body finite or reported by NonFiniteInLastStep. (A state may ask for
// up to 1000 solver passes, as a scene may; the loaded world's are capped at 20 before
// stepping, so that an input stays fast.)
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RWorldState.h>

#include "FuzzInput.h"
#include "state/RStateFormat.h"  // the header, to reseal edited states

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

using namespace REngine;
using namespace REngine::fuzz;

namespace {

RShape Box(const RVec3& half) { return RShape::Box(half); }

// The shapes, prepared once (a hull and a mesh cost more to prepare than an input to run).
struct Shapes {
  std::shared_ptr<const RPreparedShape> ground, box, ball, capsule, cylinder, hull, mesh, compound, platform;
  Shapes() {
    ground = PrepareShape(Box(RVec3(12, 0.5, 12)));
    box = PrepareShape(Box(RVec3::Constant(0.5)));
    ball = PrepareShape(RShape::Sphere(0.3));
    capsule = PrepareShape(RShape::Capsule(0.2, 0.4));
    cylinder = PrepareShape(RShape::Cylinder(0.3, 0.25));
    hull = PrepareShape(RShape::Hull({RVec3(0, 0, 0), RVec3(1, 0, 0), RVec3(0, 1, 0), RVec3(0, 0, 1), RVec3(0.6, 0.6, 0.6)}));
    mesh = PrepareShape(RShape::Mesh({RVec3(-3, 0, -3), RVec3(3, 0, -3), RVec3(3, 0.5, 3), RVec3(-3, 0.5, 3)},
                                     {{0, 1, 2}, {0, 2, 3}}));
    RCompoundChild a, b;
    a.shape = Box(RVec3(0.4, 0.1, 0.1)), a.position_S = RVec3(0, 0, 0);
    b.shape = RShape::Sphere(0.2), b.position_S = RVec3(0.5, 0, 0), b.density = 3;
    compound = PrepareShape(RShape::Compound({a, b}));
    platform = PrepareShape(Box(RVec3(1, 0.1, 1)));
  }
};

const Shapes& TheShapes() {
  static const Shapes shapes;
  return shapes;
}

RBodyHandle Add(RBodies& bodies, const char* name, const std::shared_ptr<const RPreparedShape>& shape,
                const RVec3& at, RBodyKind kind = RBodyKind::kDynamic) {
  RBodyDef d;
  d.restitution = 0.5;
  d.name = name, d.prepared = shape, d.kind = kind, d.position_W = at;
  return bodies.Add(d);
}

void Build(RBodies& bodies) {
  const Shapes& s = TheShapes();
  Add(bodies, "ground", s.ground, RVec3(0, -0.5, 0), RBodyKind::kStatic);
  // A stack resting exactly on the ground: it falls asleep after the sleep time.
  RBodyHandle below = Add(bodies, "box0", s.box, RVec3(0, 0.5, 0));
  for (int i = 1; i < 3; ++i) below = Add(bodies, i == 1 ? "box1" : "box2", s.box, RVec3(0, 0.5 + i, 0));
  Add(bodies, "ball", s.ball, RVec3(0.1, 5, 0.1));
  Add(bodies, "capsule", s.capsule, RVec3(-2, 1, 0));
  Add(bodies, "cylinder", s.cylinder, RVec3(2, 0.25, -2));
  const RBodyHandle hull = Add(bodies, "hull", s.hull, RVec3(-2, 3, 2));
  Add(bodies, "terrain", s.mesh, RVec3(8, 0, 8), RBodyKind::kStatic);
  const RBodyHandle compound = Add(bodies, "compound", s.compound, RVec3(8, 2, 8));
  RBodyDef tumbler;
  tumbler.restitution = 0.5;
  tumbler.name = "tumbler", tumbler.gravityScale = 0;
  tumbler.shape = Box(RVec3(0.2, 0.5, 0.9));
  tumbler.position_W = RVec3(0, 8, 4), tumbler.angularVelocity_W = RVec3(0.01, 3, 0.02);
  bodies.Add(tumbler);
  RBodyDef platform;
  platform.restitution = 0.5;
  platform.name = "platform", platform.prepared = s.platform, platform.kind = RBodyKind::kKinematic;
  platform.position_W = RVec3(4, 0.1, 0), platform.angularVelocity_W = RVec3(0, 1, 0);
  bodies.Add(platform);
  const RBodyHandle arm = Add(bodies, "arm", s.box, RVec3(-5, 4, 0));
  const RBodyHandle car = Add(bodies, "car", s.box, RVec3(-8, 2, 0));
  bodies.Remove(Add(bodies, "gone", s.ball, RVec3(-4, 0.3, 0)));
  bodies.Disable(Add(bodies, "parked", s.ball, RVec3(5, 5, -5)));
  // Every joint kind: a hinge to the world with limits and a motor, a ball joint, a slider
  // with limits and a motor, a weld that lets its bodies collide, a rope with two anchors.
  RJointDef hinge;
  hinge.type = RJointType::kHinge, hinge.a = arm;
  hinge.anchor_W = RVec3(-5.5, 4, 0), hinge.axis_W = RVec3(0, 0, 1);
  hinge.hasLimits = true, hinge.lower = -1, hinge.upper = 1.5;
  hinge.motor = {true, 1, 50};
  bodies.AddJoint(hinge);
  RJointDef ball;
  ball.type = RJointType::kBall, ball.a = hull, ball.b = arm, ball.anchor_W = RVec3(-3, 3.5, 1);
  bodies.AddJoint(ball);
  RJointDef slider;
  slider.type = RJointType::kSlider, slider.a = car;
  slider.anchor_W = RVec3(-8, 2, 0), slider.axis_W = RVec3(1, -1, 0);
  slider.hasLimits = true, slider.lower = -1, slider.upper = 1;
  slider.motor = {true, 0.5, 3};
  bodies.AddJoint(slider);
  RJointDef weld;
  weld.type = RJointType::kFixed, weld.a = compound, weld.b = car, weld.anchor_W = RVec3(0, 3, 4);
  weld.collideConnected = true;
  bodies.AddJoint(weld);
  RJointDef rope;
  rope.type = RJointType::kDistance, rope.a = below;
  rope.anchor_W = RVec3(0, 3, 0), rope.hasAnchorB = true, rope.anchorB_W = RVec3(0, 9, 0);
  rope.minDistance = 0, rope.maxDistance = 7;
  bodies.AddJoint(rope);
}

RWorldSettings Settings() {
  RWorldSettings s;
  s.gravity_W = RVec3(0, -9.81, 0);
  s.threads = 1;
  s.sleepTime = 0.05;  // three steps: the stack sleeps early in a run
  return s;
}

// A value a field cannot hold, or one at its edge.
double OddDouble(std::uint8_t k) {
  const double values[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity(), 1e300, -1e300, -0.0, 2e15, -1, 4, 1e-310};
  return values[k % (sizeof values / sizeof values[0])];
}
std::uint32_t OddU32(std::uint8_t k) {
  const std::uint32_t values[] = {0xFFFFFFFFu, 0, 1, 1000, 0x80000000u, 0xFFFFFFFEu, 17};
  return values[k % (sizeof values / sizeof values[0])];
}

// The world's state after each number of steps, saved once: the world is the same for
// every input, and stepping it costs more than loading and stepping a state.
constexpr int kMostSteps = 48;
const std::vector<std::uint8_t>& SavedAfter(int steps) {
  static std::vector<std::vector<std::uint8_t>> saved = [] {
    std::vector<std::vector<std::uint8_t>> states;
    RBodies source;
    Build(source);
    RIntegrator integrator(Settings());
    for (int s = 0; s < kMostSteps; ++s) {
      states.push_back(SaveState(integrator, source));
      integrator.Update(source, 1.0 / 60);
    }
    return states;
  }();
  return saved[static_cast<std::size_t>(steps)];
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const int steps = in.Byte() % kMostSteps;
  const std::uint8_t mode = in.Byte();
  const std::vector<std::uint8_t>& saved = SavedAfter(steps);
  std::vector<std::uint8_t> state = saved;
  // The edits: a kind, a 3-byte offset and a value each; then perhaps a cut.
  const int edits = in.Byte() % 8;
  for (int e = 0; e < edits; ++e) {
    const std::uint8_t kind = in.Byte() % 3;
    const std::size_t at = (in.Byte() | (std::size_t(in.Byte()) << 8) | (std::size_t(in.Byte()) << 16)) % state.size();
    const std::uint8_t value = in.Byte();
    if (kind == 0) {
      state[at] ^= value;
    } else if (kind == 1 && at + 8 <= state.size()) {
      std::uint64_t bits = 0;
      const double v = OddDouble(value);
      std::memcpy(&bits, &v, sizeof bits);
      state::StoreU64(state.data() + at, bits);
    } else if (kind == 2 && at + 4 <= state.size()) {
      const std::uint32_t v = OddU32(value);
      for (int k = 0; k < 4; ++k) state[at + k] = static_cast<std::uint8_t>(v >> (8 * k));
    }
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
  } catch (const RStateError& e) {
    RENGINE_FUZZ_CHECK(state != saved, "the state as saved was refused: %s", e.what());
    RENGINE_FUZZ_CHECK(SaveState(loaded, target) == before, "a refused load changed the world");
    return 0;
  }
  if (state == saved) RENGINE_FUZZ_CHECK(SaveState(loaded, target) == saved, "save, load, save: other bytes");
  loaded.Settings().solverIterations = std::min(loaded.Settings().solverIterations, 20);
  for (int s = 0; s < 3; ++s) {
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
