// What the contact events' suites (events_test, events_reporting_test) share: the 60 Hz
// step, gravity's g and the rounding unit.
#pragma once

#include <REngineMath/RMath.h>

#include <limits>

namespace REngine::test {

inline constexpr RScalar kDt = RScalar(1) / 60;
inline constexpr RScalar kG = 9.81;
inline constexpr RScalar kEps = std::numeric_limits<RScalar>::epsilon();

}  // namespace REngine::test
