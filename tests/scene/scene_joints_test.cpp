// A scene's joints (docs/scene-format.md, "Joints"): read with their documented meanings, every
// kind of bad input refused at the door with the file, the JSON path and what is wrong, and
// made by RSceneWorld after the bodies (a body an action removes takes its joints along).
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#include <gtest/gtest.h>

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

using namespace REngine;

namespace {

// Five bodies, one of each kind a joint cares about, and the joints `joints` (the list's
// contents) with `top` extra top-level fields.
std::string Scene(const std::string& joints, const std::string& top = "") {
  return "{" + top + (top.empty() ? "" : ", ") + R"("bodies": [
      {"name": "ship", "shape": {"type": "box", "half_extents": [1, 0.5, 2]}, "mass": 10, "position": [0, 1, 0]},
      {"name": "turret", "shape": {"type": "sphere", "radius": 0.5}, "position": [0, 2, 0]},
      {"name": "ground", "static": true, "shape": {"type": "box", "half_extents": [10, 0.5, 10]},
       "position": [0, -1, 0]},
      {"name": "lift", "kind": "kinematic", "shape": {"type": "box", "half_extents": [1, 0.1, 1]},
       "position": [5, 0, 0]},
      {"name": "bolted", "shape": {"type": "sphere", "radius": 0.5}, "position": [-5, 0, 0],
       "locks": {"linear": [true, true, true], "angular": [true, true, true]}}],
    "joints": [)" + joints + "]}";
}

// A joint object from its fields after "name": "j".
std::string J(const std::string& fields) { return R"({"name": "j", )" + fields + "}"; }

}  // namespace

// Each type with its fields: names kept for RSceneWorld, the axis made unit length, limits
// and motor as given, a distance joint's range -1 where left out (the starting distance),
// collide_connected false unless given; file order kept, the path kept for messages.
TEST(SceneJoints, AreReadWithTheirDocumentedMeanings) {
  const RScene s = ParseScene(Scene(R"(
      {"name": "hinge", "type": "hinge", "a": "turret", "b": "ship", "anchor": [0, 1.5, 0],
       "axis": [0, 3, 0], "limits": [-1, 2], "motor": {"speed": -0.5, "max_force": 7}},
      {"name": "ball", "type": "ball", "a": "ship", "anchor": [1, 2, 3], "collide_connected": true},
      {"name": "slider", "type": "slider", "a": "ship", "b": "lift", "anchor": [0, 0, 0],
       "axis": [1e200, 0, -1e200], "limits": [-10, 0]},
      {"name": "weld", "type": "fixed", "a": "ground", "b": "turret", "anchor": [0, 0, 0]},
      {"name": "rope", "type": "distance", "a": "turret", "anchor": [0, 2, 0], "anchor_b": [0, 5, 0],
       "min_distance": 0, "max_distance": 4},
      {"name": "rod", "type": "distance", "a": "turret", "b": "ship", "anchor": [0, 2, 0],
       "anchor_b": [0, 1, 0]})"),
                              "j.json");
  ASSERT_EQ(s.joints.size(), 6u);
  const RSceneJoint& hinge = s.joints[0];
  EXPECT_EQ(hinge.name, "hinge");
  EXPECT_EQ(hinge.path, "joints[0]");
  EXPECT_EQ(hinge.a, "turret");
  EXPECT_EQ(hinge.b, "ship");
  EXPECT_EQ(hinge.def.type, RJointType::kHinge);
  EXPECT_FALSE(hinge.def.a.IsValid()) << "handles are RSceneWorld's to fill";
  EXPECT_EQ(hinge.def.anchor_W, RVec3(0, 1.5, 0));
  EXPECT_EQ(hinge.def.axis_W, RVec3(0, 1, 0));
  EXPECT_TRUE(hinge.def.hasLimits);
  EXPECT_EQ(hinge.def.lower, -1);
  EXPECT_EQ(hinge.def.upper, 2);
  EXPECT_TRUE(hinge.def.motor.enabled);
  EXPECT_EQ(hinge.def.motor.speed, -0.5);
  EXPECT_EQ(hinge.def.motor.maxForce, 7);
  EXPECT_FALSE(hinge.def.collideConnected);

  const RSceneJoint& ball = s.joints[1];
  EXPECT_EQ(ball.def.type, RJointType::kBall);
  EXPECT_TRUE(ball.b.empty()) << "no b: the world";
  EXPECT_FALSE(ball.def.hasLimits);
  EXPECT_FALSE(ball.def.motor.enabled);
  EXPECT_TRUE(ball.def.collideConnected);

  // An axis too long to square is still a direction.
  EXPECT_LT((s.joints[2].def.axis_W - RVec3(1, 0, -1).normalized()).norm(), 1e-15);
  EXPECT_EQ(s.joints[3].def.type, RJointType::kFixed);

  const RSceneJoint& rope = s.joints[4];
  EXPECT_TRUE(rope.def.hasAnchorB);
  EXPECT_EQ(rope.def.anchorB_W, RVec3(0, 5, 0));
  EXPECT_EQ(rope.def.minDistance, 0);
  EXPECT_EQ(rope.def.maxDistance, 4);
  EXPECT_EQ(s.joints[5].def.minDistance, -1);
  EXPECT_EQ(s.joints[5].def.maxDistance, -1);

  EXPECT_TRUE(ParseScene(Scene(""), "j.json").joints.empty());
  EXPECT_TRUE(ParseScene(R"({"bodies": []})", "j.json").joints.empty());
}

// Values at the edges of what is allowed load, and RSceneWorld makes every one of them: the
// loader refuses nothing RBodies accepts here and accepts nothing it refuses.
TEST(SceneJoints, EdgeValuesLoadAndMakeTheirJoints) {
  const RScene s = ParseScene(Scene(R"(
      {"name": "full turn", "type": "hinge", "a": "turret", "anchor": [0, 0, 0], "axis": [1e-320, 0, 0],
       "limits": [-3.141592653589793, 3.141592653589793]},
      {"name": "stuck hinge", "type": "hinge", "a": "turret", "anchor": [0, 0, 0], "axis": [0, 0, 1],
       "limits": [0.5, 0.5], "motor": {"speed": 0, "max_force": 0}},
      {"name": "far slider", "type": "slider", "a": "ship", "b": "ground", "anchor": [1e15, -1e15, 0],
       "axis": [0, 0, -2], "limits": [-1e9, 1e9]},
      {"name": "kinematic partner", "type": "ball", "a": "lift", "b": "ship", "anchor": [5, 0, 0]},
      {"name": "locked partner", "type": "fixed", "a": "bolted", "b": "turret", "anchor": [0, 0, 0]},
      {"name": "taut", "type": "distance", "a": "ship", "anchor": [0, 0, 0], "anchor_b": [3, 4, 0],
       "min_distance": 5, "max_distance": 5},
      {"name": "from here", "type": "distance", "a": "ship", "anchor": [0, 0, 0], "anchor_b": [3, 4, 0],
       "max_distance": 9},
      {"name": "to here", "type": "distance", "a": "ship", "anchor": [0, 0, 0], "anchor_b": [3, 4, 0],
       "min_distance": 0},
      {"name": "no gap", "type": "distance", "a": "ship", "anchor": [0, 0, 0], "max_distance": 1e-9})"),
                              "j.json");
  ASSERT_EQ(s.joints.size(), 9u);
  RSceneWorld world(s);
  ASSERT_EQ(world.Bodies().JointCount(), 9u);
  EXPECT_EQ(world.Bodies().JointAt(0).def.axis_W, RVec3(1, 0, 0));
  EXPECT_EQ(world.Bodies().JointAt(6).minDistance, 5);
  EXPECT_EQ(world.Bodies().JointAt(6).maxDistance, 9);
  EXPECT_EQ(world.Bodies().JointAt(7).minDistance, 0);
  EXPECT_EQ(world.Bodies().JointAt(7).maxDistance, 5);
}

// One kind of bad joint: what it is, the joints list, the JSON path the error must name and
// words the message must hold (what is wrong).
struct BadJoint {
  const char* what;
  std::string joints;
  std::string path;
  std::string words;
};

void PrintTo(const BadJoint& bad, std::ostream* os) { *os << bad.what; }

// The scene `json` refused as `bad` says.
void ExpectRefused(const BadJoint& bad, const std::string& json) {
  try {
    ParseScene(json, "bad.json");
    FAIL() << bad.what << ": accepted\n" << json;
  } catch (const RSceneError& e) {
    const std::string message = e.what();
    EXPECT_EQ(e.File(), "bad.json");
    EXPECT_EQ(e.JsonPath(), bad.path) << bad.what << ": " << message;
    EXPECT_EQ(message.rfind("bad.json: " + bad.path + ": ", 0), 0u) << message;
    EXPECT_NE(e.Problem().find(bad.words), std::string::npos) << bad.what << ": " << message;
  }
}

class SceneJointsReject : public testing::TestWithParam<BadJoint> {};

TEST_P(SceneJointsReject, NamingTheFileThePathAndTheProblem) {
  const BadJoint& bad = GetParam();
  // A whole scene, or the entries of the joints list of Scene's.
  ExpectRefused(bad, bad.joints.rfind("{\"bodies\"", 0) == 0 ? bad.joints : Scene(bad.joints));
}

// An add_joint action's joint is the same object (README, "rengine-sim"), checked by the same
// code against the bodies that exist at its step: the cases above that are one joint, given as
// the add_joint of step 3 instead, with its path in place of "joints[0]" and the action's
// wording where the two differ (which bodies exist; when the anchors' distance is taken).
// Left out: the list itself (not an array, a name used across entries, the second entry's
// problem) and joining a body an action adds, which an add_joint may do.
std::vector<BadJoint> AsAddJointActions(const std::vector<BadJoint>& list) {
  const auto replace = [](std::string s, const std::string& from, const std::string& to) {
    const std::size_t at = s.find(from);
    return at == std::string::npos ? s : s.replace(at, from.size(), to);
  };
  std::vector<BadJoint> out;
  for (const BadJoint& bad : list) {
    const std::string first = "joints[0]";
    if (bad.joints.rfind("{\"bodies\"", 0) == 0 || bad.path.rfind(first, 0) != 0 ||
        bad.joints.find("\"actions\"") != std::string::npos) {
      continue;
    }
    BadJoint action = bad;
    action.joints = Scene("", R"("actions": [{"step": 3, "add_joint": )" + bad.joints + "}]");
    action.path = "actions[0].add_joint" + bad.path.substr(first.size());
    action.words = replace(replace(bad.words, "no body of the scene is named", "no body is named"),
                           "as the scene starts", "when the action applies");
    out.push_back(action);
  }
  return out;
}

class AddJointActionReject : public testing::TestWithParam<BadJoint> {};

TEST_P(AddJointActionReject, NamingTheFileTheActionsPathAndTheProblem) {
  ExpectRefused(GetParam(), GetParam().joints);
}

const std::string kBall = R"("type": "ball", "a": "ship", "anchor": [0, 0, 0])";
const std::string kHinge = R"("type": "hinge", "a": "ship", "anchor": [0, 0, 0], "axis": [0, 1, 0])";
const std::string kSlider = R"("type": "slider", "a": "ship", "anchor": [0, 0, 0], "axis": [0, 1, 0])";
const std::string kRope = R"("type": "distance", "a": "ship", "anchor": [0, 0, 0], "anchor_b": [0, 3, 0])";

const std::vector<BadJoint> kBadJoints = {
    // The list and its entries.
    {"joints not an array", R"({"bodies": [], "joints": {}})", "joints", "must be an array of joints"},
    {"joint not an object", "1", "joints[0]", "must be an object"},
    {"unknown joint field", J(kBall + R"(, "strength": 5)"), "joints[0].strength", "unknown field"},
    {"misspelt field", J(kHinge + R"(, "limit": [0, 1])"), "joints[0].limit", "unknown field"},
    {"field given twice", J(kBall + R"(, "a": "turret")"), "joints[0].a", "given twice"},
    {"no name", R"({"type": "ball", "a": "ship", "anchor": [0, 0, 0]})", "joints[0].name", "required"},
    {"empty name", R"({"name": "", "type": "ball", "a": "ship", "anchor": [0, 0, 0]})", "joints[0].name",
     "non-empty string"},
    {"duplicate name", J(kBall) + ", " + J(kHinge), "joints[1].name", "already the name of joints[0]"},
    // Type.
    {"no type", R"({"name": "j", "a": "ship", "anchor": [0, 0, 0]})", "joints[0].type", "required"},
    {"unknown type", J(R"("type": "weld", "a": "ship", "anchor": [0, 0, 0])"), "joints[0].type",
     "must be one of \"ball\", \"hinge\", \"slider\", \"fixed\", \"distance\""},
    {"type not a string", J(R"("type": 1, "a": "ship", "anchor": [0, 0, 0])"), "joints[0].type", "must be one of"},
    // Bodies.
    {"missing a", J(R"("type": "ball", "anchor": [0, 0, 0])"), "joints[0].a", "required field is missing"},
    {"a names no body", J(R"("type": "ball", "a": "ghost", "anchor": [0, 0, 0])"), "joints[0].a",
     "no body of the scene is named \"ghost\""},
    {"b names no body", J(kBall + R"(, "b": "ghost")"), "joints[0].b", "no body of the scene is named \"ghost\""},
    {"a not a string", J(R"("type": "ball", "a": 0, "anchor": [0, 0, 0])"), "joints[0].a", "non-empty string"},
    {"b null", J(kBall + R"(, "b": null)"), "joints[0].b", "non-empty string"},
    {"a and b the same body", J(kBall + R"(, "b": "ship")"), "joints[0].b", "another body than a"},
    {"static body to the world", J(R"("type": "ball", "a": "ground", "anchor": [0, 0, 0])"), "joints[0].a",
     "static or kinematic and b is the world"},
    {"kinematic body to the world", J(R"("type": "hinge", "a": "lift", "anchor": [0, 0, 0], "axis": [1, 0, 0])"),
     "joints[0].a", "static or kinematic"},
    {"static and kinematic", J(R"("type": "fixed", "a": "ground", "b": "lift", "anchor": [0, 0, 0])"),
     "joints[0].a", "both static or kinematic"},
    {"static and fully locked", J(R"("type": "fixed", "a": "bolted", "b": "ground", "anchor": [0, 0, 0])"),
     "joints[0].a", "both static or kinematic"},
    {"a body an action adds", J(R"("type": "ball", "a": "later", "anchor": [0, 0, 0])") + R"(], "actions": [
         {"step": 0, "add": {"name": "later", "shape": {"type": "sphere", "radius": 1}}})",
     "joints[0].a", "bodies the scene starts with"},
    // Anchor.
    {"missing anchor", J(R"("type": "ball", "a": "ship")"), "joints[0].anchor", "required field is missing"},
    {"anchor of 2 numbers", J(R"("type": "ball", "a": "ship", "anchor": [0, 0])"), "joints[0].anchor",
     "array of 3 numbers"},
    {"anchor NaN-like null", J(R"("type": "ball", "a": "ship", "anchor": [0, null, 0])"), "joints[0].anchor[1]",
     "finite number"},
    {"anchor overflowing", J(R"("type": "ball", "a": "ship", "anchor": [0, 0, 1e999])"), "joints[0].anchor[2]",
     "finite number"},
    {"anchor beyond 1e15 m", J(R"("type": "ball", "a": "ship", "anchor": [2e15, 0, 0])"), "joints[0].anchor",
     "within 1e15 m"},
    // Axis.
    {"hinge without axis", J(R"("type": "hinge", "a": "ship", "anchor": [0, 0, 0])"), "joints[0].axis",
     "required field is missing"},
    {"slider without axis", J(R"("type": "slider", "a": "ship", "anchor": [0, 0, 0])"), "joints[0].axis",
     "required field is missing"},
    {"zero axis", J(R"("type": "hinge", "a": "ship", "anchor": [0, 0, 0], "axis": [0, 0, 0])"), "joints[0].axis",
     "non-zero length"},
    {"negative zero axis", J(R"("type": "slider", "a": "ship", "anchor": [0, 0, 0], "axis": [-0.0, 0, -0.0])"),
     "joints[0].axis", "non-zero length"},
    {"infinite axis", J(R"("type": "hinge", "a": "ship", "anchor": [0, 0, 0], "axis": [1e400, 0, 0])"),
     "joints[0].axis[0]", "finite number"},
    {"axis on a ball joint", J(kBall + R"(, "axis": [0, 1, 0])"), "joints[0].axis",
     "only a hinge or a slider joint has axis (this is a ball joint)"},
    {"axis on a distance joint", J(kRope + R"(, "axis": [0, 1, 0])"), "joints[0].axis", "only a hinge or a slider"},
    // Limits.
    {"limits on a ball joint", J(kBall + R"(, "limits": [0, 1])"), "joints[0].limits",
     "only a hinge or a slider joint has limits"},
    {"limits on a fixed joint", J(R"("type": "fixed", "a": "ship", "anchor": [0, 0, 0], "limits": [0, 1])"),
     "joints[0].limits", "(this is a fixed joint)"},
    {"limits reversed", J(kHinge + R"(, "limits": [1, -1])"), "joints[0].limits", "lower <= upper"},
    {"slider limits reversed", J(kSlider + R"(, "limits": [0.5, 0.25])"), "joints[0].limits", "lower <= upper"},
    {"limits of 3 numbers", J(kHinge + R"(, "limits": [-1, 0, 1])"), "joints[0].limits", "array of 2 numbers"},
    {"limits a number", J(kSlider + R"(, "limits": 1)"), "joints[0].limits", "array of 2 numbers"},
    {"limit infinite", J(kSlider + R"(, "limits": [-1e999, 0])"), "joints[0].limits[0]", "finite number"},
    {"limit a string", J(kHinge + R"(, "limits": [0, "1"])"), "joints[0].limits[1]", "finite number"},
    {"hinge limit below -pi", J(kHinge + R"(, "limits": [-3.2, 0])"), "joints[0].limits", "within [-pi, pi]"},
    {"hinge limit above pi", J(kHinge + R"(, "limits": [0, 3.1416])"), "joints[0].limits", "within [-pi, pi]"},
    // Motor.
    {"motor on a ball joint", J(kBall + R"(, "motor": {"speed": 1, "max_force": 1})"), "joints[0].motor",
     "only a hinge or a slider joint has motor"},
    {"motor not an object", J(kHinge + R"(, "motor": 5)"), "joints[0].motor", "must be an object"},
    {"motor without speed", J(kHinge + R"(, "motor": {"max_force": 1})"), "joints[0].motor.speed", "required"},
    {"motor without force", J(kSlider + R"(, "motor": {"speed": 1})"), "joints[0].motor.max_force", "required"},
    {"negative motor force", J(kHinge + R"(, "motor": {"speed": 1, "max_force": -1})"),
     "joints[0].motor.max_force", "finite number >= 0"},
    {"infinite motor speed", J(kSlider + R"(, "motor": {"speed": 1e999, "max_force": 1})"),
     "joints[0].motor.speed", "finite number"},
    // RBodies::AddJoint's bounds (RLimits.h): a motor of 1e300 ran, its impulses beyond any state's.
    {"motor speed beyond 1e15", J(kSlider + R"(, "motor": {"speed": -1.000001e15, "max_force": 1})"),
     "joints[0].motor.speed", "a finite number within 1e15 (got -1.000001e+15)"},
    {"motor force beyond 1e30", J(kHinge + R"(, "motor": {"speed": 1, "max_force": 1e300})"),
     "joints[0].motor.max_force", "a finite number >= 0 and at most 1e30 (got 1e+300)"},
    {"unknown motor field", J(kHinge + R"(, "motor": {"speed": 1, "max_force": 1, "torque": 2})"),
     "joints[0].motor.torque", "unknown field"},
    // Distance.
    {"anchor_b on a ball joint", J(kBall + R"(, "anchor_b": [0, 1, 0])"), "joints[0].anchor_b",
     "only a distance joint has anchor_b (this is a ball joint)"},
    {"anchor_b on a slider", J(kSlider + R"(, "anchor_b": [0, 1, 0])"), "joints[0].anchor_b",
     "only a distance joint"},
    {"max_distance on a hinge", J(kHinge + R"(, "max_distance": 1)"), "joints[0].max_distance",
     "only a distance joint has max_distance"},
    {"anchor_b not finite", J(R"("type": "distance", "a": "ship", "anchor": [0, 0, 0], "anchor_b": [0, 1e999, 0])"),
     "joints[0].anchor_b[1]", "finite number"},
    {"anchor_b beyond 1e15 m",
     J(R"("type": "distance", "a": "ship", "anchor": [0, 0, 0], "anchor_b": [0, 0, -1e16])"), "joints[0].anchor_b",
     "within 1e15 m"},
    {"min above max", J(kRope + R"(, "min_distance": 2, "max_distance": 1)"), "joints[0].min_distance",
     "must not exceed max_distance"},
    {"min above the starting distance", J(kRope + R"(, "min_distance": 4)"), "joints[0].min_distance",
     "must not exceed max_distance (3 m)"},
    {"max below the starting distance", J(kRope + R"(, "max_distance": 2)"), "joints[0].max_distance",
     "less than the anchors' distance as the scene starts (3 m)"},
    {"negative min", J(kRope + R"(, "min_distance": -1)"), "joints[0].min_distance", "finite number >= 0"},
    {"max a string", J(kRope + R"(, "max_distance": "2")"), "joints[0].max_distance", "finite number >= 0"},
    {"anchors together and no range", J(R"("type": "distance", "a": "ship", "anchor": [0, 0, 0])"), "joints[0]",
     "needs max_distance > 0"},
    {"zero max_distance", J(R"("type": "distance", "a": "ship", "anchor": [0, 0, 0], "max_distance": 0)"),
     "joints[0].max_distance", "ball joint"},
    // The rest.
    {"collide_connected not a boolean", J(kBall + R"(, "collide_connected": "no")"), "joints[0].collide_connected",
     "true or false"},
    {"the second joint's problem", J(kBall) + R"(, {"name": "k", "type": "ball", "a": "ship", "b": "shp",
         "anchor": [0, 0, 0]})",
     "joints[1].b", "no body of the scene is named \"shp\""},
};

std::string BadJointName(const testing::TestParamInfo<BadJoint>& param) {
  std::string name = param.param.what;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}
INSTANTIATE_TEST_SUITE_P(BadInput, SceneJointsReject, testing::ValuesIn(kBadJoints), BadJointName);
INSTANTIATE_TEST_SUITE_P(BadInput, AddJointActionReject, testing::ValuesIn(AsAddJointActions(kBadJoints)),
                         BadJointName);

// Only the four cases about the list and the body an action adds are left out of the actions'.
TEST(SceneJoints, EveryBadJointButTheListsIsABadAddJoint) {
  EXPECT_EQ(kBadJoints.size(), 67u);
  EXPECT_EQ(AsAddJointActions(kBadJoints).size(), kBadJoints.size() - 4);
}

TEST(SceneJoints, ErrorsReadAsTheyShould) {
  try {
    ParseScene(Scene(J(kHinge + R"(, "limits": [0.5, -0.5])")), "crane.json");
    FAIL();
  } catch (const RSceneError& e) {
    EXPECT_STREQ(e.what(), "crane.json: joints[0].limits: must be [lower, upper] with lower <= upper "
                           "(got [0.5,-0.5])");
  }
}

// RSceneLimits::maxJoints bounds the list, named "joints".
TEST(SceneJoints, TheLimitCountsThem) {
  const std::string two = Scene(J(kBall) + R"(, {"name": "k", )" + kHinge + "}");
  RSceneLimits limits;
  limits.maxJoints = 1;
  try {
    ParseScene(two, "many.json", limits);
    FAIL();
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.JsonPath(), "joints");
    EXPECT_NE(e.Problem().find("at most 1 are allowed"), std::string::npos) << e.what();
  }
  limits.maxJoints = 2;
  EXPECT_EQ(ParseScene(two, "many.json", limits).joints.size(), 2u);
  EXPECT_EQ(RSceneLimits{}.maxJoints, 1000000u);
}

// RSceneWorld adds the joints after the bodies, with their handles and the frames the bodies
// have at the start; a body an action removes takes its joints with it, the others stay.
TEST(SceneJoints, TheWorldMakesThemAndARemovalTakesItsJoints) {
  const RScene s = ParseScene(Scene(R"(
      {"name": "mount", "type": "hinge", "a": "turret", "b": "ship", "anchor": [0, 1.5, 0], "axis": [0, 1, 0]},
      {"name": "tether", "type": "distance", "a": "ship", "anchor": [0, 1, 0], "anchor_b": [0, 10, 0],
       "min_distance": 0})",
                                    R"("steps": 10, "actions": [{"step": 3, "remove": "turret"}])"),
                              "j.json");
  RSceneWorld world(s);
  const RBodies& bodies = world.Bodies();
  ASSERT_EQ(bodies.JointCount(), 2u);
  const RJoint& mount = bodies.JointAt(0);
  EXPECT_EQ(mount.def.a, world.Find("turret"));
  EXPECT_EQ(mount.def.b, world.Find("ship"));
  // Each body keeps the anchor where the scene put it, as the bodies stand at the start.
  const RRigidBody& turret = bodies[mount.def.a];
  const RRigidBody& ship = bodies[mount.def.b];
  EXPECT_LT((turret.Position_W() + turret.Orientation_WB() * mount.anchorA_B - RVec3(0, 1.5, 0)).norm(), 1e-15);
  EXPECT_LT((ship.Position_W() + ship.Orientation_WB() * mount.anchorB_B - RVec3(0, 1.5, 0)).norm(), 1e-15);
  EXPECT_LT((ship.Orientation_WB() * mount.axisB_B - RVec3(0, 1, 0)).norm(), 1e-15);
  const RJoint& tether = bodies.JointAt(1);
  EXPECT_EQ(tether.def.a, world.Find("ship"));
  EXPECT_FALSE(tether.def.b.IsValid());
  EXPECT_EQ(tether.maxDistance, 9);

  RIntegrator integrator(s.settings);
  world.ApplyActions(0);
  for (std::uint64_t k = 1; k <= s.steps; ++k) {
    integrator.Update(world.Bodies(), s.dt);
    world.ApplyActions(k);
    EXPECT_EQ(bodies.JointCount(), k < 3 ? 2u : 1u) << "after step " << k;
  }
  EXPECT_EQ(bodies.JointAt(0).def.a, world.Find("ship"));
  EXPECT_EQ(bodies.JointAt(0).def.type, RJointType::kDistance);
}

// A joint RBodies refuses when RSceneWorld makes it (a scene put together in code, past the
// loader's checks) is an RSceneError named by the joint's path and RJointError's field.
TEST(SceneJoints, AnEngineRefusalIsNamedByTheJointsPath) {
  RScene s = ParseScene(Scene(J(kBall)), "code.json");
  s.joints[0].def.hasLimits = true;
  s.joints[0].def.lower = 0, s.joints[0].def.upper = 1;
  try {
    RSceneWorld world(s);
    FAIL();
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.File(), "code.json");
    EXPECT_EQ(e.JsonPath(), "joints[0].limits");
    EXPECT_NE(e.Problem().find("only a hinge or a slider"), std::string::npos) << e.what();
  }
}

// The loader makes every check RBodies::AddJoint makes: of 3000 joints drawn from a fixed
// seed (types, bodies of every kind, and values at and across each edge: zero, denormal and
// huge axes, coordinates at 1e15 m, hinge limits at and beyond pi, crossed distances), each
// one that loads is made by RSceneWorld. A fair share must load and a fair share fail, or
// the draw tests nothing.
TEST(SceneJoints, EveryJointThatLoadsIsMade) {
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&](std::size_t n) {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return static_cast<std::size_t>(state % n);
  };
  const std::vector<std::string> types = {"ball", "hinge", "slider", "fixed", "distance"};
  const std::vector<std::string> names = {"ship", "turret", "ground", "lift", "bolted"};
  const std::vector<std::string> numbers = {"0", "-0.0", "1", "-1", "2.5", "1e-320", "1e200", "1e15",
                                            "1.0000001e15", "3.141592653589793", "-3.141592653589793",
                                            "3.1416", "-7", "0.5"};
  auto number = [&] { return numbers[next(numbers.size())]; };
  auto vec = [&] { return "[" + number() + ", " + number() + ", " + number() + "]"; };
  int loaded = 0, refused = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // Mostly the type's own fields, now and then another type's.
    const std::size_t type = next(types.size());
    const bool axial = type == 1 || type == 2, distance = type == 4;
    auto maybe = [&](bool own, std::size_t ownIn, std::size_t otherIn) {
      return next(own ? ownIn : otherIn) == 0;
    };
    std::string fields = R"("type": ")" + types[type] + R"(", "a": ")" +
                         names[next(4) ? next(2) : next(names.size())] + "\"";
    if (next(2)) fields += R"(, "b": ")" + names[next(names.size())] + "\"";
    fields += R"(, "anchor": )" + vec();
    if (maybe(axial, 1, 20)) fields += R"(, "axis": )" + vec();
    if (maybe(axial, 2, 20)) fields += R"(, "limits": [)" + number() + ", " + number() + "]";
    if (maybe(axial, 3, 20)) {
      fields += R"(, "motor": {"speed": )" + number() + R"(, "max_force": )" + number() + "}";
    }
    if (maybe(distance, 2, 20)) fields += R"(, "anchor_b": )" + vec();
    if (maybe(distance, 2, 20)) fields += R"(, "min_distance": )" + number();
    if (maybe(distance, 2, 20)) fields += R"(, "max_distance": )" + number();
    const std::string json = Scene(J(fields));
    RScene s;
    try {
      s = ParseScene(json, "draw.json");
    } catch (const RSceneError&) {
      ++refused;
      continue;
    }
    ++loaded;
    try {
      RSceneWorld world(s);
      ASSERT_EQ(world.Bodies().JointCount(), 1u);
    } catch (const RSceneError& e) {
      ADD_FAILURE() << "loaded but not made: " << e.what() << "\n" << json;
    }
  }
  std::printf("joints drawn: %d loaded and made, %d refused at load\n", loaded, refused);
  EXPECT_GT(loaded, 300);
  EXPECT_GT(refused, 300);
}
