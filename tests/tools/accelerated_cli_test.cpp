// Motion under acceleration through the simulator, against closed forms: a ball bouncing
// under gravity (flight heights h e^(2n), rest at the Zeno time), a damped body falling
// (the exact flow of dv/dt = g - c v), and a crate on a spinning station's deck (no sink).
#include "support/CliRunner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace REngine::test;

namespace {
constexpr double kG = 9.81;
}  // namespace

// The scene format's solver.restitution_threshold set to 1 mm/s, so the ball bounces until
// under a step before the Zeno time t1 (1 + e)/(1 - e); every flight's energy height
// y - r + v^2/(2g) is h e^(2n) after the n-th bounce, to rounding (1e-9 of h asked).
TEST_F(Cli, BallBouncesUnderGravityAsTheClosedFormSays) {
  const double h = 5, e = 0.8, dt = 1.0 / 60;
  const std::string scene = SceneOf(
      {{"ground", R"("shape": {"type": "box", "half_extents": [5, 0.5, 5]}, "kind": "static",
                     "position": [0, -0.5, 0], "restitution": 1, "friction": 0)"},
       {"ball", kSphere + R"(, "position": [0, 5.5, 0], "mass": 2, "restitution": 0.8, "friction": 0)"}},
      R"("dt": 0.016666666666666666, "steps": 600, "gravity": [0, -9.81, 0],
         "solver": {"restitution_threshold": 0.001})");
  const Result r = Run(Quote(Write("bounce.json", scene)) + " --out " + Quote(Path("bounce.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  const double t1 = std::sqrt(2 * h / kG), zeno = t1 * (1 + e) / (1 - e);
  auto bouncesBy = [&](double t) {
    int n = 0;
    double tn = t1, flight = 2 * t1 * e;
    while (tn <= t && n < 10000) ++n, tn += flight, flight *= e;
    return n;
  };
  double worst = 0;
  int rest = 0, flights = 0;
  for (const Row& row : ParseCsv(ReadFile(Path("bounce.csv")))) {
    if (row.body != "ball") continue;
    const double t = static_cast<double>(row.step) * dt;
    const double y = row.state[1], vy = row.state[8];
    if (t < zeno - dt) {
      const int n = bouncesBy(t);
      flights = std::max(flights, n);
      worst = std::max(worst, std::abs(y - 0.5 + vy * vy / (2 * kG) - h * std::pow(e, 2 * n)) / h);
    } else if (t >= zeno + dt) {
      EXPECT_NEAR(vy, 0, 1e-9) << "step " << row.step;
      ++rest;
    }
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(flights, 20);
  EXPECT_GT(rest, 0);
}

// A damped body falling: v(t) = g/c + (v0 - g/c) e^(-ct), and the position is the exact
// flow's, x0 + g t / c + (v0 - g/c)(1 - e^(-ct))/c, to rounding (1e-12 of the distance).
TEST_F(Cli, DampedFallFollowsTheExactFlow) {
  const double c = 0.4, v0 = 3, dt = 0.01;
  const std::string scene =
      SceneOf({{"ball", kSphere + R"(, "position": [0, 100, 0], "velocity": [0, 3, 0], "linear_damping": 0.4)"}},
              R"("dt": 0.01, "steps": 500, "gravity": [0, -9.81, 0])");
  const Result r = Run(Quote(Write("drag.json", scene)) + " --out " + Quote(Path("drag.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  double worst = 0;
  for (const Row& row : ParseCsv(ReadFile(Path("drag.csv")))) {
    const double t = static_cast<double>(row.step) * dt, g = -kG;
    const double y = 100 + g * t / c + (v0 - g / c) * -std::expm1(-c * t) / c;
    worst = std::max(worst, std::abs(row.state[1] - y) / (1 + std::abs(y - 100)));
  }
  EXPECT_LT(worst, 1e-12);
}

// A crate resting on the inside of a spinning station's rim (a kinematic compound ring of
// radius R = 39.24 m turning at w about z, zero gravity: 1 g at 0.5 rad/s, 4 g at 1): the
// deck holds it on its circle with m w^2 R alone. Read from the trajectory: its bottom face
// never beyond the deck by more than the contact slop (0.5 mm, the engine's default), and
// after the first second its velocity relative to the deck's surface under it has no
// normal part (to 1e-9 m/s).
TEST_F(Cli, ACrateRestsOnASpinningDeckWithoutSinking) {
  const double R = 39.24, half = 0.5, slop = 5e-4, dt = 1.0 / 60;
  for (const double w : {0.5, 1.0}) {
    char station[600], crate[400];
    std::snprintf(station, sizeof station,
                  R"("kind": "kinematic", "friction": 0.5, "angular_velocity": [0, 0, %g], "shape": {"type": "compound",
                     "children": [{"shape": {"type": "box", "half_extents": [4, 0.5, 4]}, "position": [0, %.17g, 0]},
                                  {"shape": {"type": "box", "half_extents": [4, 0.5, 4]}, "position": [0, %.17g, 0]}]})",
                  w, -R - 0.5, R + 0.5);
    std::snprintf(crate, sizeof crate,
                  R"("shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 2, "friction": 0.5,
                     "position": [0, %.17g, 0], "velocity": [%.17g, 0, 0], "angular_velocity": [0, 0, %g])",
                  -R + half, w * (R - half), w);
    const std::string scene = SceneOf({{"station", station}, {"crate", crate}},
                                      R"("dt": 0.016666666666666666, "steps": 600, "gravity": [0, 0, 0])");
    const std::string name = w == 0.5 ? "deck_1g" : "deck_4g";
    const Result r = Run(Quote(Write(name + ".json", scene)) + " --out " + Quote(Path(name + ".csv")));
    ASSERT_EQ(r.code, 0) << r.err;
    double sink = 0, normal = 0;
    for (const Row& row : RowsOf(ParseCsv(ReadFile(Path(name + ".csv"))), "crate")) {
      const double x = row.state[0], y = row.state[1], rho = std::hypot(x, y);
      sink = std::max(sink, rho + half - R);
      // The deck's velocity at the crate, w x (x, y, 0), against the crate's, along the radius.
      const double deckX = -w * y, deckY = w * x;
      if (static_cast<double>(row.step) * dt > 1) {
        normal = std::max(normal, std::abs(((row.state[7] - deckX) * x + (row.state[8] - deckY) * y) / rho));
      }
    }
    std::printf("deck at %g rad/s through rengine-sim: sunk up to %.3g m, normal velocity up to %.3g m/s\n", w, sink,
                normal);
    EXPECT_LE(sink, slop * (1 + 1e-9)) << "w " << w;
    EXPECT_LT(normal, 1e-9) << "w " << w;
  }
}
