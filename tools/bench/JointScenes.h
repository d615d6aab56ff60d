// bench_joints' scenes (bench_joints_scenes.cpp): each built in REngine (Bullet's twin is
// made from its bodies and joints), observed after every step through the bodies' states,
// and summed up in figures computed the same way for both engines.
#pragma once

#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace REngine::bench {

inline constexpr RScalar kDt = 1.0 / 60;
inline constexpr RScalar kG = 9.81;

// One body's state after a step, as both engines report it, with its mass properties.
struct State {
  RVec3 x = RVec3::Zero();  // centre of mass, world
  RQuat q = RQuat::Identity();  // body frame (principal axes) to world
  RVec3 v = RVec3::Zero(), w = RVec3::Zero();
  RScalar m = 0;
  RVec3 I_B = RVec3::Zero();  // principal moments
  RVec3 L() const { return q * I_B.cwiseProduct(q.conjugate() * w); }  // about the centre
  RScalar Kinetic() const { return 0.5 * m * v.squaredNorm() + 0.5 * w.dot(L()); }
};

struct Figure {
  std::string name;  // what and its unit
  RScalar value = 0;
};

// A joint's anchors in its bodies' frames (the same in both engines), to measure its gap.
struct Anchor {
  std::size_t a = 0, b = 0;
  bool world = false;       // b is the world: anchorB is a world point
  RVec3 anchorA_B, anchorB_B;
  RScalar Gap(const std::vector<State>& s) const {
    const RVec3 pA = s[a].x + s[a].q * anchorA_B;
    const RVec3 pB = world ? anchorB_B : RVec3(s[b].x + s[b].q * anchorB_B);
    return (pA - pB).norm();
  }
};

inline std::size_t DenseOf(const RBodies& bodies, RBodyHandle h) {
  return static_cast<std::size_t>(&bodies[h] - bodies.begin());
}

// A scene: its bodies and joints (built in REngine; Bullet's twin is made from them), how
// many steps, and what is measured. Begin is called before each run, Observe after each step
// with the step's number (1-based) and the states, Figures at the end.
class Scene {
 public:
  virtual ~Scene() = default;
  std::string name, title;
  RVec3 gravity = RVec3(0, -kG, 0);
  int steps = 0;
  virtual void Build(RBodies& bodies) = 0;
  virtual void Begin(const std::vector<State>& /*initial*/) {}
  virtual void Observe(int step, const std::vector<State>& s) = 0;
  virtual std::vector<Figure> Figures() const = 0;
};

// The six scenes, in the order bench_joints runs them: pendulum, motor, chain, rope, slider
// and weld.
std::vector<std::unique_ptr<Scene>> JointScenes();

}  // namespace REngine::bench
