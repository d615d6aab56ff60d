// rengine-sim's door: values no game means, and resources the machine cannot give, are
// refused before the run with exit code 2 and a message naming the option or the scene
// field at fault (docs/scene-format.md, "Limits" and "Exit codes").
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "support/CliRunner.h"
#include "support/Sanitizers.h"

using namespace REngine;
using namespace REngine::test;

namespace {

const std::string kOneBall = SceneOf({{"ball", kSphere}});

}  // namespace

// --threads 1024 under a 4 GiB address space: the workers' stacks (8 MiB each) do not fit.
// The run stops at the door, exit 2 naming --threads and the thread that could not start,
// without touching the trajectory; a hang (the workers started left running under a
// destroyed pool) is ended by timeout's exit code 124, which fails the test.
TEST_F(Cli, ThreadsTheMachineCannotStartExitTwoNamingThreads) {
  if (RENGINE_TEST_SANITIZED) GTEST_SKIP() << "a sanitizer's shadow memory does not run under ulimit -v";
  const fs::path scene = Write("one.json", kOneBall);
  Write("t.csv", "earlier run\n");
  const std::string command = "bash -c 'ulimit -s 8192 && ulimit -v 4194304 && exec timeout 60 " +
                              std::string(RENGINE_SIM) + " " + scene.string() + " --threads 1024 --out " +
                              Path("t.csv").string() + "' >" + Quote(Path("stdout")) + " 2>" +
                              Quote(Path("stderr"));
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  const std::string err = ReadFile(Path("stderr"));
  EXPECT_EQ(WEXITSTATUS(status), 2) << err;
  EXPECT_EQ(err.rfind("error: --threads 1024: RThreadPool: could not start thread ", 0), 0u) << err;
  EXPECT_NE(err.find(" of 1024: "), std::string::npos) << err;
  EXPECT_EQ(ReadFile(Path("t.csv")), "earlier run\n");
  // Without the limit the same run succeeds.
  const Result r = Run(Quote(scene) + " --threads 1024 --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 0) << r.err;
}

// --steps beyond the limit is the option's fault, not the scene's "steps" field; so is a
// --steps that makes steps x bodies exceed its limit.
TEST_F(Cli, StepsBeyondTheLimitsBlameTheOption) {
  const std::string one = Quote(Write("one.json", kOneBall));
  Result r = Run(one + " --steps 100000001 --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.LastErrLine(), "error: --steps: must be at most 100000000 (got 100000001)");
  EXPECT_FALSE(fs::exists(Path("t.csv")));
  std::vector<std::pair<std::string, std::string>> balls;
  for (int i = 0; i < 200; ++i) balls.push_back({"b" + std::to_string(i), kSphere});
  r = Run(Quote(Write("many.json", SceneOf(balls))) + " --steps 100000000");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.LastErrLine(), "error: --steps: 100000000 steps of 200 bodies exceed 1e+10 body-steps");
  // The scene's own steps are still the scene's.
  r = Run(Quote(Write("long.json", SceneOf({{"ball", kSphere}}, R"("dt": 0.01, "steps": 100000001)"))));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.LastErrLine().find("long.json: steps: must be at most 100000000"), std::string::npos) << r.err;
}

// An action after the last step would never apply: refused like a ray there, by its path,
// whether the scene's steps or --steps end the run before it.
TEST_F(Cli, AnActionAfterTheLastStepExitsTwoNamingIt) {
  const std::string late = Quote(Write("late.json", SceneOf({{"ball", kSphere}}, R"("dt": 0.01, "steps": 10,
      "actions": [{"step": 10, "impulse": {"body": "ball", "impulse": [1, 0, 0]}},
                  {"step": 11, "remove": "ball"}])")));
  Result r = Run(late + " --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.LastErrLine(), "error: " + Path("late.json").string() +
                                 ": actions[1].step: is after the last step (10): the action would never be applied "
                                 "(got 11)");
  EXPECT_FALSE(fs::exists(Path("t.csv")));
  EXPECT_EQ(Run(late + " --steps 11").code, 2) << "--steps does not mend the scene";
  // The ball is set moving at step 4 and faster at step 10, the last row; --steps 12 runs
  // on past it, --steps 9 would never reach it.
  const std::string cut = Quote(Write("cut.json", SceneOf({{"ball", kSphere}}, R"("dt": 0.01, "steps": 10,
      "actions": [{"step": 10, "set_velocity": {"body": "ball", "velocity": [3, 0, 0]}},
                  {"step": 4, "set_velocity": {"body": "ball", "velocity": [1, 0, 0]}}])")));
  r = Run(cut);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(Velocity(ParseCsv(r.out).back()), RVec3(3, 0, 0));
  r = Run(cut + " --steps 12");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(Velocity(ParseCsv(r.out).back()), RVec3(3, 0, 0));
  r = Run(cut + " --steps 9 --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.LastErrLine(), "error: " + Path("cut.json").string() +
                                 ": actions[0].step: is after the last step (9): the action would never be applied "
                                 "(got 10)");
  EXPECT_FALSE(fs::exists(Path("t.csv")));
}

// The step size is at most RIntegrator::kMaxDt (1 s), from --dt or the scene's "dt": a step
// of 1e300 s ran. 1 s itself runs.
TEST_F(Cli, AStepLongerThanOneSecondExitsTwoNamingIt) {
  const std::string one = Quote(Write("one.json", kOneBall));
  Result r = Run(one + " --dt 1e300 --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.LastErrLine(), "error: --dt: must be a finite number > 0 and at most 1 (s) (got \"1e300\")");
  EXPECT_FALSE(fs::exists(Path("t.csv")));
  EXPECT_EQ(Run(one + " --dt 1.0000000000000002").code, 2);
  r = Run(one + " --dt 1");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(ParseCsv(r.out).back().time, 10.0);
  r = Run(Quote(Write("long.json", SceneOf({{"ball", kSphere}}, R"("dt": 2, "steps": 10)"))));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.LastErrLine(), "error: " + Path("long.json").string() +
                                 ": dt: must be a finite number > 0 and at most 1 (s) (got 2)");
  // --dt replaces the scene's dt, but the scene must still be valid.
  EXPECT_EQ(Run(Quote(Path("long.json")) + " --dt 0.5").code, 2);
}

// An impulse action is held to the API's 1e30 N s a component: 1e300 ran and flung the
// ball to 3e299 m.
TEST_F(Cli, AnImpulseBeyondTheLimitExitsTwoNamingIt) {
  const std::string scene = Quote(Write("kick.json", SceneOf({{"ball", kSphere}}, R"("dt": 0.01, "steps": 10,
      "actions": [{"step": 2, "impulse": {"body": "ball", "impulse": [1e300, 0, 0]}}])")));
  const Result r = Run(scene + " --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.LastErrLine(), "error: " + Path("kick.json").string() +
                                 ": actions[0].impulse.impulse[0]: must be a finite number within 1e30 (N s) (got 1e+300)");
  EXPECT_FALSE(fs::exists(Path("t.csv")));
}

// --max-seconds stops a step that runs on past it, not only between steps: a mesh of 1024
// spheres on 1984 ball joints at the most solver iterations a scene may ask for (1000) takes
// seconds a step here. Past 0.01 s of stepping and the watchdog's grace of 1 s, the run stops
// inside its first step with exit 1, the rows written before it kept (step 0's); without
// the watchdog it would run its 3 steps (a hang here ends in timeout's 124, a failure).
TEST_F(Cli, MaxSecondsStopsAStepThatRunsOnPastIt) {
  const int k = 32;
  std::string bodies, joints;
  auto name = [](int i, int j) { return "\"b" + std::to_string(i) + "_" + std::to_string(j) + "\""; };
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) {
      const double x = 0.5 * i, y = 0.5 * j;
      // Spinning about an axis off the mesh's normal: the joints have work in every step.
      bodies += std::string(bodies.empty() ? "" : ",") + "{\"name\": " + name(i, j) +
                ", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, \"mass\": 1, \"mask\": 0, \"position\": [" +
                std::to_string(x) + ", " + std::to_string(y) + ", 0], \"angular_velocity\": [0.3, 0.2, 1], " +
                "\"velocity\": [" + std::to_string(-y) + ", " + std::to_string(x) + ", " +
                std::to_string(0.3 * y - 0.2 * x) + "]}";
      if (i + 1 < k) {
        joints += std::string(joints.empty() ? "" : ",") + "{\"name\": \"h" + std::to_string(i * k + j) +
                  "\", \"type\": \"ball\", \"a\": " + name(i, j) + ", \"b\": " + name(i + 1, j) + ", \"anchor\": [" +
                  std::to_string(x + 0.25) + ", " + std::to_string(y) + ", 0]}";
      }
      if (j + 1 < k) {
        joints += std::string(joints.empty() ? "" : ",") + "{\"name\": \"v" + std::to_string(i * k + j) +
                  "\", \"type\": \"ball\", \"a\": " + name(i, j) + ", \"b\": " + name(i, j + 1) + ", \"anchor\": [" +
                  std::to_string(x) + ", " + std::to_string(y + 0.25) + ", 0]}";
      }
    }
  }
  const fs::path scene = Write("mesh.json", "{\"steps\": 3, \"solver\": {\"iterations\": 1000, \"sleeping\": false}, "
                                            "\"bodies\": [" + bodies + "], \"joints\": [" + joints + "]}");
  const std::string command = "bash -c 'exec timeout 60 " + std::string(RENGINE_SIM) + " " + scene.string() +
                              " --max-seconds 0.01 --quiet --out " + Path("t.csv").string() + "' >" +
                              Quote(Path("stdout")) + " 2>" + Quote(Path("stderr"));
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  const std::string err = ReadFile(Path("stderr"));
  EXPECT_EQ(WEXITSTATUS(status), 1) << err;
  EXPECT_EQ(err.rfind("error: stopped during step 1 of 3: --max-seconds 0.01 reached and the step still running 1 s after",
                      0),
            0u)
      << err;
  EXPECT_EQ(ParseCsv(ReadFile(Path("t.csv"))).size(), std::size_t(k * k));  // step 0's rows
}
