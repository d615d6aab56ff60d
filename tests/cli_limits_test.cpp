// rengine-sim's door: values no game means, and resources the machine cannot give, are
// refused before the run with exit code 2 and a message naming the option or the scene
// field at fault (docs/scene-format.md, "Limits" and "Exit codes").
#include <gtest/gtest.h>

#include <string>

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
