// rengine-sim with the bodies' kinds and motion fields (kind, drag, gravity scale, locks):
// every bad value exits 2 naming the JSON path, a kinematic scene runs as its closed form
// says, and --describe reports what a kinematic body weighs (nothing: mass 0, as static).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "support/CliRunner.h"

using namespace REngine;
using namespace REngine::test;

TEST_F(Cli, BadBodyKindsDragScalesAndLocksExitTwoNamingThePath) {
  struct Case {
    std::string scene, mustContain;
  };
  auto one = [](const std::string& fields) { return SceneOf({{"a", kSphere + ", " + fields}}); };
  const std::vector<Case> cases = {
      {one(R"("kind": "floating")"), "bodies[0].kind: must be one of \"dynamic\", \"static\", \"kinematic\""},
      {one(R"("kind": 1)"), "bodies[0].kind"},
      {one(R"("static": true, "kind": "kinematic")"), "bodies[0].kind: contradicts \"static\": true"},
      {one(R"("static": false, "kind": "static")"), "bodies[0].kind: contradicts \"static\": false"},
      {one(R"("static": true, "kind": "dynamic")"), "bodies[0].kind"},
      {one(R"("linear_damping": -1)"), "bodies[0].linear_damping: must be a finite number >= 0"},
      {one(R"("angular_damping": -0.5)"), "bodies[0].angular_damping"},
      {one(R"("angular_damping": "fast")"), "bodies[0].angular_damping"},
      {one(R"("linear_damping": 1e999)"), "bodies[0].linear_damping"},
      {one(R"("gravity_scale": 1e999)"), "bodies[0].gravity_scale: must be a finite number"},
      {one(R"("gravity_scale": "NaN")"), "bodies[0].gravity_scale"},
      {one(R"("locks": true)"), "bodies[0].locks: must be an object"},
      {one(R"("locks": {"linear": [true, false]})"), "bodies[0].locks.linear: must be an array of 3 booleans"},
      {one(R"("locks": {"angular": [true, false, true, false]})"), "bodies[0].locks.angular"},
      {one(R"("locks": {"linear": [1, 0, 0]})"), "bodies[0].locks.linear[0]: must be true or false"},
      {one(R"("locks": {"spin": [true, true, true]})"), "bodies[0].locks.spin: unknown field"},
      {SceneOf({{"a", kSphere}}, R"("dt": 0.01, "steps": 10, "actions": [{"step": 1, "add": {"name": "b", )" +
                                      kSphere + R"(, "gravity_scale": "x"}}])"),
       "actions[0].add.gravity_scale"},
  };
  for (const Case& c : cases) {
    const Result r = Run(Quote(Write("bad.json", c.scene)) + " --out " + Quote(Path("t.csv")));
    EXPECT_EQ(r.code, 2) << c.scene;
    EXPECT_NE(r.err.find("bad.json: " + c.mustContain), std::string::npos) << r.err;
  }
}

// A kinematic slab moving at 2 m/s and spinning, given 3 m/s by an action after step 30, a
// damped ball in zero g beside it, and a body whose "static" and "kind" agree. The slab's rows
// are x0 + v t and exp(w t) exactly (1e-12); the ball's speed decays as e^(-c t) (1e-12);
// the hash is the same on one and two threads.
TEST_F(Cli, KinematicAndDampedBodiesRunAsTheirClosedForms) {
  const std::string scene = SceneOf(
      {{"slab", R"("shape": {"type": "box", "half_extents": [1, 0.1, 1]}, "kind": "kinematic",
                   "velocity": [2, 0, 0], "angular_velocity": [0, 0.5, 0], "mass": 3)"},
       {"ball", kSphere + R"(, "position": [0, 10, 0], "velocity": [0, 0, 4], "linear_damping": 0.5,
                   "angular_damping": 2, "angular_velocity": [1, 0, 0], "gravity_scale": 0)"},
       {"ground", R"("shape": {"type": "box", "half_extents": [1, 1, 1]}, "static": true,
                     "kind": "static", "position": [0, -50, 0])"}},
      R"("dt": 0.01, "steps": 60, "gravity": [0, -9.81, 0],
         "actions": [{"step": 30, "set_velocity": {"body": "slab", "velocity": [3, 0, 0]}}])");
  std::string hash[2];
  for (int threads = 1; threads <= 2; ++threads) {
    const Result r = Run(Quote(Write("k.json", scene)) + " --threads " + std::to_string(threads) +
                         " --out " + Quote(Path("t.csv")));
    ASSERT_EQ(r.code, 0) << r.err;
    hash[threads - 1] = r.LastErrLine().substr(r.LastErrLine().find("hash="));
    const std::vector<Row> rows = ParseCsv(ReadFile(Path("t.csv")));
    ASSERT_EQ(rows.size(), 61u * 3);
    for (const Row& row : rows) {
      const double t = static_cast<double>(row.step) * 0.01;
      if (row.body == "slab") {
        const double x = row.step <= 30 ? 2 * t : 0.6 + 3 * (t - 0.3);
        EXPECT_NEAR(row.state[0], x, 1e-12) << row.step;
        EXPECT_EQ(row.state[7], row.step < 30 ? 2 : 3) << row.step;  // vx, exactly as set
        EXPECT_EQ(row.state[11], 0.5);                                // wy
        EXPECT_NEAR(row.state[3], std::cos(0.25 * t), 1e-12) << row.step;  // qw of exp(w t)
      } else if (row.body == "ball") {
        EXPECT_NEAR(row.state[9], 4 * std::exp(-0.5 * t), 1e-12) << row.step;
        EXPECT_NEAR(row.state[10], std::exp(-2 * t), 1e-12) << row.step;
        EXPECT_EQ(row.state[1], 10) << "gravity scale 0";
      }
    }
  }
  EXPECT_EQ(hash[0], hash[1]);
}

// --describe: a kinematic body weighs nothing (mass 0 and no moments, as a static body); a
// body with locked axes keeps its mass and moments (only the solver's inverses are zeroed).
TEST_F(Cli, DescribeReportsKinematicBodiesAsMassless) {
  const std::string scene = SceneOf(
      {{"k", kSphere + R"(, "kind": "kinematic", "mass": 7)"},
       {"l", kSphere + R"(, "mass": 7, "locks": {"linear": [true, false, false], "angular": [false, true, true]})"}});
  const Result r = Run(Quote(Write("d.json", scene)) + " --describe");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json list = nlohmann::json::parse(r.out);
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0]["mass"].get<double>(), 0);
  EXPECT_EQ(list[0]["principal_moments"][0].get<double>(), 0);
  EXPECT_EQ(list[1]["mass"].get<double>(), 7);
  EXPECT_NEAR(list[1]["principal_moments"][0].get<double>(), 0.4 * 7 * 0.25, 1e-12);
}
