// The ranges the engine accepts at its doors, shared by every check that applies them: the
// API, the scene loader and the state loader refuse what lies outside them (RBodyError,
// RJointError, RSceneError, RStateError). A game may check its own input against them.
#pragma once

#include <REngineMath/RMath.h>

namespace REngine {

// Positions: 1e15 m (6700 au) is beyond any game, and squared distances there (1e30) are far
// from overflowing; at 1e185 m they overflow, and a sphere pair's distance came out infinite
// (found by fuzz_narrowphase).
inline constexpr RScalar kMaxPosition = 1e15;
// Shape points (hull points, mesh vertices) further than this from the shape frame's origin
// are refused: beyond it the squares in Qhull's and the mass properties' arithmetic leave the
// doubles (Qhull crashed on points of 1e300). 1e12 m is far beyond any game object, and its
// squares stay finite.
inline constexpr RScalar kMaxCoordinate = 1e12;
// Points and offsets a saved state keeps in a body's frame or between two bodies (a joint's
// anchor from a body's centre, a remembered contact point): the distance between two points
// within kMaxPosition of the origin, measured along any axis, is within 4e15 m.
inline constexpr RScalar kMaxSpan = 4e15;
// Impulses a saved state remembers (contact warm starts, joints' last impulses), N s or N m s:
// a step that keeps every body within the ranges above computes impulses far below 1e30 (a
// body of 1e12 kg at 1e18 m/s), and squares of 1e30 stay finite in the solver's arithmetic;
// 1e300 in an edited state would overflow the first step.
inline constexpr RScalar kMaxImpulse = 1e30;
// The game's impulses are held to the same bound, each component (RRigidBody::AddImpulse_W
// and its kin, the scene's impulse action): one of 1e300 flung a body to 1e299 m in a step
// with nothing reported. A motor's max_force too (N or N m): over a step of at most
// RIntegrator::kMaxDt (1 s) its impulse stays within kMaxImpulse, as a saved state's must.
inline constexpr RScalar kMaxMotorForce = kMaxImpulse;
// A motor's target speed (m/s for a slider, rad/s for a hinge): a slider beyond 1e15 m/s
// would cross the whole world (kMaxPosition) within one step; no game drives one faster.
inline constexpr RScalar kMaxMotorSpeed = 1e15;

}  // namespace REngine
