// Surfaces through the simulator, against what their geometry says: a box sliding across
// flush static tiles, and across the box children of one compound body, keeps its speed
// and height (to 1e-9, as on one floor); a capsule hitting a 5 cm plate obliquely at
// 2500 m/s never passes its mid-plane.
#include "support/CliRunner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace REngine::test;

namespace {

// Six tiles 1 m long (half extents 0.5, 0.1, 2) from x = 0, their tops at y = 0: separate
// static boxes, or the children of one static compound.
std::vector<std::pair<std::string, std::string>> Tiles(bool compound) {
  const std::string tile = R"("shape": {"type": "box", "half_extents": [0.5, 0.1, 2]})";
  std::vector<std::pair<std::string, std::string>> bodies;
  if (compound) {
    std::string children;
    for (int k = 0; k < 6; ++k) {
      children += std::string(k ? ", " : "") + R"({"shape": {"type": "box", "half_extents": [0.5, 0.1, 2]}, "position": [)" +
                  std::to_string(k + 0.5) + ", -0.1, 0]}";
    }
    bodies.push_back({"deck", R"("kind": "static", "friction": 0, "shape": {"type": "compound", "children": [)" +
                                  children + "]}"});
  } else {
    for (int k = 0; k < 6; ++k) {
      bodies.push_back({"tile" + std::to_string(k),
                        tile + R"(, "kind": "static", "friction": 0, "position": [)" + std::to_string(k + 0.5) + ", -0.1, 0]"});
    }
  }
  return bodies;
}

}  // namespace

// A frictionless box 0.4 m tall sliding at 5 m/s under gravity across five seams in 60
// steps: its velocity (5, 0, 0) and its height 0.2 m at every step, to 1e-9, as on one floor.
TEST_F(Cli, ABoxSlidesAcrossFlushTilesAsAcrossOneFloor) {
  for (const bool compound : {false, true}) {
    std::vector<std::pair<std::string, std::string>> bodies = Tiles(compound);
    bodies.push_back({"box", R"("shape": {"type": "box", "half_extents": [0.3, 0.2, 0.25]}, "mass": 1,
                               "friction": 0, "restitution": 0, "position": [0.4, 0.2, 0], "velocity": [5, 0, 0])"});
    const std::string scene = SceneOf(bodies, R"("dt": 0.016666666666666666, "steps": 60,
        "gravity": [0, -9.81, 0], "solver": {"sleeping": false})");
    const std::string name = compound ? "compound_tiles" : "tiles";
    const Result r = Run(Quote(Write(name + ".json", scene)) + " --out " + Quote(Path(name + ".csv")));
    ASSERT_EQ(r.code, 0) << r.err;
    double speed = 0, height = 0, last = 0;
    for (const Row& row : RowsOf(ParseCsv(ReadFile(Path(name + ".csv"))), "box")) {
      speed = std::max({speed, std::abs(row.state[7] - 5), std::abs(row.state[8]), std::abs(row.state[9])});
      height = std::max(height, std::abs(row.state[1] - 0.2));
      last = row.state[0];
    }
    std::printf("box across %s: velocity off (5, 0, 0) by %.3g m/s, height off 0.2 m by %.3g m\n", name.c_str(), speed,
                height);
    EXPECT_LT(speed, 1e-9) << name;
    EXPECT_LT(height, 1e-9) << name;
    EXPECT_GT(last, 5) << name;  // it crossed the seams at x = 1 to 5
  }
}

// A capsule (radius 0.1 m, 1 m long) flying nose first at 2500 m/s, 30 degrees below the
// horizontal, onto a static plate 5 cm thick: the impact spins it up, and it must bounce
// off the plate's face, inelastic or elastic, never crossing its mid-plane y = 0.
TEST_F(Cli, ACapsuleHittingAThinPlateAt2500MetresASecondStaysOnItsSide) {
  const double speed = 2500, angle = M_PI / 6, dt = 1.0 / 60;
  const double vx = speed * std::cos(angle), vy = -speed * std::sin(angle);
  // Half a step's flight above the plate: it hits in the middle of the first step.
  const double y0 = 0.025 + 0.6 + 0.5 * speed * std::sin(angle) * dt;
  for (const double e : {0.0, 1.0}) {
    char capsule[400];
    // The capsule's axis (its shape's y) turned -120 degrees about z, onto the velocity.
    std::snprintf(capsule, sizeof capsule,
                  R"("shape": {"type": "capsule", "radius": 0.1, "half_height": 0.4}, "mass": 1, "friction": 0.5,
                     "restitution": %g, "position": [-150, %.17g, 0], "orientation": [0.5, 0, 0, -0.8660254037844386],
                     "velocity": [%.17g, %.17g, 0])",
                  e, y0, vx, vy);
    char plate[200];
    std::snprintf(plate, sizeof plate,
                  R"("shape": {"type": "box", "half_extents": [240, 0.025, 240]}, "kind": "static", "restitution": %g)", e);
    const std::string scene = SceneOf({{"plate", plate}, {"capsule", capsule}}, R"("dt": 0.016666666666666666, "steps": 20)");
    const std::string name = e == 0 ? "plate_inelastic" : "plate_elastic";
    const Result r = Run(Quote(Write(name + ".json", scene)) + " --out " + Quote(Path(name + ".csv")));
    ASSERT_EQ(r.code, 0) << r.err;
    double lowest = y0;
    for (const Row& row : RowsOf(ParseCsv(ReadFile(Path(name + ".csv"))), "capsule")) {
      if (std::abs(row.state[0]) < 240 && std::abs(row.state[2]) < 240) lowest = std::min(lowest, row.state[1]);
    }
    std::printf("capsule at 2500 m/s, 30 degrees, e = %g: lowest centre %.4g m (the plate's mid-plane at 0)\n", e, lowest);
    EXPECT_GT(lowest, 0) << "e = " << e;
  }
}
