// The ranges the engine accepts at its doors, shared by every check that applies them.
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

}  // namespace REngine
