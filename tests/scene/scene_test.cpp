// Scene files: the reference scenes (scenes/) load with their values, defaults are the
// documented ones, and every kind of bad input is refused with the file and the JSON path.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RScene.h>

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "support/ReferenceScenes.h"

using namespace REngine;
using namespace REngine::test;

namespace {


// A valid scene with one body named "a": `body` holds the body's other fields (its shape
// at least), `top` extra top-level fields.
std::string OneBody(const std::string& body, const std::string& top = "") {
  return "{" + top + (top.empty() ? "" : ", ") + R"("bodies": [{"name": "a", )" + body + "}]}";
}
const std::string kSphere = R"("shape": {"type": "sphere", "radius": 1})";
std::string Sphere(const std::string& more) { return kSphere + ", " + more; }
std::string Shape(const std::string& shape) { return R"("shape": )" + shape; }

}  // namespace

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

// One kind of bad input: what it is, the scene text, the JSON path the error must name.
struct BadScene {
  const char* what;
  std::string json;
  std::string path;  // "" for a problem with the file as a whole
};

void PrintTo(const BadScene& bad, std::ostream* os) { *os << bad.what; }

class SceneRejects : public testing::TestWithParam<BadScene> {};

TEST_P(SceneRejects, NamingTheFileAndThePath) {
  const BadScene& bad = GetParam();
  try {
    ParseScene(bad.json, "bad.json");
    FAIL() << bad.what << ": accepted\n" << bad.json;
  } catch (const RSceneError& e) {
    const std::string message = e.what();
    EXPECT_EQ(e.File(), "bad.json");
    EXPECT_EQ(e.JsonPath(), bad.path) << bad.what << ": " << message;
    const std::string prefix = "bad.json: " + (bad.path.empty() ? "" : bad.path + ": ");
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
    EXPECT_GT(message.size(), prefix.size()) << "no problem stated: " << message;
  }
}

const std::vector<BadScene> kBadScenes = {
    // The file as a whole.
    {"syntax error", R"({"bodies": [}")", ""},
    {"text after the scene", R"({"bodies": []} x)", ""},
    {"empty file", "", ""},
    {"not an object", "[]", ""},
    {"number overflowing to infinity", OneBody(kSphere, R"("gravity": [0, 1e999, 0])"),
     "gravity[1]"},
    {"negative overflow", OneBody(Sphere(R"("velocity": [0, 0, -1e400])")),
     "bodies[0].velocity[2]"},
    {"top-level field given twice", R"({"dt": 0.1, "dt": 0.2, "bodies": []})", "dt"},
    {"body field given twice", OneBody(Sphere(R"("mass": 1, "mass": 2)")), "bodies[0].mass"},
    // Top level.
    {"unknown top-level field", OneBody(kSphere, R"("gravty": [0, 0, 0])"), "gravty"},
    {"other format", OneBody(kSphere, R"("format": "rengine-scene/2")"), "format"},
    {"format not a string", OneBody(kSphere, R"("format": 1)"), "format"},
    {"gravity of 2 numbers", OneBody(kSphere, R"("gravity": [0, -9.81])"), "gravity"},
    {"gravity of 4 numbers", OneBody(kSphere, R"("gravity": [0, -9.81, 0, 0])"), "gravity"},
    {"gravity not an array", OneBody(kSphere, R"("gravity": -9.81)"), "gravity"},
    {"gravity component a string", OneBody(kSphere, R"("gravity": [0, 0, "0"])"), "gravity[2]"},
    {"gravity component null", OneBody(kSphere, R"("gravity": [null, 0, 0])"), "gravity[0]"},
    {"zero dt", OneBody(kSphere, R"("dt": 0)"), "dt"},
    {"negative dt", OneBody(kSphere, R"("dt": -0.01)"), "dt"},
    {"dt a string", OneBody(kSphere, R"("dt": "0.01")"), "dt"},
    {"infinite dt", OneBody(kSphere, R"("dt": 1e999)"), "dt"},
    {"negative steps", OneBody(kSphere, R"("steps": -1)"), "steps"},
    {"fractional steps", OneBody(kSphere, R"("steps": 1.5)"), "steps"},
    {"steps beyond 2^64", OneBody(kSphere, R"("steps": 1e20)"), "steps"},
    {"steps a boolean", OneBody(kSphere, R"("steps": true)"), "steps"},
    {"restitution combine not in its set",
     OneBody(kSphere, R"("restitution_combine": "geometric")"), "restitution_combine"},
    {"friction combine unknown", OneBody(kSphere, R"("friction_combine": "median")"),
     "friction_combine"},
    {"combine mode not a string", OneBody(kSphere, R"("friction_combine": 1)"),
     "friction_combine"},
    {"solver not an object", OneBody(kSphere, R"("solver": 10)"), "solver"},
    {"unknown solver key", OneBody(kSphere, R"("solver": {"iters": 10})"), "solver.iters"},
    {"zero solver iterations", OneBody(kSphere, R"("solver": {"iterations": 0})"),
     "solver.iterations"},
    {"sleeping not a boolean", OneBody(kSphere, R"("solver": {"sleeping": 1})"),
     "solver.sleeping"},
    {"fractional solver iterations", OneBody(kSphere, R"("solver": {"iterations": 2.5})"),
     "solver.iterations"},
    {"solver iterations beyond int", OneBody(kSphere, R"("solver": {"iterations": 3000000000})"),
     "solver.iterations"},
    {"no bodies", R"({"dt": 0.01})", "bodies"},
    {"bodies not an array", R"({"bodies": {}})", "bodies"},
    {"body not an object", R"({"bodies": [1]})", "bodies[0]"},
    // Body fields.
    {"no name", R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}}]})", "bodies[0].name"},
    {"empty name", R"({"bodies": [{"name": "", "shape": {"type": "sphere", "radius": 1}}]})",
     "bodies[0].name"},
    {"name not a string", R"({"bodies": [{"name": 7, "shape": {"type": "sphere", "radius": 1}}]})",
     "bodies[0].name"},
    {"duplicate name", R"({"bodies": [{"name": "a", "shape": {"type": "sphere", "radius": 1}},
                                      {"name": "a", "shape": {"type": "sphere", "radius": 1}}]})",
     "bodies[1].name"},
    {"unknown body field", OneBody(Sphere(R"("restitutoin": 0.5)")), "bodies[0].restitutoin"},
    {"static not a boolean", OneBody(Sphere(R"("static": "yes")")), "bodies[0].static"},
    {"zero mass", OneBody(Sphere(R"("mass": 0)")), "bodies[0].mass"},
    {"negative mass", OneBody(Sphere(R"("mass": -1)")), "bodies[0].mass"},
    {"mass a string", OneBody(Sphere(R"("mass": "1")")), "bodies[0].mass"},
    {"negative mass on a static body", OneBody(Sphere(R"("static": true, "mass": -1)")),
     "bodies[0].mass"},
    {"zero density", OneBody(Sphere(R"("density": 0)")), "bodies[0].density"},
    {"mass and density", OneBody(Sphere(R"("mass": 1, "density": 1)")), "bodies[0].density"},
    {"position of 2 numbers", OneBody(Sphere(R"("position": [0, 0])")), "bodies[0].position"},
    {"position component a string", OneBody(Sphere(R"("position": [0, "x", 0])")),
     "bodies[0].position[1]"},
    {"velocity not an array", OneBody(Sphere(R"("velocity": 3)")), "bodies[0].velocity"},
    {"angular velocity overflow", OneBody(Sphere(R"("angular_velocity": [1e309, 0, 0])")),
     "bodies[0].angular_velocity[0]"},
    {"zero quaternion", OneBody(Sphere(R"("orientation": [0, 0, 0, 0])")),
     "bodies[0].orientation"},
    {"quaternion of 3 numbers", OneBody(Sphere(R"("orientation": [1, 0, 0])")),
     "bodies[0].orientation"},
    {"quaternion component not a number", OneBody(Sphere(R"("orientation": [1, 0, false, 0])")),
     "bodies[0].orientation[2]"},
    {"negative restitution", OneBody(Sphere(R"("restitution": -0.1)")), "bodies[0].restitution"},
    {"restitution above 1", OneBody(Sphere(R"("restitution": 1.5)")), "bodies[0].restitution"},
    {"negative friction", OneBody(Sphere(R"("friction": -0.5)")), "bodies[0].friction"},
    {"friction a string", OneBody(Sphere(R"("friction": "low")")), "bodies[0].friction"},
    {"responds not a boolean", OneBody(Sphere(R"("responds": 0)")), "bodies[0].responds"},
    {"ignore not an array", OneBody(Sphere(R"("ignore": "b")")), "bodies[0].ignore"},
    {"ignore entry not a string", OneBody(Sphere(R"("ignore": [1])")), "bodies[0].ignore[0]"},
    {"ignore names no body", OneBody(Sphere(R"("ignore": ["ghost"])")), "bodies[0].ignore[0]"},
    {"ignore names the body itself", OneBody(Sphere(R"("ignore": ["a"])")),
     "bodies[0].ignore[0]"},
    // Shapes.
    {"no shape", R"({"bodies": [{"name": "a"}]})", "bodies[0].shape"},
    {"shape not an object", OneBody(Shape(R"("sphere")")), "bodies[0].shape"},
    {"no shape type", OneBody(Shape(R"({"radius": 1})")), "bodies[0].shape.type"},
    {"unknown shape type", OneBody(Shape(R"({"type": "cube", "half_extents": [1, 1, 1]})")),
     "bodies[0].shape.type"},
    {"unknown shape field", OneBody(Shape(R"({"type": "sphere", "radius": 1, "color": 3})")),
     "bodies[0].shape.color"},
    {"box field on a sphere",
     OneBody(Shape(R"({"type": "sphere", "radius": 1, "half_extents": [1, 1, 1]})")),
     "bodies[0].shape.half_extents"},
    {"sphere field on a box",
     OneBody(Shape(R"({"type": "box", "half_extents": [1, 1, 1], "radius": 1})")),
     "bodies[0].shape.radius"},
    {"hull field on a sphere", OneBody(Shape(R"({"type": "sphere", "radius": 1, "points": []})")),
     "bodies[0].shape.points"},
    {"sphere without radius", OneBody(Shape(R"({"type": "sphere"})")), "bodies[0].shape.radius"},
    {"zero radius", OneBody(Shape(R"({"type": "sphere", "radius": 0})")),
     "bodies[0].shape.radius"},
    {"negative radius", OneBody(Shape(R"({"type": "sphere", "radius": -1})")),
     "bodies[0].shape.radius"},
    {"radius a string", OneBody(Shape(R"({"type": "sphere", "radius": "1"})")),
     "bodies[0].shape.radius"},
    {"box without half extents", OneBody(Shape(R"({"type": "box"})")),
     "bodies[0].shape.half_extents"},
    {"half extents of 2 numbers", OneBody(Shape(R"({"type": "box", "half_extents": [1, 1]})")),
     "bodies[0].shape.half_extents"},
    {"zero half extent", OneBody(Shape(R"({"type": "box", "half_extents": [1, 0, 1]})")),
     "bodies[0].shape.half_extents[1]"},
    {"negative half extent", OneBody(Shape(R"({"type": "box", "half_extents": [1, 1, -1]})")),
     "bodies[0].shape.half_extents[2]"},
    {"hull without points", OneBody(Shape(R"({"type": "hull"})")), "bodies[0].shape.points"},
    {"hull points not an array", OneBody(Shape(R"({"type": "hull", "points": 4})")),
     "bodies[0].shape.points"},
    {"hull of 3 points",
     OneBody(Shape(R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]})")),
     "bodies[0].shape.points"},
    {"hull point of 2 numbers",
     OneBody(Shape(R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1], [0, 0, 1]]})")),
     "bodies[0].shape.points[2]"},
    {"hull point component not a number",
     OneBody(Shape(
         R"({"type": "hull", "points": [[0, 0, 0], ["1", 0, 0], [0, 1, 0], [0, 0, 1]]})")),
     "bodies[0].shape.points[1][0]"},
    {"hull points all the same",
     OneBody(Shape(R"({"type": "hull", "points": [[1, 2, 3], [1, 2, 3], [1, 2, 3], [1, 2, 3]]})")),
     "bodies[0].shape.points"},
    {"capsule without half height", OneBody(Shape(R"({"type": "capsule", "radius": 1})")),
     "bodies[0].shape.half_height"},
    {"capsule of negative half height",
     OneBody(Shape(R"({"type": "capsule", "radius": 1, "half_height": -1})")),
     "bodies[0].shape.half_height"},
    {"capsule of zero radius", OneBody(Shape(R"({"type": "capsule", "radius": 0, "half_height": 1})")),
     "bodies[0].shape.radius"},
    {"box field on a capsule",
     OneBody(Shape(R"({"type": "capsule", "radius": 1, "half_height": 1, "half_extents": [1, 1, 1]})")),
     "bodies[0].shape.half_extents"},
    {"capsule field on a sphere", OneBody(Shape(R"({"type": "sphere", "radius": 1, "half_height": 1})")),
     "bodies[0].shape.half_height"},
    {"cylinder without radius", OneBody(Shape(R"({"type": "cylinder", "half_height": 1})")),
     "bodies[0].shape.radius"},
    {"cylinder of zero half height", OneBody(Shape(R"({"type": "cylinder", "radius": 1, "half_height": 0})")),
     "bodies[0].shape.half_height"},
    {"compound without children", OneBody(Shape(R"({"type": "compound", "children": []})")),
     "bodies[0].shape.children"},
    {"compound child with an unknown key",
     OneBody(Shape(R"({"type": "compound", "children": [{"shape": {"type": "sphere", "radius": 1}, "colour": 1}]})")),
     "bodies[0].shape.children[0].colour"},
    {"compound in a compound",
     OneBody(Shape(R"({"type": "compound", "children": [{"shape": {"type": "compound", "children": [
         {"shape": {"type": "sphere", "radius": 1}}]}}]})")),
     "bodies[0].shape.children[0].shape.type"},
    {"compound child of negative density",
     OneBody(Shape(R"({"type": "compound", "children": [{"shape": {"type": "sphere", "radius": 1}, "density": -2}]})")),
     "bodies[0].shape.children[0].density"},
    {"compound child's bad radius",
     OneBody(Shape(R"({"type": "compound", "children": [{"shape": {"type": "sphere", "radius": 0}}]})")),
     "bodies[0].shape.children[0].shape.radius"},
    {"points field on a cylinder",
     OneBody(Shape(R"({"type": "cylinder", "radius": 1, "half_height": 1, "points": []})")),
     "bodies[0].shape.points"},
    {"category negative", OneBody(Sphere(R"("category": -1)")), "bodies[0].category"},
    {"category beyond 32 bits", OneBody(Sphere(R"("category": 4294967296)")),
     "bodies[0].category"},
    {"mask not whole", OneBody(Sphere(R"("mask": 1.5)")), "bodies[0].mask"},
    {"mask a string", OneBody(Sphere(R"("mask": "0xff")")), "bodies[0].mask"},
    {"hull points on a line",
     OneBody(Shape(R"({"type": "hull", "points": [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]})")),
     "bodies[0].shape.points"},
    {"hull points in a plane",
     OneBody(Shape(
         R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 3, 0]]})")),
     "bodies[0].shape.points"},
    {"hull points in a plane to 1e-12 of its size",
     OneBody(Shape(
         R"({"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1e-12]]})")),
     "bodies[0].shape.points"},
};

// Test names from the descriptions: "zero dt" -> zero_dt.
std::string BadSceneName(const testing::TestParamInfo<BadScene>& param) {
  std::string name = param.param.what;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}
INSTANTIATE_TEST_SUITE_P(BadInput, SceneRejects, testing::ValuesIn(kBadScenes), BadSceneName);

TEST(Scene, SyntaxErrorsGiveTheLine) {
  try {
    ParseScene("{\n  \"dt\": 0.1,\n  \"bodies\": [tru]\n}", "bad.json");
    FAIL();
  } catch (const RSceneError& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
}

TEST(Scene, ErrorsSayWhatIsWrongAndWhatWasGiven) {
  try {
    ParseScene(OneBody(Shape(R"({"type": "sphere", "radius": -2})")), "scene.json");
    FAIL();
  } catch (const RSceneError& e) {
    EXPECT_STREQ(e.what(),
                 "scene.json: bodies[0].shape.radius: must be a finite number > 0 (got -2)");
  }
}

TEST(Scene, MissingFileIsASceneError) {
  try {
    LoadScene("/nonexistent/scene.json");
    FAIL();
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.File(), "/nonexistent/scene.json");
    EXPECT_EQ(e.JsonPath(), "");
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
  }
}

// A definition that parses but has no valid mass properties fails in CreateBodies, still as
// a scene error naming the body's field.
TEST(Scene, CreateBodiesNamesTheBodysField) {
  const RScene s = ParseScene(R"({"bodies": [
      {"name": "ok", "shape": {"type": "sphere", "radius": 1}},
      {"name": "huge", "shape": {"type": "box", "half_extents": [1e200, 1e200, 1e200]}}]})",
                              "huge.json");
  try {
    CreateBodies(s);
    FAIL();
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.File(), "huge.json");
    EXPECT_EQ(e.JsonPath().rfind("bodies[1].", 0), 0u) << e.what();
  }
}

// A value nested 100k deep (200 KB): a loader that printed it with a recursive dump would
// crash (SIGSEGV). Refused as it is read, naming where, with a message of bounded length.
TEST(Scene, DeepNestingIsRefusedAtAFixedDepth) {
  const int depth = 100000;
  const std::string text = "{\"gravity\": " + std::string(depth, '[') + std::string(depth, ']') +
                           ", \"bodies\": []}";
  try {
    ParseScene(text, "deep.json");
    FAIL() << "accepted";
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.JsonPath().rfind("gravity", 0), 0u) << e.JsonPath().substr(0, 80);
    EXPECT_NE(e.Problem().find("nested deeper than 64"), std::string::npos) << e.Problem();
    EXPECT_LT(std::string(e.what()).size(), 600u);
  }
  // 60 deep is not refused for its depth (it is not a vector of 3 numbers).
  const std::string ok = "{\"gravity\": " + std::string(60, '[') + std::string(60, ']') +
                         ", \"bodies\": []}";
  try {
    ParseScene(ok, "ok.json");
  } catch (const RSceneError& e) {
    EXPECT_EQ(e.JsonPath(), "gravity");
    EXPECT_NE(e.Problem().find("(got an array of 1 values)"), std::string::npos) << e.Problem();
  }
}

// A huge value where a number belongs is summarised, not dumped.
TEST(Scene, ErrorMessagesStayShortWhateverTheValue) {
  std::string big = "[";
  for (int i = 0; i < 200000; ++i) big += (i ? ",1" : "1");
  big += "]";
  for (const std::string& value : {big, "\"" + std::string(1 << 20, 'x') + "\""}) {
    try {
      ParseScene("{\"dt\": " + value + ", \"bodies\": []}", "big.json");
      FAIL();
    } catch (const RSceneError& e) {
      EXPECT_EQ(e.JsonPath(), "dt");
      EXPECT_LT(std::string(e.what()).size(), 200u) << std::string(e.what()).substr(0, 300);
    }
  }
}

// Names go into the CSV: a NUL or any control character is refused (it was written raw).
TEST(Scene, NamesWithControlCharactersAreRefused) {
  for (const char* name : {"a\\u0000b", "line\\nbreak", "tab\\there", "esc\\u001b[31m", "del\\u007f",
                           "next\\u0085line"}) {
    const std::string text = std::string(R"({"bodies": [{"name": ")") + name +
                             R"(", "shape": {"type": "sphere", "radius": 1}}]})";
    try {
      ParseScene(text, "names.json");
      FAIL() << name;
    } catch (const RSceneError& e) {
      EXPECT_EQ(e.JsonPath(), "bodies[0].name") << name;
      EXPECT_NE(e.Problem().find("control characters"), std::string::npos) << e.Problem();
    }
  }
  // Other Unicode is a name like any other.
  EXPECT_EQ(ParseScene(R"({"bodies": [{"name": "Schlepper \u00e9 \u2603", "shape": {"type": "sphere", "radius": 1}}]})",
                       "names.json").bodies[0].name,
            "Schlepper \xc3\xa9 \xe2\x98\x83");
}

// The limits refuse a scene by the field that asks for too much (small limits to test them).
TEST(Scene, LimitsNameTheFieldThatExceedsThem) {
  const std::string three = R"({"steps": 10, "bodies": [
      {"name": "a", "shape": {"type": "sphere", "radius": 1}},
      {"name": "b", "shape": {"type": "sphere", "radius": 1}},
      {"name": "c", "shape": {"type": "hull", "points": [[0,0,0],[1,0,0],[0,1,0],[0,0,1],[1,1,1]]}}]})";
  const struct {
    RSceneLimits limits;
    const char* path;
  } cases[] = {{{1 << 20, 2, 100, 100, 1e9}, "bodies"},
               {{1 << 20, 10, 4, 100, 1e9}, "bodies[2].shape.points"},
               {{1 << 20, 10, 100, 9, 1e9}, "steps"},
               {{1 << 20, 10, 100, 100, 29}, "steps"}};
  for (const auto& c : cases) {
    try {
      ParseScene(three, "limits.json", c.limits);
      ADD_FAILURE() << c.path;
    } catch (const RSceneError& e) {
      EXPECT_EQ(e.JsonPath(), c.path) << e.what();
    }
  }
  EXPECT_NO_THROW(ParseScene(three, "limits.json", {1 << 20, 3, 5, 10, 30}));
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
