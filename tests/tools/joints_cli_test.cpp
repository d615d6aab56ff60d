// Scenes with joints run through rengine-sim (docs/scene-format.md, "Joints"), their trajectory
// CSV checked against closed forms at 60 Hz: a ball hung from the world by a ball joint
// swings with the physical pendulum's period, a brake-motored slider on an incline runs down
// at g sin(a) - F / m and stops at its limit, a rope stops a falling weight at its length, a
// removed body frees what its joint held; and bad joints exit 2 naming the JSON path.
#include <REngineMath/RMath.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/CliRunner.h"
#include "support/Joints.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr double kG = 9.81;
constexpr double kDt = 1.0 / 60;

}  // namespace

// A 2 kg ball of radius 0.2 m hung 1 m below a ball joint to the world and released from
// 0.2 rad. The joint holds a point of the ball, so the ball turns with the swing (its
// velocity is w x r about the pivot): a physical pendulum of moment I = 2/5 m R^2 + m L^2
// about the pivot, whose period is 2 pi sqrt(I / (m g L)) times 2 K(sin(theta0 / 2)) / pi.
// Measured from the CSV's zero crossings of x over 20 periods, asserted to 1e-3; the
// length, the rolling-with-the-swing and the energy from every row.
TEST_F(Cli, BallJointPendulumSwingsWithThePhysicalPendulumsPeriod) {
  const double L = 1, R = 0.2, m = 2, theta0 = 0.2;
  const RVec3 pivot(0, 2, 0);
  const RVec3 start = pivot + L * RVec3(std::sin(theta0), -std::cos(theta0), 0);
  const double I = 0.4 * m * R * R + m * L * L;
  const double period = 2 * kPi * std::sqrt(I / (m * kG * L)) * 2 * CompleteEllipticK(std::sin(theta0 / 2)) / kPi;
  const int steps = static_cast<int>(std::ceil(20.5 * period / kDt));
  const std::string scene = R"({"gravity": [0, -9.81, 0], "dt": )" + Number(kDt) + R"(, "steps": )" +
                            std::to_string(steps) + R"(, "bodies": [
      {"name": "bob", "shape": {"type": "sphere", "radius": 0.2}, "mass": 2, "position": )" +
                            Vec(start) + R"(}],
    "joints": [{"name": "pivot", "type": "ball", "a": "bob", "anchor": [0, 2, 0]}]})";
  const Result r = Run(Quote(Write("pendulum.json", scene)) + " --out " + Quote(Path("t.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> rows = ParseCsv(ReadFile(Path("t.csv")));
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(steps + 1));

  std::vector<double> crossings;  // times x goes from + to - (interpolated)
  double worstLength = 0, worstTurn = 0, worstEnergy = 0;
  const double swing = m * kG * L * (1 - std::cos(theta0));  // J
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const RVec3 x = Position(rows[k]), v = Velocity(rows[k]), w = AngularVelocity(rows[k]);
    if (k > 0) {
      const double x0 = rows[k - 1].state[0], x1 = x.x();
      if (x0 > 0 && x1 <= 0) crossings.push_back(rows[k - 1].time + x0 / (x0 - x1) * kDt);
    }
    worstLength = std::max(worstLength, std::abs((x - pivot).norm() - L));
    worstTurn = std::max(worstTurn, (v - w.cross(x - pivot)).norm());
    const double energy = 0.5 * m * v.squaredNorm() + 0.5 * (0.4 * m * R * R) * w.squaredNorm() +
                          m * kG * (x.y() - (pivot.y() - L));
    worstEnergy = std::max(worstEnergy, std::abs(energy - swing) / swing);
  }
  ASSERT_GE(crossings.size(), 21u);
  const double measured = (crossings[20] - crossings[0]) / 20;
  std::printf("pendulum (CSV): period %.9f s, closed form %.9f s (rel %.2e); length within %.2e m; "
              "v - w x r within %.2e m/s; energy within %.2e of the swing's\n",
              measured, period, measured / period - 1, worstLength, worstTurn, worstEnergy);
  EXPECT_NEAR(measured / period, 1, 1e-3);
  EXPECT_LT(worstLength, 1e-6);
  EXPECT_LT(worstTurn, 1e-6);
  EXPECT_LT(worstEnergy, 1e-3);
  // It swings in its plane.
  for (const Row& row : rows) ASSERT_LT(std::abs(row.state[2]), 1e-9) << "step " << row.step;
}

// A 4 kg crate on a slider to the world along the incline (2, -1, 0) (sin a = 1 / sqrt 5 of
// g along it), braked by a motor of speed 0 and at most F = 5 N, which is less than
// m g sin a = 17.5 N: it runs down at a = g sin a - F / m from rest, v = a t and
// s = a t^2 / 2, and stops at its upper limit, 2 m of travel, where it stays; it never
// leaves the axis nor turns. The motor's impulse of a step, F dt, is split about the step's
// drift as gravity's is (kick-drift-kick, exact for constant forces): the speed and the travel
// are exact at every row.
TEST_F(Cli, BrakedSliderRunsDownAtGSinAMinusFOverMAndStopsAtItsLimit) {
  const double m = 4, F = 5, limit = 2;
  const RVec3 axis = RVec3(2, -1, 0).normalized();
  const double a = kG * (-axis.y()) - F / m;
  const RVec3 start(1, 3, -2);
  const std::string scene = R"({"gravity": [0, -9.81, 0], "dt": )" + Number(kDt) + R"(, "steps": 120,
    "bodies": [{"name": "crate", "shape": {"type": "box", "half_extents": [0.4, 0.3, 0.5]}, "mass": 4,
                "position": [1, 3, -2]}],
    "joints": [{"name": "rail", "type": "slider", "a": "crate", "anchor": [1, 3, -2], "axis": [2, -1, 0],
                "limits": [-0.5, 2], "motor": {"speed": 0, "max_force": 5}}]})";
  const Result r = Run(Quote(Write("slider.json", scene)) + " --out " + Quote(Path("t.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> rows = ParseCsv(ReadFile(Path("t.csv")));
  ASSERT_EQ(rows.size(), 121u);
  const double reach = std::sqrt(2 * limit / a);  // s: when the limit is reached
  double worstLag = 0, worstSpeed = 0, worstStopped = 0, worstOffAxis = 0, worstTurn = 0;
  int free = 0, stopped = 0;
  for (const Row& row : rows) {
    const RVec3 d = Position(row) - start;
    const double s = d.dot(axis);
    worstOffAxis = std::max(worstOffAxis, (d - s * axis).norm());
    worstTurn = std::max({worstTurn, std::abs(row.state[3] - 1), AngularVelocity(row).norm()});
    if (row.time < reach - kDt) {
      worstLag = std::max(worstLag, std::abs(s - 0.5 * a * row.time * row.time));
      worstSpeed = std::max(worstSpeed, std::abs(Velocity(row).dot(axis) - a * row.time));
      ++free;
    } else if (row.time > reach + kDt) {
      worstStopped = std::max({worstStopped, std::abs(s - limit), Velocity(row).norm()});
      ++stopped;
    }
  }
  std::printf("slider (CSV): a = %.6f m/s^2; v = a t within %.2e m/s and s = a t^2 / 2 within %.3e m over %d rows; "
              "at the limit within %.2e over %d rows; off the axis %.2e m, turned %.2e\n",
              a, worstSpeed, worstLag, free, worstStopped, stopped, worstOffAxis, worstTurn);
  EXPECT_GT(free, 50);
  EXPECT_GT(stopped, 40);
  EXPECT_LT(worstSpeed, 1e-9);
  EXPECT_LT(worstLag, 1e-9);
  EXPECT_LT(worstStopped, 1e-6);
  EXPECT_LT(worstOffAxis, 1e-9);
  EXPECT_LT(worstTurn, 1e-9);
}

// A 5 kg weight on a 2 m rope (a distance joint, min_distance 0) to the world, released 1 m
// below the rope's hook: it falls freely (y = y0 - g t^2 / 2) until the rope is taut at
// t = sqrt(2 / g), then hangs at 2 m without bouncing back.
TEST_F(Cli, RopeLetsItsWeightFallFreelyAndHoldsItAtItsLength) {
  const RVec3 hook(0, 5, 0);
  const double L = 2, y0 = 4;
  const std::string scene = R"({"gravity": [0, -9.81, 0], "dt": )" + Number(kDt) + R"(, "steps": 120,
    "bodies": [{"name": "weight", "shape": {"type": "sphere", "radius": 0.1}, "mass": 5, "position": [0, 4, 0]}],
    "joints": [{"name": "rope", "type": "distance", "a": "weight", "anchor": [0, 4, 0], "anchor_b": [0, 5, 0],
                "min_distance": 0, "max_distance": 2}]})";
  const Result r = Run(Quote(Write("rope.json", scene)) + " --out " + Quote(Path("t.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> rows = ParseCsv(ReadFile(Path("t.csv")));
  ASSERT_EQ(rows.size(), 121u);
  const double taut = std::sqrt(2 * (y0 - (hook.y() - L)) / kG);
  double worstFall = 0, worstHang = 0, longest = 0;
  int falling = 0, hanging = 0;
  for (const Row& row : rows) {
    const RVec3 x = Position(row);
    longest = std::max(longest, (x - hook).norm());
    if (row.time < taut - kDt) {
      worstFall = std::max(worstFall, std::abs(x.y() - (y0 - 0.5 * kG * row.time * row.time)));
      ++falling;
    } else if (row.time > taut + kDt) {
      worstHang = std::max({worstHang, std::abs(x.y() - (hook.y() - L)), Velocity(row).norm()});
      ++hanging;
    }
  }
  std::printf("rope (CSV): free fall within %.2e m over %d rows; hanging at its length within %.2e over %d rows; "
              "longest %.12f m\n",
              worstFall, falling, worstHang, hanging, longest);
  EXPECT_GT(falling, 20);
  EXPECT_GT(hanging, 50);
  EXPECT_LT(worstFall, 1e-9);
  EXPECT_LT(worstHang, 1e-8);
  EXPECT_LT(longest - L, 1e-8);
}

// A ball hangs at rest from a static hook by a ball joint; removing the hook after step 30
// removes the joint with it, and the ball falls freely from then on: v = -g (k - 30) dt.
TEST_F(Cli, RemovingABodyFreesWhatItsJointHeld) {
  const std::string scene = R"({"gravity": [0, -9.81, 0], "dt": )" + Number(kDt) + R"(, "steps": 60,
    "bodies": [{"name": "hook", "static": true, "shape": {"type": "box", "half_extents": [0.1, 0.1, 0.1]},
                "position": [0, 3, 0]},
               {"name": "ball", "shape": {"type": "sphere", "radius": 0.25}, "position": [0, 2, 0]}],
    "joints": [{"name": "chain", "type": "ball", "a": "ball", "b": "hook", "anchor": [0, 3, 0]}],
    "actions": [{"step": 30, "remove": "hook"}]})";
  const Result r = Run(Quote(Write("drop.json", scene)) + " --out " + Quote(Path("t.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> ball = RowsOf(ParseCsv(ReadFile(Path("t.csv"))), "ball");
  ASSERT_EQ(ball.size(), 61u);
  for (const Row& row : ball) {
    const double expected = row.step <= 30 ? 0.0 : -kG * static_cast<double>(row.step - 30) * kDt;
    EXPECT_NEAR(row.state[8], expected, 1e-9) << "step " << row.step;
    if (row.step <= 30) {
      EXPECT_NEAR(row.state[1], 2, 1e-9) << "step " << row.step;
    }
  }
}

// collide_connected: two overlapping crates welded by a fixed joint in zero g do not collide
// (no contact events, no push) unless the joint says they still do.
TEST_F(Cli, JoinedBodiesCollideOnlyWhenTheJointSaysSo) {
  auto scene = [](const char* collide) {
    return std::string(R"({"dt": 0.01, "steps": 10, "bodies": [
        {"name": "a", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
        {"name": "b", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "position": [0.9, 0, 0]}],
      "joints": [{"name": "weld", "type": "fixed", "a": "a", "b": "b", "anchor": [0.45, 0, 0])") +
           collide + "}]}";
  };
  const Result apart = Run(Quote(Write("apart.json", scene(""))) + " --out " + Quote(Path("t.csv")) +
                           " --events " + Quote(Path("e.csv")));
  ASSERT_EQ(apart.code, 0) << apart.err;
  EXPECT_EQ(ReadFile(Path("e.csv")),
            "step,time,event,body_a,body_b,x,y,z,nx,ny,nz,normal_impulse,tangent_impulse\n");
  for (const Row& row : ParseCsv(ReadFile(Path("t.csv")))) {
    EXPECT_LT(Velocity(row).norm(), 1e-12) << row.body << " step " << row.step;
  }
  const Result touching = Run(Quote(Write("touching.json", scene(R"(, "collide_connected": true)"))) + " --out " +
                              Quote(Path("t2.csv")) + " --events " + Quote(Path("e2.csv")));
  ASSERT_EQ(touching.code, 0) << touching.err;
  EXPECT_NE(ReadFile(Path("e2.csv")).find(",begin,a,b,"), std::string::npos) << ReadFile(Path("e2.csv"));
}

// A joint scene runs the same, bit for bit, on one thread and on two, and in a second run.
TEST_F(Cli, JointSceneHashesAlikeOnAnyThreadCount) {
  std::string bodies, joints;
  for (int k = 0; k < 8; ++k) {
    const std::string name = "link" + std::to_string(k);
    bodies += std::string(k ? ", " : "") + R"({"name": ")" + name +
              R"(", "shape": {"type": "capsule", "radius": 0.05, "half_height": 0.2}, "position": )" +
              Vec(RVec3(0.5 * k + 0.25, 10, 0)) + R"(, "orientation": [0.7071067811865476, 0, 0, 0.7071067811865476]})";
    joints += std::string(k ? ", " : "") + R"({"name": "j)" + std::to_string(k) + R"(", "type": "ball", "a": ")" +
              name + "\"" + (k ? R"(, "b": "link)" + std::to_string(k - 1) + "\"" : "") +
              R"(, "anchor": )" + Vec(RVec3(0.5 * k, 10, 0)) + "}";
  }
  const std::string scene = R"({"gravity": [0, -9.81, 0], "steps": 120, "bodies": [)" + bodies +
                            R"(, {"name": "ground", "static": true, "shape": {"type": "box", "half_extents": [10, 0.5, 10]},
                            "position": [0, 6.5, 0]}], "joints": [)" + joints + "]}";
  const fs::path file = Write("chain.json", scene);
  const Result one = Run(Quote(file) + " --threads 1 --out " + Quote(Path("t1.csv")));
  const Result two = Run(Quote(file) + " --threads 2 --out " + Quote(Path("t2.csv")));
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_EQ(Hash(one), Hash(two));
  EXPECT_EQ(ReadFile(Path("t1.csv")), ReadFile(Path("t2.csv")));
  // The chain swings down onto the ground, 3 m below its hook.
  const std::vector<Row> rows = ParseCsv(ReadFile(Path("t1.csv")));
  ASSERT_FALSE(rows.empty());
  EXPECT_LT(RowsOf(rows, "link7").back().state[1], 9.5);
}

TEST_F(Cli, BadJointsExitTwoNamingThePath) {
  auto scene = [](const std::string& joint) {
    return R"({"dt": 0.01, "steps": 10, "bodies": [
        {"name": "a", "shape": {"type": "sphere", "radius": 1}},
        {"name": "floor", "static": true, "shape": {"type": "box", "half_extents": [5, 1, 5]}, "position": [0, -3, 0]}],
      "joints": [)" + joint + "]}";
  };
  struct Case {
    std::string scene, mustContain;
  };
  const std::vector<Case> cases = {
      {scene(R"({"name": "j", "type": "ball", "a": "ghost", "anchor": [0, 0, 0]})"),
       "joints[0].a: no body of the scene is named \"ghost\""},
      {scene(R"({"name": "j", "type": "spring", "a": "a", "anchor": [0, 0, 0]})"), "joints[0].type: must be one of"},
      {scene(R"({"name": "j", "type": "ball", "a": "a", "anchor": [0, 0, 0], "stiffness": 1})"),
       "joints[0].stiffness: unknown field"},
      {scene(R"({"name": "j", "type": "hinge", "a": "a", "anchor": [0, 0, 0], "axis": [0, 0, 0]})"),
       "joints[0].axis: must have a non-zero length"},
      {scene(R"({"name": "j", "type": "hinge", "a": "a", "anchor": [0, 0, 0], "axis": [0, 1, 0], "limits": [1, 0]})"),
       "joints[0].limits: must be [lower, upper] with lower <= upper"},
      {scene(R"({"name": "j", "type": "slider", "a": "a", "anchor": [0, 0, 0], "axis": [0, 1, 0],
                 "motor": {"speed": 1, "max_force": -2}})"),
       "joints[0].motor.max_force: must be a finite number >= 0"},
      {scene(R"({"name": "j", "type": "ball", "a": "floor", "anchor": [0, 0, 0]})"),
       "joints[0].a: \"floor\" is static or kinematic"},
      {scene(R"({"name": "j", "type": "ball", "a": "a", "b": "a", "anchor": [0, 0, 0]})"),
       "joints[0].b: must be another body than a"},
      {scene(R"({"name": "j", "type": "distance", "a": "a", "anchor": [0, 0, 0], "anchor_b": [0, 1, 0],
                 "min_distance": 2, "max_distance": 1})"),
       "joints[0].min_distance: must not exceed max_distance"},
      {scene(R"({"name": "j", "type": "ball", "a": "a", "anchor": [0, 0, 0]}, {"name": "j", "type": "ball",
                 "a": "a", "b": "floor", "anchor": [0, 0, 0]})"),
       "joints[1].name: \"j\" is already the name of joints[0]"},
      {R"({"bodies": [], "joints": 3})", "joints: must be an array of joints"},
  };
  for (const Case& c : cases) {
    Write("keep.csv", "earlier run\n");
    const Result r = Run(Quote(Write("bad.json", c.scene)) + " --out " + Quote(Path("keep.csv")));
    EXPECT_EQ(r.code, 2) << c.scene << "\n" << r.err;
    EXPECT_NE(r.err.find("bad.json: " + c.mustContain), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("hash="), std::string::npos) << r.err;
    EXPECT_EQ(ReadFile(Path("keep.csv")), "earlier run\n");  // never truncated by bad input
  }
}

// A joint scene saved mid-run and loaded again ends with the hash of the run that never
// stopped (the state holds the joints and their warm starts); a state of the same scene
// without its joints is another world's, refused.
TEST_F(Cli, JointScenesSavedAndLoadedContinueBitForBit) {
  const fs::path scene = Write("hung.json", R"({"gravity": [0, -9.81, 0], "dt": 0.01, "steps": 40,
      "bodies": [{"name": "bob", "shape": {"type": "sphere", "radius": 0.1}, "position": [0.5, 1, 0]},
                 {"name": "link", "shape": {"type": "box", "half_extents": [0.05, 0.2, 0.05]}, "position": [0.5, 0.7, 0]},
                 {"name": "free", "shape": {"type": "sphere", "radius": 0.1}, "position": [5, 1, 0]}],
      "joints": [{"name": "pivot", "type": "ball", "a": "bob", "anchor": [0, 2, 0]},
                 {"name": "elbow", "type": "hinge", "a": "link", "b": "bob", "anchor": [0.5, 0.9, 0],
                  "axis": [0, 0, 1], "limits": [-0.5, 0.5]}]})");
  const Result whole = Run(Quote(scene) + " --out /dev/null");
  ASSERT_EQ(whole.code, 0) << whole.err;
  const Result save = Run(Quote(scene) + " --out /dev/null --save-state 10:" + Quote(Path("s.bin")));
  ASSERT_EQ(save.code, 0) << save.err;
  const Result load = Run(Quote(scene) + " --out /dev/null --load-state " + Quote(Path("s.bin")));
  ASSERT_EQ(load.code, 0) << load.err;
  auto hash = [](const std::string& err) { return err.substr(err.rfind("hash=")); };
  EXPECT_EQ(hash(load.err), hash(whole.err));
  const fs::path jointless = Write("jointless.json", R"({"gravity": [0, -9.81, 0], "dt": 0.01, "steps": 40,
      "bodies": [{"name": "bob", "shape": {"type": "sphere", "radius": 0.1}, "position": [0.5, 1, 0]},
                 {"name": "link", "shape": {"type": "box", "half_extents": [0.05, 0.2, 0.05]}, "position": [0.5, 0.7, 0]},
                 {"name": "free", "shape": {"type": "sphere", "radius": 0.1}, "position": [5, 1, 0]}]})");
  ASSERT_EQ(Run(Quote(jointless) + " --out /dev/null --save-state 10:" + Quote(Path("j.bin"))).code, 0);
  const Result foreign = Run(Quote(scene) + " --out /dev/null --load-state " + Quote(Path("j.bin")));
  EXPECT_EQ(foreign.code, 2) << foreign.err;
}
