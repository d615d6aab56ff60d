// Scene files refused: every kind of bad input names the file and the JSON path, syntax
// errors their line; messages say what is wrong and what was given, and stay short however
// large or deep the value; names with control characters and scenes beyond the limits are
// refused by their field.
#include <REnginePhysics/RScene.h>

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <ostream>
#include <string>
#include <vector>

#include "scene/SceneText.h"

using namespace REngine;
using namespace REngine::test;
using namespace REngine::test::scenetext;

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
    {"negative restitution threshold", OneBody(kSphere, R"("solver": {"restitution_threshold": -0.1})"),
     "solver.restitution_threshold"},
    {"restitution threshold not a number", OneBody(kSphere, R"("solver": {"restitution_threshold": "0.5"})"),
     "solver.restitution_threshold"},
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
