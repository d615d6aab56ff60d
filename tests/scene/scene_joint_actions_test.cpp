// Joints the scene's actions add and remove (README, "rengine-sim": `add_joint`, a joint
// object as in `joints`; `remove_joint`, a joint's name): checked at load against the bodies
// and joints that exist at each step (a body removed takes its joints along), and applied by
// RSceneWorld with the anchors and axis as the bodies stand at the action's step. The joint
// object's own fields are refused as the scene's joints are (scene_joints_test.cpp runs its 61
// single-joint cases as add_joint actions too).
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#include <gtest/gtest.h>

#include <REngineMath/RQuaternion.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "support/Joints.h"

using namespace REngine;

namespace {

// Under gravity: a static hook, a ball below it and a crate beside it, the scene joint "rope"
// (the crate to the hook), and the actions `actions` (the list's contents).
std::string Scene(const std::string& actions, const std::string& top = R"("steps": 60)") {
  return "{" + top + R"(, "gravity": [0, -9.81, 0], "bodies": [
      {"name": "hook", "static": true, "shape": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}, "position": [0, 5, 0]},
      {"name": "ball", "shape": {"type": "sphere", "radius": 0.25}, "position": [1, 4, 0], "velocity": [0.5, 2, -0.25]},
      {"name": "crate", "shape": {"type": "box", "half_extents": [0.3, 0.2, 0.1]}, "position": [-1, 3, 0]}],
    "joints": [{"name": "rope", "type": "distance", "a": "crate", "b": "hook", "anchor": [-1, 3.2, 0],
                "anchor_b": [0, 5, 0], "min_distance": 0}],
    "actions": [)" + actions + "]}";
}

// A joint object's fields after its name.
std::string AddJoint(std::uint64_t step, const std::string& name, const std::string& fields) {
  return R"({"step": )" + std::to_string(step) + R"(, "add_joint": {"name": ")" + name + "\", " + fields + "}}";
}
std::string RemoveJoint(std::uint64_t step, const std::string& name) {
  return R"({"step": )" + std::to_string(step) + R"(, "remove_joint": ")" + name + "\"}";
}
const std::string kBallToHook = R"("type": "ball", "a": "ball", "b": "hook", "anchor": [0, 5, 0])";

void ExpectBadAt(const std::string& json, const std::string& path, const std::string& words) {
  try {
    ParseScene(json, "a.json");
    ADD_FAILURE() << "accepted; expected an error at " << path << "\n" << json;
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.JsonPath(), path) << e.what();
    EXPECT_NE(e.Problem().find(words), std::string::npos) << e.what();
  }
}

// Runs a world to `steps`, applying its actions as rengine-sim does; after(k) after each step's.
template <class After>
void RunWorld(RSceneWorld& world, const RScene& scene, std::uint64_t steps, After after) {
  RIntegrator integrator(scene.settings);
  world.ApplyActions(0);
  after(std::uint64_t(0));
  for (std::uint64_t k = 1; k <= steps; ++k) {
    integrator.Update(world.Bodies(), scene.dt);
    world.ApplyActions(k);
    after(k);
  }
}

}  // namespace

TEST(SceneJointActions, AreReadWithTheirPathsAndSortedByStep) {
  const RScene s = ParseScene(Scene(RemoveJoint(9, "rope") + ", " +
                                    AddJoint(4, "hinge", R"("type": "hinge", "a": "ball", "anchor": [1, 4, 0],
                                             "axis": [0, 0, 2], "limits": [-1, 1])")),
                              "a.json");
  ASSERT_EQ(s.actions.size(), 2u);
  const RSceneAction& add = s.actions[0];
  EXPECT_EQ(add.verb, RSceneAction::Verb::kAddJoint);
  EXPECT_EQ(add.step, 4u);
  EXPECT_EQ(add.path, "actions[1]");
  EXPECT_EQ(add.joint.name, "hinge");
  EXPECT_EQ(add.joint.path, "actions[1].add_joint");
  EXPECT_EQ(add.joint.a, "ball");
  EXPECT_TRUE(add.joint.b.empty());
  EXPECT_EQ(add.joint.def.type, RJointType::kHinge);
  EXPECT_EQ(add.joint.def.axis_W, RVec3(0, 0, 1));
  EXPECT_EQ(add.joint.def.upper, 1);
  const RSceneAction& remove = s.actions[1];
  EXPECT_EQ(remove.verb, RSceneAction::Verb::kRemoveJoint);
  EXPECT_EQ(remove.joint.name, "rope");
  EXPECT_EQ(remove.path, "actions[0]");
}

// What exists at a step is what the actions before it (in step order, then list order) left.
TEST(SceneJointActions, NamesAreCheckedAgainstWhatExistsAtTheirStep) {
  const std::string addBox = R"({"step": 6, "add": {"name": "box", "shape": {"type": "sphere", "radius": 0.1}}})";
  // Bodies.
  ExpectBadAt(Scene(AddJoint(2, "j", R"("type": "ball", "a": "ghost", "anchor": [0, 0, 0])")),
              "actions[0].add_joint.a", "no body is named \"ghost\" at step 2");
  ExpectBadAt(Scene(R"({"step": 3, "remove": "ball"}, )" + AddJoint(3, "j", kBallToHook)), "actions[1].add_joint.a",
              "no body is named \"ball\" at step 3");
  ExpectBadAt(Scene(AddJoint(5, "j", R"("type": "fixed", "a": "crate", "b": "ball", "anchor": [0, 0, 0])") +
                    R"(, {"step": 1, "remove": "ball"})"),
              "actions[0].add_joint.b", "no body is named \"ball\" at step 5");
  ExpectBadAt(Scene(AddJoint(5, "j", R"("type": "ball", "a": "box", "anchor": [0, 0, 0])") + ", " + addBox),
              "actions[0].add_joint.a", "no body is named \"box\" at step 5");
  // Added at the same step but later in the list: not there yet.
  ExpectBadAt(Scene(AddJoint(6, "j", R"("type": "ball", "a": "box", "anchor": [0, 0, 0])") + ", " + addBox),
              "actions[0].add_joint.a", "no body is named \"box\" at step 6");
  // A body an action adds is static: the world cannot hold it, so it cannot be joined to it.
  ExpectBadAt(Scene(R"({"step": 1, "add": {"name": "post", "static": true, "shape": {"type": "sphere", "radius": 1}}},)" +
                    AddJoint(2, "j", R"("type": "ball", "a": "post", "anchor": [0, 0, 0])")),
              "actions[1].add_joint.a", "\"post\" is static or kinematic and b is the world");
  ExpectBadAt(Scene(AddJoint(2, "j", R"("type": "hinge", "a": "hook", "b": "hook", "anchor": [0, 0, 0], "axis": [1, 0, 0])")),
              "actions[0].add_joint.b", "another body than a");
  // Joint names.
  ExpectBadAt(Scene(AddJoint(2, "rope", kBallToHook)), "actions[0].add_joint.name",
              "\"rope\" is already the name of a joint at step 2");
  ExpectBadAt(Scene(AddJoint(2, "j", kBallToHook) + ", " + AddJoint(7, "j", kBallToHook)), "actions[1].add_joint.name",
              "\"j\" is already the name of a joint at step 7");
  ExpectBadAt(Scene(RemoveJoint(2, "cord")), "actions[0].remove_joint", "no joint is named \"cord\" at step 2");
  ExpectBadAt(Scene(RemoveJoint(2, "rope") + ", " + RemoveJoint(2, "rope")), "actions[1].remove_joint",
              "no joint is named \"rope\" at step 2 (removed by actions[0] at step 2)");
  // A body removed takes its joints along: the scene's and those actions added.
  ExpectBadAt(Scene(R"({"step": 10, "remove": "hook"}, )" + RemoveJoint(11, "rope")), "actions[1].remove_joint",
              "no joint is named \"rope\" at step 11 (it went with body \"hook\", removed by actions[0] at step 10)");
  ExpectBadAt(Scene(AddJoint(1, "j", kBallToHook) + R"(, {"step": 4, "remove": "ball"}, )" + RemoveJoint(4, "j")),
              "actions[2].remove_joint", "it went with body \"ball\"");
  // Added later.
  ExpectBadAt(Scene(RemoveJoint(3, "j") + ", " + AddJoint(8, "j", kBallToHook)), "actions[0].remove_joint",
              "no joint is named \"j\" at step 3");
  // The verbs.
  ExpectBadAt(Scene(R"({"step": 1, "remove_joint": 7})"), "actions[0].remove_joint", "non-empty string");
  ExpectBadAt(Scene(R"({"step": 1, "remove_joint": "rope", "add_joint": {"name": "j", "type": "ball", "a": "ball",
                       "anchor": [0, 0, 0]}})"),
              "actions[0]", "exactly one of the verbs add, remove, impulse, set_velocity, add_joint, remove_joint (has 2)");
  ExpectBadAt(Scene(R"({"step": 1, "add_joints": {}})"), "actions[0].add_joints", "unknown field");
  ExpectBadAt(Scene(R"({"add_joint": {"name": "j", "type": "ball", "a": "ball", "anchor": [0, 0, 0]}})"),
              "actions[0].step", "required");
}

// What a removal frees may be taken again: a joint's name once it is removed, or once its body
// went; a body an action adds, from its step on (later in the same step's list too).
TEST(SceneJointActions, ANameFreedMayBeTakenAgain) {
  const RScene s = ParseScene(
      Scene(RemoveJoint(2, "rope") + ", " + AddJoint(2, "rope", kBallToHook) + ", " +
            R"({"step": 5, "remove": "ball"}, )" + AddJoint(5, "rope", R"("type": "slider", "a": "crate",
            "anchor": [0, 0, 0], "axis": [1, 0, 0])") + ", " +
            R"({"step": 7, "add": {"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "position": [2, 2, 2]}}, )" +
            AddJoint(7, "tie", R"("type": "distance", "a": "ball", "b": "crate", "anchor": [2, 2, 2],
                     "anchor_b": [-1, 3, 0])")),
      "a.json");
  ASSERT_EQ(s.actions.size(), 6u);
  RSceneWorld world(s);
  std::vector<RJointHandle> rope;
  RunWorld(world, s, 8, [&](std::uint64_t) {
    EXPECT_TRUE(world.HoldsExactlyItsJoints());
    if (rope.empty() || rope.back() != world.FindJoint("rope")) rope.push_back(world.FindJoint("rope"));
  });
  // The scene's rope, the ball's, removed with the ball at 5 and made again a slider the same step.
  ASSERT_EQ(rope.size(), 3u);
  const RBodies& bodies = world.Bodies();
  EXPECT_FALSE(bodies.ContainsJoint(rope[0]));
  EXPECT_FALSE(bodies.ContainsJoint(rope[1]));
  EXPECT_EQ(bodies.Joint(rope[2]).def.type, RJointType::kSlider);
  EXPECT_EQ(bodies.Joint(world.FindJoint("tie")).def.a, world.Find("ball"));
  EXPECT_EQ(bodies.JointCount(), 2u);
}

// An add_joint's anchors and axis are world values as the bodies stand at its step: the ball,
// flying since step 0, is hinged to the crate, hanging on its rope, after step 20, where each
// keeps the anchor in its frame; the hinge's angle starts at 0 there. A remove_joint removes
// it; the hook's removal takes the rope along.
TEST(SceneJointActions, AJointIsMadeAsTheBodiesStandAtItsStep) {
  const RScene s = ParseScene(Scene(AddJoint(20, "elbow", R"("type": "hinge", "a": "ball", "b": "crate",
                                             "anchor": [0.25, 2.5, 0.5], "axis": [1, 1, 0], "limits": [-0.5, 0.5])") +
                                    ", " + RemoveJoint(40, "elbow") + R"(, {"step": 50, "remove": "hook"})"),
                              "a.json");
  RSceneWorld world(s);
  RunWorld(world, s, 60, [&](std::uint64_t k) {
    const RBodies& bodies = world.Bodies();
    ASSERT_TRUE(world.HoldsExactlyItsJoints()) << "step " << k;
    EXPECT_EQ(bodies.ContainsJoint(world.FindJoint("elbow")), k >= 20 && k < 40) << "step " << k;
    EXPECT_EQ(world.FindJoint("rope").IsValid(), k < 50) << "step " << k;
    if (k != 20) return;
    const RJointHandle h = world.FindJoint("elbow");
    const RJoint& j = bodies.Joint(h);
    EXPECT_EQ(j.def.a, world.Find("ball"));
    EXPECT_EQ(j.def.b, world.Find("crate"));
    const auto [onBall, onCrate] = test::Anchors(bodies, h);
    std::printf("add_joint after step 20: anchors %.2e m and %.2e m from [0.25, 2.5, 0.5]\n",
                (onBall - RVec3(0.25, 2.5, 0.5)).norm(), (onCrate - RVec3(0.25, 2.5, 0.5)).norm());
    EXPECT_LT((onBall - RVec3(0.25, 2.5, 0.5)).norm(), 1e-14);
    EXPECT_LT((onCrate - RVec3(0.25, 2.5, 0.5)).norm(), 1e-14);
    const RVec3 axis = RVec3(1, 1, 0).normalized();
    EXPECT_LT((bodies[j.def.a].Orientation_WB() * j.axisA_B - axis).norm(), 1e-15);
    EXPECT_LT((bodies[j.def.b].Orientation_WB() * j.axisB_B - axis).norm(), 1e-15);
    EXPECT_LT(std::abs(bodies.JointPosition(h)), 1e-15);
    // The ball flew: it is not where the scene started it.
    EXPECT_GT((bodies[j.def.a].Position_W() - RVec3(1, 4, 0)).norm(), 0.1);
  });
}

// A world that holds other joints than the scene named (a state from elsewhere) is told apart.
TEST(SceneJointActions, TheWorldKnowsWhetherItHoldsItsJoints) {
  const RScene s = ParseScene(Scene(AddJoint(0, "j", kBallToHook)), "a.json");
  RSceneWorld world(s);
  world.ApplyActions(0);
  EXPECT_TRUE(world.HoldsExactlyItsJoints());
  world.Bodies().RemoveJoint(world.FindJoint("rope"));
  EXPECT_FALSE(world.HoldsExactlyItsJoints());
}

// RSceneLimits::maxJoints counts the joints actions add with the scene's, named "actions".
TEST(SceneJointActions, TheLimitCountsThemWithTheScenesJoints) {
  const std::string json = Scene(AddJoint(1, "j", kBallToHook));
  RSceneLimits limits;
  limits.maxJoints = 1;
  try {
    ParseScene(json, "many.json", limits);
    FAIL();
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.JsonPath(), "actions");
    EXPECT_NE(e.Problem().find("has 2 joints with those the actions add; at most 1"), std::string::npos) << e.what();
  }
  limits.maxJoints = 2;
  EXPECT_EQ(ParseScene(json, "many.json", limits).actions.size(), 1u);
}

// The loader's replay of names and the world's agree: of 3000 action lists drawn from a fixed
// seed (bodies added and removed, joints added and removed, names from small pools so that
// they meet, steps out of order), every list that loads runs to its end with every name
// applied, and the world holds exactly the joints it named after every step. A fair share must
// load and a fair share fail, or the draw tests nothing.
TEST(SceneJointActions, EveryActionListThatLoadsRuns) {
  std::uint64_t state = 0x2545F4914F6CDD1Dull;
  auto next = [&](std::size_t n) {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return static_cast<std::size_t>(state % n);
  };
  const std::vector<std::string> bodies = {"hook", "ball", "crate", "p", "q"};
  const std::vector<std::string> joints = {"rope", "j", "k"};
  const std::vector<std::string> types = {
      R"("type": "ball", "anchor": [0, 4, 0])", R"("type": "fixed", "anchor": [1, 1, 1])",
      R"("type": "hinge", "anchor": [0, 0, 0], "axis": [0, 0, 1], "limits": [-1, 1])",
      R"("type": "distance", "anchor": [0, 3, 0], "anchor_b": [0, 5, 0], "min_distance": 0)"};
  int loaded = 0, refused = 0, withJointVerbs = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string actions;
    for (int n = 1 + static_cast<int>(next(5)), i = 0; i < n; ++i) {
      const std::uint64_t step = next(6);
      std::string action;
      switch (next(4)) {
        case 0:
          // Mostly a name that is free, now and then one that is taken.
          action = R"({"step": )" + std::to_string(step) + R"(, "add": {"name": ")" + bodies[3 + next(2) - 2 * !next(4)] +
                   R"(", "shape": {"type": "sphere", "radius": 0.2}, "position": [)" + std::to_string(next(5)) +
                   R"(, 1, 0])" + (next(4) ? "" : R"(, "kind": "kinematic")") + "}}";
          break;
        case 1: action = R"({"step": )" + std::to_string(step) + R"(, "remove": ")" + bodies[next(bodies.size())] + "\"}"; break;
        case 2: {
          std::string fields = R"("a": ")" + bodies[next(bodies.size())] + "\"";
          if (next(2)) fields += R"(, "b": ")" + bodies[next(bodies.size())] + "\"";
          action = AddJoint(step, joints[next(joints.size())], fields + ", " + types[next(types.size())]);
          break;
        }
        default: action = RemoveJoint(step, joints[next(joints.size())]);
      }
      actions += (i ? ", " : "") + action;
    }
    const std::string json = Scene(actions, R"("steps": 6)");
    RScene s;
    try {
      s = ParseScene(json, "draw.json");
    } catch (const RSceneError&) {
      ++refused;
      continue;
    }
    ++loaded;
    withJointVerbs += std::any_of(s.actions.begin(), s.actions.end(), [](const RSceneAction& a) {
      return a.verb == RSceneAction::Verb::kAddJoint || a.verb == RSceneAction::Verb::kRemoveJoint;
    });
    try {
      RSceneWorld world(s);
      RunWorld(world, s, s.steps, [&](std::uint64_t k) {
        ASSERT_TRUE(world.HoldsExactlyItsJoints()) << "after step " << k << "\n" << json;
      });
    } catch (const std::exception& e) {
      ADD_FAILURE() << "loaded but did not run: " << e.what() << "\n" << json;
    }
  }
  std::printf("action lists drawn: %d loaded and ran (%d with add_joint or remove_joint), %d refused at load\n",
              loaded, withJointVerbs, refused);
  EXPECT_GT(loaded, 300);
  EXPECT_GT(withJointVerbs, 150);
  EXPECT_GT(refused, 300);
}
