// A scene's actions (docs/scene-format.md, "Actions"): checked at the door (exit-2 errors name the
// JSON path), and replayed by RSceneWorld. Each verb against its closed form in zero g: a
// free body drifts as x0 + v t exactly (kick-drift-kick with no force adds no rounding
// beyond the additions), an impulse J changes v by J / m and a sphere's spin by
// (r x J) / (2/5 m R^2).
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#include <gtest/gtest.h>

#include <string>

using namespace REngine;

namespace {

// A scene in zero g with a 2 kg sphere "a" at the origin and a static box far away.
std::string Scene(const std::string& actions, const std::string& extra = "") {
  return R"({"dt": 0.01, "steps": 100, "bodies": [
    {"name": "a", "shape": {"type": "sphere", "radius": 0.5}, "mass": 2},
    {"name": "wall", "static": true, "shape": {"type": "box", "half_extents": [1, 1, 1]},
     "position": [1000, 0, 0]})" + extra + R"(],
    "actions": [)" + actions + "]}";
}

// Runs a world to `steps`, applying its actions as rengine-sim does.
void RunWorld(RSceneWorld& world, const RScene& scene, std::uint64_t steps) {
  RIntegrator integrator(scene.settings);
  world.ApplyActions(0);
  for (std::uint64_t k = 1; k <= steps; ++k) {
    integrator.Update(world.Bodies(), scene.dt);
    world.ApplyActions(k);
  }
}

void ExpectBadAt(const std::string& json, const std::string& path, const std::string& words) {
  try {
    ParseScene(json, "a.json");
    ADD_FAILURE() << "accepted; expected an error at " << path;
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.JsonPath(), path) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(Actions, AreSortedByStepKeepingListOrderWithinAStep) {
  const RScene s = ParseScene(Scene(R"(
    {"step": 5, "set_velocity": {"body": "a", "velocity": [1, 0, 0]}},
    {"step": 2, "impulse": {"body": "a", "impulse": [1, 0, 0]}},
    {"step": 5, "remove": "a"})"), "a.json");
  ASSERT_EQ(s.actions.size(), 3u);
  EXPECT_EQ(s.actions[0].step, 2u);
  EXPECT_EQ(s.actions[1].verb, RSceneAction::Verb::kSetVelocity);
  EXPECT_EQ(s.actions[2].verb, RSceneAction::Verb::kRemove);
  EXPECT_EQ(s.actions[2].path, "actions[2]");
}

TEST(Actions, BadOnesAreRefusedNamingThePath) {
  ExpectBadAt(Scene(R"({"step": 1})"), "actions[0]", "exactly one of the verbs");
  ExpectBadAt(Scene(R"({"step": 1, "remove": "a", "impulse": {"body": "a", "impulse": [1, 0, 0]}})"),
              "actions[0]", "exactly one");
  ExpectBadAt(Scene(R"({"step": -1, "remove": "a"})"), "actions[0].step", "integer");
  ExpectBadAt(Scene(R"({"step": 1, "remove": "b"})"), "actions[0].remove", "no body is named \"b\"");
  ExpectBadAt(Scene(R"({"step": 1, "explode": "a"})"), "actions[0].explode", "unknown field");
  // Removed at 3, so not there at 4, whatever the list order.
  ExpectBadAt(Scene(R"({"step": 4, "impulse": {"body": "a", "impulse": [1, 0, 0]}},
                       {"step": 3, "remove": "a"})"),
              "actions[0].impulse.body", "at step 4");
  // Added at 7: not there at 6.
  ExpectBadAt(Scene(R"({"step": 6, "set_velocity": {"body": "b", "velocity": [1, 0, 0]}},
                       {"step": 7, "add": {"name": "b", "shape": {"type": "sphere", "radius": 1}}})"),
              "actions[0].set_velocity.body", "no body is named \"b\"");
  ExpectBadAt(Scene(R"({"step": 1, "add": {"name": "a", "shape": {"type": "sphere", "radius": 1}}})"),
              "actions[0].add.name", "already the name");
  ExpectBadAt(Scene(R"({"step": 1, "add": {"name": "b", "shape": {"type": "sphere", "radius": 1},
                                            "ignore": ["ghost"]}})"),
              "actions[0].add.ignore[0]", "no body is named \"ghost\"");
  ExpectBadAt(Scene(R"({"step": 1, "add": {"name": "b", "shape": {"type": "sphere", "radius": -1}}})"),
              "actions[0].add.shape.radius", "> 0");
  ExpectBadAt(Scene(R"({"step": 1, "impulse": {"body": "a", "impulse": [1, 0]}})"),
              "actions[0].impulse.impulse", "3 numbers");
  ExpectBadAt(Scene(R"({"step": 1, "impulse": {"body": "a", "impulse": [1e999, 0, 0]}})"),
              "actions[0].impulse.impulse[0]", "finite");
  // RRigidBody::AddImpulse_W's bound (1e30 N s a component): 1e300 flung the body to 1e299 m.
  ExpectBadAt(Scene(R"({"step": 1, "impulse": {"body": "a", "impulse": [0, 0, -1e300]}})"),
              "actions[0].impulse.impulse[2]", "must be a finite number within 1e30 (N s) (got -1e+300)");
  ExpectBadAt(Scene(R"({"step": 1, "impulse": {"body": "a", "impulse": [0, 1.0000000000000001e30, 0],
                                                 "point": [0, 0, 1]}})"),
              "actions[0].impulse.impulse[1]", "within 1e30");
  ExpectBadAt(Scene(R"({"step": 1, "add": {"name": "far", "shape": {"type": "sphere", "radius": 1},
                                            "position": [1e16, 0, 0]}})"),
              "actions[0].add.position", "1e15");
  ExpectBadAt(R"({"bodies": [], "actions": {}})", "actions", "array");
  EXPECT_NO_THROW(ParseScene(Scene(R"({"step": 1, "impulse": {"body": "a", "impulse": [1e30, -1e30, 0]}})"), "a.json"));
  // A name freed by a removal may be used again by a later add.
  EXPECT_NO_THROW(ParseScene(Scene(R"({"step": 1, "remove": "a"},
      {"step": 1, "add": {"name": "a", "shape": {"type": "sphere", "radius": 1}}})"), "a.json"));
}

// The scene runs 100 steps: an action at step 100 applies (after the last step's motion, in
// the last row), one at 101 would never apply and is refused as a ray there is, by the path
// of its step; so is one that a run shortened afterwards (rengine-sim's --steps, then
// CheckSceneLimits) would never reach.
TEST(Actions, AnActionAfterTheLastStepIsRefused) {
  EXPECT_NO_THROW(ParseScene(Scene(R"({"step": 100, "remove": "a"})"), "a.json"));
  ExpectBadAt(Scene(R"({"step": 3, "remove": "wall"}, {"step": 101, "remove": "a"},
                       {"step": 2, "impulse": {"body": "a", "impulse": [1, 0, 0]}})"),
              "actions[1].step", "is after the last step (100): the action would never be applied (got 101)");
  RScene scene = ParseScene(Scene(R"({"step": 3, "remove": "wall"}, {"step": 2, "remove": "a"})"), "a.json");
  scene.steps = 3;
  EXPECT_NO_THROW(CheckSceneLimits(scene, RSceneLimits{}));
  scene.steps = 2;
  try {
    CheckSceneLimits(scene, RSceneLimits{});
    ADD_FAILURE() << "an action after the last step was accepted";
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.JsonPath(), "actions[0].step") << e.what();
    EXPECT_NE(std::string(e.what()).find("after the last step (2)"), std::string::npos) << e.what();
  }
}

// add at step k with velocity v: after N steps the body is at x0 + v (N - k) dt.
TEST(Actions, AddedBodyDriftsFromItsStep) {
  const RScene scene = ParseScene(Scene(R"({"step": 30, "add": {"name": "b",
      "shape": {"type": "box", "half_extents": [0.1, 0.2, 0.3]}, "position": [0, 50, 0],
      "velocity": [3, -1, 2]}})"), "a.json");
  RSceneWorld world(scene);
  RunWorld(world, scene, 29);
  EXPECT_FALSE(world.Find("b").IsValid());
  EXPECT_EQ(world.Live().size(), 2u);
  RSceneWorld fresh(scene);
  RunWorld(fresh, scene, 100);
  const RBodyHandle b = fresh.Find("b");
  ASSERT_TRUE(b.IsValid());
  ASSERT_EQ(fresh.Live().size(), 3u);
  EXPECT_EQ(fresh.Live().back(), b) << "rows in order of creation";
  const RVec3 expected = RVec3(0, 50, 0) + RVec3(3, -1, 2) * (70 * scene.dt);
  EXPECT_LT((fresh.Bodies()[b].Position_W() - expected).norm(), 1e-12);
}

// remove at step k: gone from then on, and nobody else notices.
TEST(Actions, RemovedBodyIsGoneAndOthersCarryOn) {
  const RScene scene = ParseScene(Scene(R"({"step": 40, "remove": "a"})",
      R"(, {"name": "c", "shape": {"type": "sphere", "radius": 0.5}, "position": [0, 0, 10],
           "velocity": [0, 1, 0]})"),
      "a.json");
  RSceneWorld world(scene);
  RunWorld(world, scene, 100);
  EXPECT_FALSE(world.Find("a").IsValid());
  ASSERT_EQ(world.Live().size(), 2u);
  const RRigidBody& c = world.Bodies()[world.Find("c")];
  EXPECT_LT((c.Position_W() - RVec3(0, 1, 10)).norm(), 1e-12);
}

// impulse J on the 2 kg sphere at step 10: v = J / m from then on; at a world point p it
// also spins it at (r x J) / I, r = p - x(step 20), I = 2/5 m R^2.
TEST(Actions, ImpulseChangesMomentumByJ) {
  const RScene scene = ParseScene(Scene(R"(
      {"step": 10, "impulse": {"body": "a", "impulse": [4, 0, 0]}},
      {"step": 20, "impulse": {"body": "a", "impulse": [0, 2, 0], "point": [0, 0, 0.5]}})"),
      "a.json");
  RSceneWorld world(scene);
  RunWorld(world, scene, 100);
  const RRigidBody& a = world.Bodies()[world.Find("a")];
  const RVec3 v1(2, 0, 0), v2(2, 1, 0);
  const RVec3 x = v1 * (10 * scene.dt) + v2 * (80 * scene.dt);
  EXPECT_LT((a.Velocity_W() - v2).norm(), 1e-14);
  EXPECT_LT((a.Position_W() - x).norm(), 1e-12);
  const RScalar I = 0.4 * 2 * 0.25;
  const RVec3 r = RVec3(0, 0, 0.5) - v1 * (10 * scene.dt);
  const RVec3 w = r.cross(RVec3(0, 2, 0)) / I;
  EXPECT_LT((a.AngularVelocity_W() - w).norm(), 1e-13);
}

// set_velocity at step k: x = v0 k dt + v1 (N - k) dt; an absent field is left as it is.
TEST(Actions, SetVelocityReplacesOnlyWhatItGives) {
  const RScene scene = ParseScene(Scene(R"(
      {"step": 0, "set_velocity": {"body": "a", "velocity": [1, 0, 0], "angular_velocity": [0, 0, 3]}},
      {"step": 25, "set_velocity": {"body": "a", "velocity": [0, 0, -2]}})"), "a.json");
  RSceneWorld world(scene);
  RunWorld(world, scene, 100);
  const RRigidBody& a = world.Bodies()[world.Find("a")];
  const RVec3 x = RVec3(1, 0, 0) * (25 * scene.dt) + RVec3(0, 0, -2) * (75 * scene.dt);
  EXPECT_LT((a.Position_W() - x).norm(), 1e-12);
  EXPECT_LT((a.AngularVelocity_W() - RVec3(0, 0, 3)).norm(), 1e-13);
}

// An added body's ignore list is symmetric and speaks of bodies that exist at its step: a
// missile added inside its launcher passes through it.
TEST(Actions, AddedBodyIgnoresItsLauncher) {
  const RScene scene = ParseScene(Scene(R"({"step": 5, "add": {"name": "missile",
      "shape": {"type": "sphere", "radius": 0.1}, "mass": 1, "position": [0, 0, 0],
      "velocity": [0, 10, 0], "ignore": ["a"]}})"), "a.json");
  RSceneWorld world(scene);
  RunWorld(world, scene, 100);
  const RRigidBody& a = world.Bodies()[world.Find("a")];
  const RRigidBody& m = world.Bodies()[world.Find("missile")];
  EXPECT_EQ(a.Velocity_W(), RVec3::Zero()) << "the launcher was pushed";
  EXPECT_LT((m.Position_W() - RVec3(0, 10 * 95 * scene.dt, 0)).norm(), 1e-12);
}

// Spawning the same shape many times shares one prepared shape: the hull is built once.
TEST(Actions, EqualShapesArePreparedOnce) {
  std::string actions;
  for (int i = 0; i < 5; ++i) {
    actions += std::string(i ? "," : "") + R"({"step": )" + std::to_string(i) +
               R"(, "add": {"name": "f)" + std::to_string(i) +
               R"(", "shape": {"type": "hull", "points": [[0,0,0],[1,0,0],[0,1,0],[0,0,1]]},
               "position": [)" + std::to_string(10 * i + 10) + R"(, 0, 0]}})";
  }
  const RScene scene = ParseScene(Scene(actions), "a.json");
  ASSERT_EQ(scene.actions.size(), 5u);
  for (const RSceneAction& a : scene.actions) {
    ASSERT_TRUE(a.def.prepared);
    EXPECT_EQ(a.def.prepared.get(), scene.actions[0].def.prepared.get());
  }
}

// The churn scene: a pile of boxes resting exactly under gravity falls asleep; a small body
// is added far away and the previous one removed every 10 steps from then on. The pile stays
// asleep and does not move by a single bit (bench_churn measures what the churn costs).
TEST(Actions, ChurnSceneLeavesTheSleepingPileUntouched) {
  std::string bodies = R"({"name": "ground", "static": true, "position": [0, -0.5, 0],
      "shape": {"type": "box", "half_extents": [50, 0.5, 50]}})";
  for (int c = 0; c < 4; ++c) {
    for (int k = 0; k < 3; ++k) {
      bodies += R"(, {"name": "box)" + std::to_string(3 * c + k) + R"(", "mass": 1,
          "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
          "position": [)" + std::to_string(1.5 * c) + ", " + std::to_string(0.5 + k) + ", 0]}";
    }
  }
  std::string actions;
  for (int s = 60, i = 0; s < 300; s += 10, ++i) {
    if (i > 0) actions += R"(, {"step": )" + std::to_string(s) + R"(, "remove": "d)" + std::to_string(i - 1) + "\"}";
    actions += std::string(i > 0 ? ", " : "") + R"({"step": )" + std::to_string(s) +
               R"(, "add": {"name": "d)" + std::to_string(i) +
               R"(", "shape": {"type": "sphere", "radius": 0.1}, "position": [40, 5, 40]}})";
  }
  const RScene scene = ParseScene(R"({"gravity": [0, -9.81, 0], "dt": 0.0166666666666666667,
      "steps": 300, "bodies": [)" + bodies + R"(], "actions": [)" + actions + "]}", "churn.json");
  RSceneWorld world(scene);
  RIntegrator integrator(scene.settings);
  world.ApplyActions(0);
  std::vector<RVec3> settled;
  for (std::uint64_t k = 1; k <= scene.steps; ++k) {
    integrator.Update(world.Bodies(), scene.dt);
    world.ApplyActions(k);
    if (k == 60) {
      for (std::size_t i = 1; i <= 12; ++i) settled.push_back(world.Bodies()[world.Live()[i]].Position_W());
    }
    if (k >= 60) {
      EXPECT_EQ(integrator.PairStats().sleepingBodies, 12u) << "step " << k;
    }
  }
  for (std::size_t i = 1; i <= 12; ++i) {
    EXPECT_EQ(world.Bodies()[world.Live()[i]].Position_W(), settled[i - 1]) << i;
  }
}
