// rengine-sim's exit codes and messages (docs/scene-format.md, "Exit codes"): bad scenes and
// bad command lines exit 2 naming the file, the field or the option; a body that becomes
// non-finite exits 1 naming it and the step; hostile scenes get exit 2, not a crash. Runs
// the built binary through the shell.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/CliRunner.h"
#include "support/ReferenceScenes.h"

using namespace REngine;
using namespace REngine::test;

TEST_F(Cli, BadScenesExitTwoNamingTheFileAndTheField) {
  struct Case {
    std::string scene, mustContain;
  };
  const std::vector<Case> cases = {
      {SceneOf({{"a", R"("shape": {"type": "sphere", "radius": -1})"}}),
       "bodies[0].shape.radius"},
      {SceneOf({{"a", kSphere + R"(, "frction": 0.5)"}}), "bodies[0].frction"},
      {SceneOf({{"a", kSphere}, {"a", kSphere}}), "bodies[1].name"},
      {SceneOf({{"a", kSphere + R"(, "orientation": [0, 0, 0, 0])"}}), "bodies[0].orientation"},
      {SceneOf({{"a", R"("shape": {"type": "hull",
                                   "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]})"}}),
       "bodies[0].shape.points"},
      {SceneOf({{"a", kSphere}}, R"("dt": 1e999)"), "dt"},
      // A cylinder as flat as a coin of 1e-5 of its radius: refused when the body is made.
      {SceneOf({{"a", R"("shape": {"type": "cylinder", "radius": 1, "half_height": 1e-5})"}}),
       "bodies[0].shape.half_height"},
      {"{\"bodies\": [\n  {\"name\": \"a\",}\n]}", "invalid JSON at line 2, column 16"},
  };
  for (const Case& c : cases) {
    // A trajectory from an earlier run must survive a bad scene.
    Write("keep.csv", "earlier run\n");
    const Result r = Run(Quote(Write("bad scene.json", c.scene)) + " --out " +
                         Quote(Path("keep.csv")));
    EXPECT_EQ(r.code, 2) << c.scene;
    EXPECT_NE(r.err.find("bad scene.json: " + c.mustContain), std::string::npos) << r.err;
    EXPECT_EQ(ReadFile(Path("keep.csv")), "earlier run\n");
  }
}

TEST_F(Cli, BadCommandLinesExitTwo) {
  const std::string scene = Quote(ReferenceScenePath("head_on_elastic"));
  struct Case {
    std::string args, mustContain;
  };
  const std::vector<Case> cases = {
      {scene + " --every 0", "--every"},
      {scene + " --every -3", "--every"},
      {scene + " --dt -1", "--dt"},
      {scene + " --dt 0", "--dt"},
      {scene + " --dt inf", "--dt"},
      {scene + " --dt nan", "--dt"},
      {scene + " --steps -1", "--steps"},
      {scene + " --steps 2.5", "--steps"},
      {scene + " --steps ten", "--steps"},
      {scene + " --bogus", "--bogus"},
      {scene + " --describe --steps 3", "--describe"},
      {"", "scene"},
      {Quote(Path("missing.json")), "missing.json"},
      {scene + " --out " + Quote(Path("no/such/dir/t.csv")), "no/such/dir/t.csv"},
  };
  for (const Case& c : cases) {
    const Result r = Run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.mustContain), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_EQ(Run("--help").code, 0);
}

// A body flung towards the largest double leaves the world (1e15 m of the origin) in its
// first step of 1 s: put back, reported, and the run stops there.
TEST_F(Cli, NonFiniteBodyExitsOneNamingItAndTheStep) {
  const std::string scene = SceneOf({
      {"calm", kSphere},
      {"runaway", kSphere + R"(, "position": [1e15, 0, 0], "velocity": [8e307, 0, 0])"},
  });
  const Result r = Run(Quote(Write("overflow.json", scene)) + " --dt 1 --out " +
                       Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.LastErrLine(), "error: body 'runaway' became non-finite or left the world (1e15 m) at step 1") << r.err;
  // The rows before the failure are kept, to find its cause.
  EXPECT_EQ(ParseCsv(ReadFile(Path("t.csv"))).size(), 2u * 1);
}

// Untrusted scenes cannot crash or hang the CLI: a value nested 100k deep must not crash it
// (SIGSEGV), a body name with a control character must not go raw into the CSV; the work a scene
// asks for is bounded by documented limits, and --max-seconds stops a run that takes too long.
TEST_F(Cli, HostileScenesGetExitTwoNotACrash) {
  const std::string deep = "{\"gravity\": " + std::string(100000, '[') +
                           std::string(100000, ']') + ", \"bodies\": []}";
  Result r = Run(Quote(Write("deep.json", deep)) + " --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 2) << r.err.substr(0, 300);
  EXPECT_NE(r.err.find("nested deeper than 64"), std::string::npos) << r.err.substr(0, 300);
  r = Run(Quote(Write("name.json", SceneOf({{"bad\\u0000name", kSphere}}))));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bodies[0].name"), std::string::npos) << r.err;
  const std::string one = Quote(Write("one.json", SceneOf({{"ball", kSphere}})));
  r = Run(one + " --steps 100000001 --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("steps"), std::string::npos) << r.err;
  // 1e8 steps of one body are allowed, and --max-seconds stops them early with exit 1 and
  // the rows so far.
  r = Run(one + " --steps 100000000 --every 1000 --max-seconds 0.05 --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.LastErrLine().find("--max-seconds 0.05 reached"), std::string::npos) << r.err;
  EXPECT_GE(ParseCsv(ReadFile(Path("t.csv"))).size(), 2u);
  EXPECT_EQ(Run(one + " --max-seconds -1").code, 2);
}
