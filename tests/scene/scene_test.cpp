// Scene files: the reference scenes (scenes/) load with their values, defaults are the
// documented ones, equal shapes share one prepared shape, and the edge values, ignore lists
// and rays a scene may hold are read as documented. Bad input: scene_rejects_test.cpp.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RScene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scene/SceneText.h"
#include "support/ReferenceScenes.h"

using namespace REngine;
using namespace REngine::test;
using namespace REngine::test::scenetext;

TEST(Scene, ReferenceScenesLoadWithTheirValues) {
  {
    const RScene s = LoadScene(ReferenceScenePath("dzhanibekov"));
    ASSERT_EQ(s.bodies.size(), 1u);
    const RBodyDef& b = s.bodies[0];
    EXPECT_EQ(b.name, "tbar");
    EXPECT_EQ(b.shape.type, RShapeType::kBox);
    EXPECT_EQ(b.shape.halfExtents, RVec3(0.5, 1.0, 1.5));
    ASSERT_TRUE(b.mass.has_value());
    EXPECT_EQ(*b.mass, 1.0);
    EXPECT_EQ(b.angularVelocity_W, RVec3(0.01, 5.0, 0.01));
    EXPECT_EQ(s.steps, 36000u);
    EXPECT_EQ(s.dt, 0.016666666666666666);
    EXPECT_EQ(s.settings.gravity_W, RVec3::Zero());
  }
  {
    const RScene s = LoadScene(ReferenceScenePath("head_on_elastic"));
    ASSERT_EQ(s.bodies.size(), 2u);
    EXPECT_EQ(s.steps, 240u);
    EXPECT_EQ(s.dt, 0.008333333333333333);
    EXPECT_EQ(s.settings.restitutionCombine, RCombineMode::kMin);
    EXPECT_EQ(s.bodies[0].shape.type, RShapeType::kSphere);
    EXPECT_EQ(s.bodies[0].shape.radius, 0.5);
    EXPECT_EQ(*s.bodies[1].mass, 3.0);
    EXPECT_EQ(s.bodies[1].velocity_W, RVec3(-1, 0, 0));
    EXPECT_EQ(s.bodies[1].restitution, 1.0);
    EXPECT_EQ(s.bodies[1].friction, 0.0);
  }
  {
    const RScene s = LoadScene(ReferenceScenePath("box_stack_10"));
    ASSERT_EQ(s.bodies.size(), 11u);
    EXPECT_EQ(s.settings.gravity_W, RVec3(0, -9.81, 0));
    EXPECT_EQ(s.bodies[0].kind, RBodyKind::kStatic);
    EXPECT_EQ(s.bodies[0].shape.halfExtents, RVec3(50, 0.5, 50));
    EXPECT_EQ(s.bodies[10].name, "box9");
    EXPECT_EQ(s.bodies[10].position_W, RVec3(0, 9.5, 0));
  }
  {
    const RScene s = LoadScene(ReferenceScenePath("debris_cloud_1000"));
    ASSERT_EQ(s.bodies.size(), 1000u);
    EXPECT_EQ(s.steps, 600u);
    // The file's quaternions are unit already: normalising must keep them to rounding.
    const RQuat q(-0.19326972277945167, -0.23191723553917554, -0.14930901864932258,
                  0.9415774142717086);
    EXPECT_LT(QuatAngleBetween(s.bodies[0].q_WS, q), 1e-15);
    EXPECT_NEAR(s.bodies[0].q_WS.w(), q.w(), 1e-16);
    for (const RBodyDef& b : s.bodies) {
      EXPECT_EQ(b.restitution, 1.0);
      EXPECT_EQ(b.friction, 0.0);
    }
  }
  {
    const RScene s = LoadScene(ReferenceScenePath("box_pile_1000"));
    ASSERT_EQ(s.bodies.size(), 1001u);
    EXPECT_EQ(s.steps, 300u);
    EXPECT_EQ(s.bodies[0].kind, RBodyKind::kStatic);
    EXPECT_EQ(s.bodies[1000].name, "p999");
  }
}

TEST(Scene, ReferenceScenesCreateTheirBodies) {
  for (const char* name : {"dzhanibekov", "head_on_elastic", "box_stack_10",
                           "debris_cloud_1000", "box_pile_1000"}) {
    const RScene scene = LoadScene(ReferenceScenePath(name));
    EXPECT_EQ(CreateBodies(scene).size(), scene.bodies.size()) << name;
    EXPECT_EQ(scene.ignore.size(), scene.bodies.size()) << name;
  }
}

TEST(Scene, DefaultsAreTheDocumentedOnes) {
  const RScene s =
      ParseScene(OneBody(R"("shape": {"type": "box", "half_extents": [1, 2, 3]})"), "d.json");
  EXPECT_EQ(s.settings.gravity_W, RVec3::Zero());
  EXPECT_EQ(s.dt, 1.0 / 60);
  EXPECT_EQ(s.steps, 600u);
  EXPECT_EQ(s.settings.restitutionCombine, RCombineMode::kMin);
  EXPECT_EQ(s.settings.frictionCombine, RCombineMode::kGeometric);
  EXPECT_EQ(s.settings.solverIterations, RWorldSettings().solverIterations);
  ASSERT_EQ(s.bodies.size(), 1u);
  const RBodyDef& b = s.bodies[0];
  EXPECT_EQ(b.kind, RBodyKind::kDynamic);
  EXPECT_FALSE(b.mass.has_value());
  EXPECT_EQ(b.density, 1.0);
  EXPECT_EQ(b.position_W, RVec3::Zero());
  EXPECT_EQ(b.q_WS.coeffs(), RQuat::Identity().coeffs());
  EXPECT_EQ(b.velocity_W, RVec3::Zero());
  EXPECT_EQ(b.angularVelocity_W, RVec3::Zero());
  EXPECT_EQ(b.restitution, 0.5);
  EXPECT_EQ(b.friction, 0.5);
  EXPECT_TRUE(b.responds);
  EXPECT_EQ(b.category, 1u);
  EXPECT_EQ(b.mask, 4294967295u);
  EXPECT_TRUE(s.ignore[0].empty());
  // Density 1: the mass is the volume, 2 * 4 * 6 m^3.
  EXPECT_DOUBLE_EQ(CreateBodies(s)[0].Mass(), 48.0);
}

// Equal shapes share one prepared shape, and shapes that differ in any field do not: two
// capsules of one radius and two lengths keep their own lengths and masses.
TEST(Scene, CapsulesOfOneRadiusAndTwoLengthsStayApart) {
  const RScene s = ParseScene(R"({"bodies": [
      {"name": "short", "shape": {"type": "capsule", "radius": 0.5, "half_height": 0.5}},
      {"name": "long", "shape": {"type": "capsule", "radius": 0.5, "half_height": 3}, "position": [5, 0, 0]},
      {"name": "again", "shape": {"type": "capsule", "radius": 0.5, "half_height": 3}, "position": [9, 0, 0]}]})",
                              "capsules.json");
  const std::vector<RRigidBody> bodies = CreateBodies(s);
  EXPECT_EQ(bodies[0].Shape().halfHeight, 0.5);
  EXPECT_EQ(bodies[1].Shape().halfHeight, 3.0);
  EXPECT_NEAR(bodies[1].Mass(), 3.14159265358979 * 0.25 * 6 + 4.0 / 3 * 3.14159265358979 * 0.125, 1e-12);
  EXPECT_NE(bodies[0].PreparedShape(), bodies[1].PreparedShape());
  EXPECT_EQ(bodies[1].PreparedShape(), bodies[2].PreparedShape());
}

// A cylinder and a capsule of the same radius and half height are different shapes.
TEST(Scene, ACylinderAndACapsuleOfOneSizeStayApart) {
  const RScene s = ParseScene(R"({"bodies": [
      {"name": "can", "shape": {"type": "cylinder", "radius": 0.5, "half_height": 3}},
      {"name": "pill", "shape": {"type": "capsule", "radius": 0.5, "half_height": 3}, "position": [5, 0, 0]},
      {"name": "can2", "shape": {"type": "cylinder", "radius": 0.5, "half_height": 3}, "position": [9, 0, 0]}]})",
                              "cylinders.json");
  const std::vector<RRigidBody> bodies = CreateBodies(s);
  EXPECT_EQ(bodies[0].Shape().type, RShapeType::kCylinder);
  EXPECT_NEAR(bodies[0].Mass(), 3.14159265358979 * 0.25 * 6, 1e-12);
  EXPECT_NE(bodies[0].PreparedShape(), bodies[1].PreparedShape());
  EXPECT_EQ(bodies[0].PreparedShape(), bodies[2].PreparedShape());
}

// Compounds that differ only in one child's density are different shapes; equal ones share
// their prepared shape.
TEST(Scene, CompoundsShareOnlyWhenEqualInEveryChild) {
  const RScene s = ParseScene(R"({"bodies": [
      {"name": "a", "shape": {"type": "compound", "children": [{"shape": {"type": "box", "half_extents": [1, 1, 1]}},
                                                               {"shape": {"type": "sphere", "radius": 1}, "position": [2, 0, 0]}]}},
      {"name": "b", "shape": {"type": "compound", "children": [{"shape": {"type": "box", "half_extents": [1, 1, 1]}},
                                                               {"shape": {"type": "sphere", "radius": 1}, "position": [2, 0, 0], "density": 2}]},
       "position": [9, 0, 0]},
      {"name": "c", "shape": {"type": "compound", "children": [{"shape": {"type": "box", "half_extents": [1, 1, 1]}},
                                                               {"shape": {"type": "sphere", "radius": 1}, "position": [2, 0, 0]}]},
       "position": [19, 0, 0]}]})",
                              "compounds.json");
  const std::vector<RRigidBody> bodies = CreateBodies(s);
  const double sphere = 4.0 / 3 * 3.14159265358979323846;
  EXPECT_NEAR(bodies[0].Mass(), 8 + sphere, 1e-12);
  EXPECT_NEAR(bodies[1].Mass(), 8 + 2 * sphere, 1e-12);
  EXPECT_NE(bodies[0].PreparedShape(), bodies[1].PreparedShape());
  EXPECT_EQ(bodies[0].PreparedShape(), bodies[2].PreparedShape());
}

TEST(Scene, TheFormatDocumentsExampleLoads) {
  const std::string text = R"({
    "format": "rengine-scene/1",
    "gravity": [0, -9.81, 0],
    "dt": 0.016666666666666666,
    "steps": 600,
    "restitution_combine": "max",
    "friction_combine": "average",
    "solver": { "iterations": 7, "sleeping": false },
    "bodies": [
      { "name": "ground", "shape": { "type": "box", "half_extents": [50, 0.5, 50] },
        "static": true, "position": [0, -0.5, 0] },
      { "name": "crate", "shape": { "type": "box", "half_extents": [0.5, 0.5, 0.5] },
        "mass": 1.0, "position": [0, 0.5, 0], "orientation": [1, 0, 0, 0],
        "velocity": [0, 0, 0], "angular_velocity": [0, 0, 0],
        "restitution": 0.0, "friction": 0.5, "responds": false },
      { "name": "ball", "shape": { "type": "sphere", "radius": 0.5 }, "density": 2.0,
        "position": [3, 2, 0] },
      { "name": "rock", "shape": { "type": "hull",
                                   "points": [[1, 0, 0], [0, 1, 0], [0, 0, 1], [-1, -1, -1]] },
        "mass": 4.0, "position": [0, 5, 0] }
    ]
  })";
  const RScene s = ParseScene(text, "example.json");
  EXPECT_EQ(s.settings.restitutionCombine, RCombineMode::kMax);
  EXPECT_EQ(s.settings.frictionCombine, RCombineMode::kAverage);
  EXPECT_EQ(s.settings.solverIterations, 7);
  EXPECT_FALSE(s.settings.shortcuts.sleeping);
  EXPECT_TRUE(RWorldSettings().shortcuts.sleeping) << "on unless the scene says otherwise";
  ASSERT_EQ(s.bodies.size(), 4u);
  EXPECT_FALSE(s.bodies[1].responds);
  EXPECT_EQ(s.bodies[2].density, 2.0);
  EXPECT_FALSE(s.bodies[2].mass.has_value());
  EXPECT_EQ(s.bodies[3].shape.type, RShapeType::kHull);
  ASSERT_EQ(s.bodies[3].shape.points.size(), 4u);
  EXPECT_EQ(s.bodies[3].shape.points[3], RVec3(-1, -1, -1));
}

TEST(Scene, OrientationIsNormalised) {
  const RScene s = ParseScene(OneBody(Sphere(R"("orientation": [0.9, 0.1, 0.3, 0.2])")), "q.json");
  const RQuat q = s.bodies[0].q_WS;
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
  const double n = std::sqrt(0.81 + 0.01 + 0.09 + 0.04);
  EXPECT_NEAR(q.w(), 0.9 / n, 1e-15);
  EXPECT_NEAR(q.x(), 0.1 / n, 1e-15);
  EXPECT_NEAR(q.y(), 0.3 / n, 1e-15);
  EXPECT_NEAR(q.z(), 0.2 / n, 1e-15);
}

TEST(Scene, IgnoreListsAreSymmetricSortedAndUnique) {
  const std::string sphere = R"("shape": {"type": "sphere", "radius": 1})";
  const RScene s = ParseScene(R"({"bodies": [
      {"name": "a", )" + sphere + R"(, "ignore": ["c", "b", "c"]},
      {"name": "b", )" + sphere + R"(},
      {"name": "c", )" + sphere + R"(, "ignore": ["a"]},
      {"name": "d", )" + sphere + R"(, "ignore": ["b"]}]})",
                              "ignore.json");
  using V = std::vector<std::size_t>;
  ASSERT_EQ(s.ignore.size(), 4u);
  EXPECT_EQ(s.ignore[0], (V{1, 2}));
  EXPECT_EQ(s.ignore[1], (V{0, 3}));
  EXPECT_EQ(s.ignore[2], (V{0}));
  EXPECT_EQ(s.ignore[3], (V{1}));
}

TEST(Scene, AcceptedEdgeValues) {
  // Whole numbers written as floating point are the integers they are.
  EXPECT_EQ(ParseScene(OneBody(kSphere, R"("steps": 600.0)"), "s.json").steps, 600u);
  EXPECT_EQ(ParseScene(OneBody(kSphere, R"("steps": 6e2)"), "s.json").steps, 600u);
  EXPECT_EQ(ParseScene(OneBody(kSphere, R"("steps": 0)"), "s.json").steps, 0u);
  // Restitution at both ends of [0, 1]; zero friction.
  EXPECT_EQ(ParseScene(OneBody(Sphere(R"("restitution": 1)")), "s.json").bodies[0].restitution,
            1.0);
  EXPECT_EQ(ParseScene(OneBody(Sphere(R"("restitution": 0)")), "s.json").bodies[0].restitution,
            0.0);
  EXPECT_EQ(ParseScene(OneBody(Sphere(R"("friction": 0)")), "s.json").bodies[0].friction, 0.0);
  // Filter bits: the whole unsigned 32-bit range, 0 included (a body that collides with
  // nothing), and whole numbers written as floating point.
  const RScene bits =
      ParseScene(OneBody(Sphere(R"("category": 0, "mask": 4294967295.0)")), "s.json");
  EXPECT_EQ(bits.bodies[0].category, 0u);
  EXPECT_EQ(bits.bodies[0].mask, 4294967295u);
  EXPECT_EQ(CreateBodies(bits)[0].Mask(), 4294967295u);
  // A static body may keep its mass; it is ignored.
  const RScene s = ParseScene(OneBody(Sphere(R"("static": true, "mass": 5)")), "s.json");
  EXPECT_EQ(CreateBodies(s)[0].Mass(), 0.0);
  // No bodies at all is a valid, empty world.
  EXPECT_TRUE(ParseScene(R"({"bodies": []})", "s.json").bodies.empty());
}

// "rays": read with their defaults (mask all bits, nearest only), sorted by step stably, the
// path kept for messages.
TEST(Scene, RaysAreReadSortedByStepWithTheirDefaults) {
  const RScene s = ParseScene(OneBody(kSphere, R"("steps": 9, "rays": [
      {"name": "b", "step": 4, "origin": [1, 2, 3], "direction": [0, 0, 2], "max_distance": 0},
      {"name": "a", "step": 2, "origin": [0, 0, 0], "direction": [1, 0, 0], "max_distance": 5,
       "mask": 6, "all": true},
      {"name": "c", "step": 4, "origin": [0, 0, 0], "direction": [1e-300, 0, 0], "max_distance": 5}])"),
                              "s.json");
  ASSERT_EQ(s.rays.size(), 3u);
  EXPECT_EQ(s.rays[0].name, "a");
  EXPECT_EQ(s.rays[0].path, "rays[1]");
  EXPECT_EQ(s.rays[0].mask, 6u);
  EXPECT_TRUE(s.rays[0].all);
  EXPECT_EQ(s.rays[1].name, "b");
  EXPECT_EQ(s.rays[1].step, 4u);
  EXPECT_EQ(s.rays[1].origin_W, RVec3(1, 2, 3));
  EXPECT_EQ(s.rays[1].direction_W, RVec3(0, 0, 2));
  EXPECT_EQ(s.rays[1].maxDistance, 0.0);
  EXPECT_EQ(s.rays[1].mask, 4294967295u);
  EXPECT_FALSE(s.rays[1].all);
  EXPECT_EQ(s.rays[2].name, "c");
  EXPECT_TRUE(ParseScene(OneBody(kSphere), "s.json").rays.empty());
  try {
    ParseScene(OneBody(kSphere, R"("steps": 3, "rays": [
        {"name": "a", "step": 4, "origin": [0, 0, 0], "direction": [1, 0, 0], "max_distance": 1}])"),
               "s.json");
    FAIL() << "a ray after the last step was accepted";
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.JsonPath(), "rays[0].step");
  }
}
