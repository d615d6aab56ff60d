// The save-and-load check the shape suites share: a world saved mid-run and loaded into
// another made the same way continues bit for bit. Header-only.
#pragma once

#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RWorldState.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace REngine::test {

// Two worlds from build(bodies) under gravity: the first steps `before` times (1/60 s), is
// saved and loaded into the second, then both step `after` times; every body's pose must be
// the same bit for bit. Returns the most contacts the first world had after the load.
template <class Build>
std::size_t ExpectSavedWorldContinues(const Build& build, int before, int after) {
  RWorldSettings settings;
  settings.gravity_W = RVec3(0, -9.81, 0);
  std::vector<RRigidBody> a, b;
  build(a), build(b);
  RIntegrator ia(settings), ib(settings);
  for (int k = 0; k < before; ++k) ia.Update(a, 1.0 / 60);
  LoadState(ib, b, SaveState(ia, a));
  std::size_t most = 0;
  for (int k = 0; k < after; ++k) {
    ia.Update(a, 1.0 / 60), ib.Update(b, 1.0 / 60);
    most = std::max(most, ia.Contacts().size());
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].Position_W(), b[i].Position_W()) << i;
    EXPECT_EQ(a[i].Orientation_WB().coeffs(), b[i].Orientation_WB().coeffs()) << i;
  }
  return most;
}

}  // namespace REngine::test
