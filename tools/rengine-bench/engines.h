// rengine-bench's engines: a world built for one grid point, stepped by REngine or by Bullet
// (where it was found at build time: RENGINE_HAVE_BULLET), and read back as one state that
// both are measured on. The scenes (scenes.h) build worlds and compute errors from states.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RIntegrator.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace rbench {

using REngine::RQuat;
using REngine::RRigidBody;
using REngine::RScalar;
using REngine::RVec3;
using REngine::RWorldSettings;

// One point of the grid.
struct GridPoint {
  RScalar dt = 0;      // s
  int iterations = 0;  // contact solver passes (both engines)
  bool quick = false;  // --quick: the expensive scenes run a shorter time
};

// A world ready to step: what a scene builds for one grid point, for either engine.
struct World {
  RWorldSettings settings;
  std::vector<RRigidBody> bodies;
  RScalar dt = 0;  // s
  std::uint64_t steps = 0;
};

// A run's errors against the closed form; unset: not applicable to the scene (empty field).
struct Errors {
  std::optional<double> error, energyDrift, momentumDrift;
};

// Whole steps covering `duration` seconds: every duration and step size in the grid divide
// exactly, so this is the exact count, not a rounding of it.
inline std::uint64_t StepsFor(RScalar duration, RScalar dt) {
  return static_cast<std::uint64_t>(std::llround(duration / dt));
}

// The errors are computed from this state, read the same way from either engine: centre of
// mass, orientation of the principal frame, world velocities, and REngine's exact mass
// properties (which both engines were given).

struct BodyState {
  bool isStatic = false;
  RScalar mass = 0;                 // kg (0 when static)
  RVec3 inertia_B = RVec3::Zero();  // principal moments, kg m^2
  RVec3 x_W = RVec3::Zero();        // centre of mass, m
  RQuat q_WB = RQuat::Identity();
  RVec3 v_W = RVec3::Zero();        // m/s
  RVec3 w_W = RVec3::Zero();        // rad/s

  RVec3 Momentum_W() const { return mass * v_W; }
  // About the centre of mass, world frame, kg m^2/s.
  RVec3 SpinMomentum_W() const { return q_WB * inertia_B.cwiseProduct(q_WB.conjugate() * w_W); }
  RScalar Kinetic() const {
    const RVec3 w_B = q_WB.conjugate() * w_W;
    return RScalar(0.5) * mass * v_W.squaredNorm() +
           RScalar(0.5) * w_B.dot(inertia_B.cwiseProduct(w_B));
  }
};
using State = std::vector<BodyState>;

inline RScalar KineticEnergy(const State& s) {
  RScalar e = 0;
  for (const BodyState& b : s) e += b.Kinetic();
  return e;
}

inline RVec3 Momentum_W(const State& s) {
  RVec3 p = RVec3::Zero();
  for (const BodyState& b : s) p += b.Momentum_W();
  return p;
}

// Sum of m |v|: what a momentum drift is relative to (the total may cancel to nearly 0).
inline RScalar MomentumScale(const State& s) {
  RScalar sum = 0;
  for (const BodyState& b : s) sum += b.mass * b.v_W.norm();
  return sum;
}

// Angular momentum about the world origin, kg m^2/s, and its scale sum(|x x m v| + |L_spin|).
inline RVec3 AngularMomentumAboutOrigin_W(const State& s) {
  RVec3 l = RVec3::Zero();
  for (const BodyState& b : s) l += b.x_W.cross(b.Momentum_W()) + b.SpinMomentum_W();
  return l;
}
inline RScalar AngularMomentumScale(const State& s) {
  RScalar sum = 0;
  for (const BodyState& b : s) {
    sum += b.x_W.cross(b.Momentum_W()).norm() + b.SpinMomentum_W().norm();
  }
  return sum;
}

enum class Method { kREngine, kBullet };

inline const char* MethodName(Method m) {
  return m == Method::kREngine ? "REngine" : "bullet";
}

// One engine stepping one world. Step(n) loops inside, so timing a run costs one virtual
// call, not one per step.
class Engine {
 public:
  Engine(RScalar dt, std::uint64_t steps) : m_dt(dt), m_steps(steps) {}
  virtual ~Engine() = default;
  Engine(const Engine&) = delete;
  Engine& operator=(const Engine&) = delete;

  RScalar Dt() const { return m_dt; }
  std::uint64_t Steps() const { return m_steps; }
  virtual void Step(std::uint64_t n) = 0;
  virtual void Read(State& out) const = 0;

 private:
  RScalar m_dt;
  std::uint64_t m_steps;
};

// A new engine for the world: REngine (with sleeping off, see engines.cpp) or Bullet.
std::unique_ptr<Engine> MakeEngine(Method method, World world);

// Steps an engine through its world, calling afterStep(state, t) with the state and the time
// at the end of each step. Time is a product, not a running sum, so the contact-time checks
// of the scenes carry no accumulated rounding.
template <class AfterStep>
void Simulate(Engine& engine, AfterStep&& afterStep) {
  State state;
  for (std::uint64_t step = 1; step <= engine.Steps(); ++step) {
    engine.Step(1);
    engine.Read(state);
    afterStep(state, static_cast<RScalar>(step) * engine.Dt());
  }
}

inline State Initial(const Engine& engine) {
  State s;
  engine.Read(s);
  return s;
}

}  // namespace rbench
