// Joints added and removed by the scene's actions (README, "rengine-sim": `add_joint`,
// `remove_joint`), run through rengine-sim and checked on its CSV against closed forms: a bob
// in free fall caught by an add_joint keeps its distance from the pivot from that step on; in
// zero g the catch keeps the angular momentum about the pivot, and the bob circles at
// w = L / (I + m d^2); a weight whose rope a remove_joint cuts falls freely from that step, to
// the rounding of the integrator (kick-drift-kick is exact for constant gravity). Save and
// load across joint actions continue bit for bit, on any thread count; bad joint actions exit
// 2 naming the JSON path.
#include <REngineMath/RMath.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "support/CliRunner.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr double kG = 9.81;
constexpr double kDt = 1.0 / 60;

// How far n steps of kick-drift-kick under constant gravity may stray from the closed form
// x0 + v0 t + g t^2 / 2 by rounding alone (unit roundoff u = 2^-53): each step rounds the two
// half kicks (u |v| each, and u |g dt / 2|) and the drift (u |x| + u |v dt|); a velocity error
// made at step i is drifted for the n - i steps left. So |dv| <= 2 n u (|v| + |g| dt) and
// |dx| <= n u (|x| + |v| dt) + n^2 dt |dv| / n, plus the closed form's own three roundings;
// doubled for the sums' orders this bound leaves out.
struct FreeFallTolerance {
  double position, velocity;
};
FreeFallTolerance FreeFallBound(int n, double maxX, double maxV) {
  const double u = std::numeric_limits<double>::epsilon() / 2;
  const double dv = 2 * n * u * (maxV + kG * kDt);
  const double dx = n * u * (maxX + maxV * kDt) + n * kDt * dv + 3 * u * (maxX + maxV * n * kDt);
  return {2 * dx, 2 * (dv + 2 * u * maxV)};
}

}  // namespace

// A 2 kg ball of radius 0.1 m thrown up and sideways falls freely until the add_joint of step
// 30 joins it to the world by a ball joint at the pivot (0, 4, 0), 1.5 m from it then. Before:
// x0 + v0 t + g t^2 / 2 to the integrator's rounding. After: it hangs from that point of itself,
// its centre at the distance it had at step 30 (to 1e-9 m), and that point stays put (its
// velocity v + w x (p - x) is 0: the ball turns with its swing).
TEST_F(Cli, ABobInFreeFallCaughtByAnAddJointKeepsItsDistanceFromThePivot) {
  const RVec3 x0(1.5, 3, 0.4), v0(-0.5, 3, 0.2), pivot(0, 4, 0), g(0, -kG, 0);
  const int k = 30, steps = 240;
  const std::string scene = R"({"gravity": [0, -9.81, 0], "dt": )" + Number(kDt) + R"(, "steps": )" +
                            std::to_string(steps) + R"(, "bodies": [
      {"name": "bob", "shape": {"type": "sphere", "radius": 0.1}, "mass": 2, "position": )" + Vec(x0) +
                            R"(, "velocity": )" + Vec(v0) + R"(}],
    "actions": [{"step": )" + std::to_string(k) + R"(, "add_joint": {"name": "catch", "type": "ball", "a": "bob",
                 "anchor": )" + Vec(pivot) + "}}]}";
  const Result r = Run(Quote(Write("catch.json", scene)) + " --out " + Quote(Path("t.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> rows = ParseCsv(ReadFile(Path("t.csv")));
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(steps + 1));

  double worstX = 0, worstV = 0, maxX = 0, maxV = 0;
  for (int s = 0; s <= k; ++s) {
    const double t = rows[s].time;
    worstX = std::max(worstX, (Position(rows[s]) - (x0 + v0 * t + 0.5 * g * t * t)).cwiseAbs().maxCoeff());
    worstV = std::max(worstV, (Velocity(rows[s]) - (v0 + g * t)).cwiseAbs().maxCoeff());
    maxX = std::max(maxX, Position(rows[s]).cwiseAbs().maxCoeff());
    maxV = std::max(maxV, Velocity(rows[s]).cwiseAbs().maxCoeff());
  }
  const FreeFallTolerance tol = FreeFallBound(k, maxX, maxV);
  const double d = (Position(rows[k]) - pivot).norm();
  double worstLength = 0, worstAnchor = 0, lowest = pivot.y();
  for (int s = k; s <= steps; ++s) {
    const RVec3 x = Position(rows[s]);
    worstLength = std::max(worstLength, std::abs((x - pivot).norm() - d));
    if (s > k) worstAnchor = std::max(worstAnchor, (Velocity(rows[s]) + AngularVelocity(rows[s]).cross(pivot - x)).norm());
    lowest = std::min(lowest, x.y());
  }
  std::printf("caught after step %d (CSV): free fall within %.2e m and %.2e m/s (bounds %.2e, %.2e); "
              "distance %.6f m kept within %.2e m over %d steps; the caught point moves at most %.2e m/s; "
              "lowest %.3f m below the pivot\n",
              k, worstX, worstV, tol.position, tol.velocity, d, worstLength, steps - k, worstAnchor, pivot.y() - lowest);
  EXPECT_LE(worstX, tol.position);
  EXPECT_LE(worstV, tol.velocity);
  EXPECT_GT(d, 1.4);
  EXPECT_LT(worstLength, 1e-9);
  EXPECT_LT(worstAnchor, 1e-6);
  EXPECT_GT(pivot.y() - lowest, 0.99 * d) << "it swings down to hang below the pivot";
}

// In zero g the same catch: the only impulse acts at the pivot, so the angular momentum about
// it, m (x - p) x v + I w, keeps the value L = m (x_k - p) x v_k it had when the add_joint came
// (the ball did not spin). Held at a point d from its centre, the ball then turns about the
// pivot as one rigid body whose moment about any axis across (x - p) is I + m d^2, with L across
// (x - p): a steady rotation at w = L / (I + m d^2), the centre circling at d, the kinetic
// energy |L|^2 / (2 (I + m d^2)).
TEST_F(Cli, ACatchInZeroGKeepsTheAngularMomentumAboutThePivotAndCirclesAtLOverI) {
  const double m = 2, R = 0.1, I = 0.4 * m * R * R;
  const RVec3 x0(1, 0, 0), v0(0.3, 1.2, -0.4), pivot(0.5, -1, 2);
  const int k = 12, steps = 300;
  const std::string scene = R"({"dt": )" + Number(kDt) + R"(, "steps": )" + std::to_string(steps) + R"(, "bodies": [
      {"name": "bob", "shape": {"type": "sphere", "radius": 0.1}, "mass": 2, "position": )" + Vec(x0) +
                            R"(, "velocity": )" + Vec(v0) + R"(}],
    "actions": [{"step": )" + std::to_string(k) + R"(, "add_joint": {"name": "tether", "type": "ball", "a": "bob",
                 "anchor": )" + Vec(pivot) + "}}]}";
  const Result r = Run(Quote(Write("tether.json", scene)) + " --out " + Quote(Path("t.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> rows = ParseCsv(ReadFile(Path("t.csv")));
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(steps + 1));
  const RVec3 rk = Position(rows[k]) - pivot;
  const double d = rk.norm();
  const RVec3 L = m * rk.cross(Velocity(rows[k]));
  const RVec3 w = L / (I + m * d * d);
  const double energy = L.squaredNorm() / (2 * (I + m * d * d));
  double worstL = 0, worstW = 0, worstEnergy = 0, worstLength = 0, worstPlane = 0;
  for (int s = k + 1; s <= steps; ++s) {
    const RVec3 r_ = Position(rows[s]) - pivot, v = Velocity(rows[s]), ws = AngularVelocity(rows[s]);
    worstL = std::max(worstL, (m * r_.cross(v) + I * ws - L).norm() / L.norm());
    worstW = std::max(worstW, (ws - w).norm() / w.norm());
    worstEnergy = std::max(worstEnergy, std::abs(0.5 * m * v.squaredNorm() + 0.5 * I * ws.squaredNorm() - energy) / energy);
    worstLength = std::max(worstLength, std::abs(r_.norm() - d));
    worstPlane = std::max(worstPlane, std::abs(r_.dot(L.normalized())));  // the circle's plane is across L
  }
  std::printf("zero-g catch after step %d (CSV): |w| = %.9f rad/s; angular momentum about the pivot within %.2e (rel), "
              "w within %.2e (rel), energy within %.2e (rel), distance within %.2e m, off the circle's plane %.2e m\n",
              k, w.norm(), worstL, worstW, worstEnergy, worstLength, worstPlane);
  EXPECT_LT(worstL, 1e-9);
  EXPECT_LT(worstW, 1e-9);
  EXPECT_LT(worstEnergy, 1e-9);
  EXPECT_LT(worstLength, 1e-9);
  EXPECT_LT(worstPlane, 1e-9);
}

// A 5 kg weight swings on a 2 m rope (a distance joint, min_distance 0) from the scene's start;
// the remove_joint of step 40 cuts it while it swings. Before: never beyond the rope's length.
// After: thrown free, x = x_k + v_k t + g t^2 / 2 and v = v_k + g t exactly but for the
// integrator's rounding (FreeFallBound), and its spin unchanged.
TEST_F(Cli, AWeightWhoseRopeARemoveJointCutsFallsFreelyFromThatStep) {
  const RVec3 hook(0, 5, 0), x0(1.2, 3.4, 0), g(0, -kG, 0), w0(0, 0, 3);
  const double L = 2;
  const int k = 40, steps = 100;
  const std::string scene = R"({"gravity": [0, -9.81, 0], "dt": )" + Number(kDt) + R"(, "steps": )" +
                            std::to_string(steps) + R"(, "bodies": [
      {"name": "weight", "shape": {"type": "sphere", "radius": 0.1}, "mass": 5, "position": )" + Vec(x0) +
                            R"(, "angular_velocity": )" + Vec(w0) + R"(}],
    "joints": [{"name": "rope", "type": "distance", "a": "weight", "anchor": )" + Vec(x0) + R"(, "anchor_b": )" +
                            Vec(hook) + R"(, "min_distance": 0, "max_distance": 2}],
    "actions": [{"step": )" + std::to_string(k) + R"(, "remove_joint": "rope"}]})";
  const Result r = Run(Quote(Write("cut.json", scene)) + " --out " + Quote(Path("t.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> rows = ParseCsv(ReadFile(Path("t.csv")));
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(steps + 1));
  double longest = 0;
  for (int s = 0; s <= k; ++s) longest = std::max(longest, (Position(rows[s]) - hook).norm());
  const RVec3 xk = Position(rows[k]), vk = Velocity(rows[k]), wk = AngularVelocity(rows[k]);
  double worstX = 0, worstV = 0, worstSpin = 0, maxX = 0, maxV = 0;
  for (int s = k; s <= steps; ++s) {
    const double t = static_cast<double>(s - k) * kDt;
    worstX = std::max(worstX, (Position(rows[s]) - (xk + vk * t + 0.5 * g * t * t)).cwiseAbs().maxCoeff());
    worstV = std::max(worstV, (Velocity(rows[s]) - (vk + g * t)).cwiseAbs().maxCoeff());
    worstSpin = std::max(worstSpin, (AngularVelocity(rows[s]) - wk).norm());
    maxX = std::max(maxX, Position(rows[s]).cwiseAbs().maxCoeff());
    maxV = std::max(maxV, Velocity(rows[s]).cwiseAbs().maxCoeff());
  }
  const FreeFallTolerance tol = FreeFallBound(steps - k, maxX, maxV);
  std::printf("rope cut after step %d (CSV): held within %.2e m of its length before; then thrown at %.3f m/s and "
              "free within %.2e m and %.2e m/s over %d steps (bounds %.2e, %.2e); spin changed %.2e rad/s\n",
              k, longest - L, vk.norm(), worstX, worstV, steps - k, tol.position, tol.velocity, worstSpin);
  EXPECT_LT(longest - L, 1e-8);
  EXPECT_GT(vk.norm(), 1) << "cut while it swings";
  EXPECT_LE(worstX, tol.position);
  EXPECT_LE(worstV, tol.velocity);
  EXPECT_LT(worstSpin, 1e-12);
  EXPECT_LT((wk - w0).norm(), 1e-12) << "a rope at its centre never turned it";
}

// A chain assembled and taken apart by actions: links joined by add_joints at steps 5 and 10
// (one to a link added at 10), a remove_joint at 25, a name taken again at 30, a body removed
// at 40 with its joints. Saved after steps before, at, between and after the actions and
// loaded again, each run writes the uninterrupted run's rows from its step on, bit for bit, and
// its hash; on one thread and on two alike.
TEST_F(Cli, SaveAndLoadAcrossJointActionsContinueBitForBitOnAnyThreadCount) {
  std::string bodies;
  for (int i = 0; i < 4; ++i) {
    bodies += R"({"name": "link)" + std::to_string(i) + R"(", "shape": {"type": "capsule", "radius": 0.05,
                 "half_height": 0.2}, "position": )" + Vec(RVec3(0.5 * i + 0.25, 3, 0)) +
              R"(, "orientation": [0.7071067811865476, 0, 0, 0.7071067811865476]}, )";
  }
  const std::string scene = R"({"gravity": [0, -9.81, 0], "dt": 0.01, "steps": 60, "bodies": [)" + bodies + R"(
      {"name": "floor", "static": true, "shape": {"type": "box", "half_extents": [5, 0.5, 5]}, "position": [0, 0, 0]}],
    "joints": [{"name": "top", "type": "ball", "a": "link0", "anchor": [0, 3, 0]}],
    "actions": [
      {"step": 5, "add_joint": {"name": "j1", "type": "hinge", "a": "link1", "b": "link0", "anchor": [0.5, 2.95, 0],
                                "axis": [0, 0, 1], "limits": [-0.5, 0.5]}},
      {"step": 10, "add_joint": {"name": "j2", "type": "ball", "a": "link2", "b": "link1", "anchor": [1, 2.8, 0]}},
      {"step": 10, "add": {"name": "tip", "shape": {"type": "sphere", "radius": 0.1}, "position": [2.5, 3, 0]}},
      {"step": 10, "add_joint": {"name": "j3", "type": "distance", "a": "tip", "b": "link2", "anchor": [2.5, 3, 0],
                                 "anchor_b": [1.2, 2.7, 0], "min_distance": 0}},
      {"step": 25, "remove_joint": "j1"},
      {"step": 30, "add_joint": {"name": "j1", "type": "fixed", "a": "link3", "b": "link2", "anchor": [1.5, 2.5, 0]}},
      {"step": 40, "remove": "link2"}]})";
  const fs::path file = Write("chain.json", scene);
  const Result whole = Run(Quote(file) + " --threads 1 --out " + Quote(Path("whole.csv")));
  ASSERT_EQ(whole.code, 0) << whole.err;
  const std::string wholeCsv = ReadFile(Path("whole.csv"));
  const Result two = Run(Quote(file) + " --threads 2 --out " + Quote(Path("two.csv")));
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_EQ(Hash(two), Hash(whole));
  EXPECT_EQ(ReadFile(Path("two.csv")), wholeCsv);
  for (const std::uint64_t n : {2u, 5u, 17u, 30u, 45u}) {
    const std::string state = Quote(Path("s" + std::to_string(n) + ".bin"));
    const Result save = Run(Quote(file) + " --threads 1 --out /dev/null --save-state " + std::to_string(n) + ":" + state);
    ASSERT_EQ(save.code, 0) << save.err;
    EXPECT_EQ(Hash(save), Hash(whole)) << "saving changes nothing";
    for (const char* threads : {"1", "2"}) {
      const Result load = Run(Quote(file) + " --threads " + threads + " --out " + Quote(Path("l.csv")) +
                              " --load-state " + state);
      ASSERT_EQ(load.code, 0) << load.err;
      EXPECT_EQ(Hash(load), Hash(whole)) << "loaded at step " << n << " on " << threads << " threads";
      EXPECT_EQ(RowsFrom(ReadFile(Path("l.csv")), 0), RowsFrom(wholeCsv, n))
          << "loaded at step " << n << " on " << threads << " threads";
    }
  }
  // The chain did something: the tip hangs from it, below where it started.
  const std::vector<Row> rows = ParseCsv(wholeCsv);
  const auto tip = std::find_if(rows.rbegin(), rows.rend(), [](const Row& row) { return row.body == "tip"; });
  ASSERT_NE(tip, rows.rend());
  EXPECT_LT(tip->state[1], 2.5);
  std::printf("chain with joint actions: %s on 1 and 2 threads and loaded at steps 2, 5, 17, 30, 45\n",
              Hash(whole).c_str());
}

// The scene's actions are part of the scene: a state saved without the remove_joint is
// another scene's, refused.
TEST_F(Cli, AStateFromTheSceneWithOtherJointActionsIsRefused) {
  auto scene = [](const std::string& actions) {
    return R"({"gravity": [0, -9.81, 0], "dt": 0.01, "steps": 20, "bodies": [
        {"name": "bob", "shape": {"type": "sphere", "radius": 0.1}, "position": [1, 2, 0]}],
      "joints": [{"name": "pivot", "type": "ball", "a": "bob", "anchor": [0, 2, 0]}], "actions": [)" + actions + "]}";
  };
  ASSERT_EQ(Run(Quote(Write("kept.json", scene(""))) + " --out /dev/null --save-state 5:" + Quote(Path("s.bin"))).code, 0);
  const Result r = Run(Quote(Write("cut.json", scene(R"({"step": 10, "remove_joint": "pivot"})"))) +
                       " --out /dev/null --load-state " + Quote(Path("s.bin")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("another scene"), std::string::npos) << r.err;
}

TEST_F(Cli, BadJointActionsExitTwoNamingThePath) {
  auto scene = [](const std::string& actions) {
    return R"({"dt": 0.01, "steps": 20, "bodies": [
        {"name": "a", "shape": {"type": "sphere", "radius": 1}},
        {"name": "b", "shape": {"type": "sphere", "radius": 1}, "position": [3, 0, 0]},
        {"name": "floor", "static": true, "shape": {"type": "box", "half_extents": [5, 1, 5]}, "position": [0, -3, 0]}],
      "joints": [{"name": "weld", "type": "fixed", "a": "a", "b": "b", "anchor": [1.5, 0, 0]}],
      "actions": [)" + actions + "]}";
  };
  struct Case {
    std::string scene, mustContain;
  };
  const std::vector<Case> cases = {
      {scene(R"({"step": 2, "remove_joint": "weld"},
                {"step": 3, "add_joint": {"name": "j", "type": "hinge", "a": "a", "anchor": [0, 0, 0], "axis": [0, 0, 0]}})"),
       "actions[1].add_joint.axis: must have a non-zero length"},
      {scene(R"({"step": 4, "remove_joint": "wled"})"), "actions[0].remove_joint: no joint is named \"wled\" at step 4"},
      {scene(R"({"step": 4, "add_joint": {"name": "weld", "type": "ball", "a": "b", "anchor": [0, 0, 0]}})"),
       "actions[0].add_joint.name: \"weld\" is already the name of a joint at step 4"},
      {scene(R"({"step": 1, "remove": "b"}, {"step": 6, "add_joint": {"name": "j", "type": "ball", "a": "a", "b": "b",
                 "anchor": [0, 0, 0]}})"),
       "actions[1].add_joint.b: no body is named \"b\" at step 6"},
      {scene(R"({"step": 6, "add_joint": {"name": "j", "type": "ball", "a": "c", "anchor": [0, 0, 0]}},
                {"step": 7, "add": {"name": "c", "shape": {"type": "sphere", "radius": 1}}})"),
       "actions[0].add_joint.a: no body is named \"c\" at step 6"},
      {scene(R"({"step": 5, "remove": "a"}, {"step": 8, "remove_joint": "weld"})"),
       "actions[1].remove_joint: no joint is named \"weld\" at step 8 (it went with body \"a\""},
      {scene(R"({"step": 5, "add_joint": {"name": "j", "type": "ball", "a": "floor", "anchor": [0, 0, 0]}})"),
       "actions[0].add_joint.a: \"floor\" is static or kinematic"},
      {scene(R"({"step": 5, "add_joint": {"name": "j", "type": "slider", "a": "a", "anchor": [0, 0, 0],
                 "axis": [1, 0, 0], "limits": [1, -1]}})"),
       "actions[0].add_joint.limits: must be [lower, upper] with lower <= upper"},
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
