// What the joint suites (joints_test, joints_api_test, the joints_adversarial tests) share:
// the 60 Hz step, gravity along -y, and the energy of the moving bodies in that gravity.
#pragma once

#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include "support/Joints.h"

namespace REngine::test {

inline constexpr RScalar kDt = 1.0 / 60;
inline constexpr RScalar kG = 9.81;

inline RWorldSettings Gravity() { return GravityAlongMinusY(kG); }

// Kinetic plus potential energy (gravity along -y) of the enabled dynamic bodies.
inline RScalar Energy(const RBodies& bodies) {
  RScalar E = 0;
  for (const RRigidBody& b : bodies) {
    if (b.IsStatic() || b.IsKinematic()) continue;
    E += b.LinearKineticEnergy() + b.RotationalKineticEnergy() + b.Mass() * kG * b.Position_W().y();
  }
  return E;
}

}  // namespace REngine::test
