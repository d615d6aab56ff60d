// rengine-bench --scaling's scenes (scaling_scenes.h): the list, the reference table, and the
// generator run where files are missing.
#include "scaling_scenes.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

extern char** environ;

namespace rbench {

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// Where the build put the generator and the interpreter to run it (tools/CMakeLists.txt).
constexpr const char* kScript = RENGINE_SCALING_SCRIPT;
constexpr const char* kPython = RENGINE_PYTHON3;

// Runs `python3 script outDir`; "" when it exited with 0.
std::string RunGenerator(const std::filesystem::path& outDir) {
  const std::string python = kPython, script = kScript, out = outDir.string();
  std::vector<char*> argv{const_cast<char*>(python.c_str()), const_cast<char*>(script.c_str()),
                          const_cast<char*>(out.c_str()), nullptr};
  pid_t pid = 0;
  // Its "written to <temporary directory>" would mislead: standard output goes to /dev/null,
  // its errors still reach standard error.
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  // posix_spawnp: no shell, so paths with spaces or quotes need no quoting; PATH is searched
  // when the build found no interpreter and left the bare name "python3".
  const int err = posix_spawnp(&pid, python.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0) return "cannot run " + python + ": " + std::strerror(err);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return std::string("waitpid: ") + std::strerror(errno);
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  return python + " " + script + " " + out + " failed (" +
         (WIFEXITED(status) ? "exit code " + std::to_string(WEXITSTATUS(status))
                            : "signal " + std::to_string(WTERMSIG(status))) +
         ")";
}

}  // namespace

const std::vector<ScalingScene>& ScalingScenes() {
  // The reference table, ms/step: 3000-box piles and Jolt's 3000 pile give ranges (17-21,
  // 4.9-6.1, 4.4-6.1, 2.2-2.6): their midpoints. No row for the 1000-box pile sleeping and
  // the 1000-rock sparse field.
  static const std::vector<ScalingScene> scenes{
      {"debris_1000", "debris", true, 0.84, 0.86, 0.50},
      {"debris_3000", "debris", false, 6.6, 3.0, 1.45},
      {"debris_10000", "debris", false, 60, 14, 5.8},
      {"debris_30000", "debris", false, 661, 61, 21},
      {"pile_1000_awake", "pile_awake", true, 5.1, 2.5, 1.95},
      {"pile_3000_awake", "pile_awake", false, 19, 7.6, 5.5},
      {"pile_10000_awake", "pile_awake", false, 113, 30, 17.5},
      {"pile_1000_sleep", "pile_sleep", true, kNone, kNone, kNone},
      {"pile_3000_sleep", "pile_sleep", false, 5.25, 4.2, 2.4},
      {"pile_10000_sleep", "pile_sleep", false, 29, 17.7, 8.2},
      {"sparse_1000", "sparse", true, kNone, kNone, kNone},
      {"sparse_5000", "sparse", false, 14.5, 7.0, 2.5},
      {"sparse_20000", "sparse", false, 211, 47.5, 15},
  };
  return scenes;
}

std::filesystem::path ScalingScenePath(const std::filesystem::path& dir,
                                       const ScalingScene& scene) {
  return dir / (std::string(scene.name) + ".json");
}

std::string EnsureScalingScenes(const std::filesystem::path& dir,
                                const std::vector<const ScalingScene*>& scenes) {
  namespace fs = std::filesystem;
  bool missing = false;
  for (const ScalingScene* s : scenes) missing = missing || !fs::exists(ScalingScenePath(dir, *s));
  if (!missing) return "";

  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return dir.string() + ": " + ec.message();
  // Private to this process, so two runs generating at once do not write the same files.
  const fs::path work = dir / (".generating-" + std::to_string(getpid()));
  fs::remove_all(work, ec);
  std::printf("generating the scaling scenes into %s (%s, ~55 MB)\n", dir.c_str(), kScript);
  std::fflush(stdout);
  std::string error = RunGenerator(work);
  if (error.empty()) {
    // A rename within one directory is atomic: a reader sees a whole file or none.
    for (const fs::directory_entry& e : fs::directory_iterator(work, ec)) {
      fs::rename(e.path(), dir / e.path().filename(), ec);
      if (ec) {
        error = e.path().string() + ": " + ec.message();
        break;
      }
    }
    if (ec && error.empty()) error = work.string() + ": " + ec.message();
  }
  fs::remove_all(work, ec);
  if (!error.empty()) return error;
  for (const ScalingScene* s : scenes) {
    if (!fs::exists(ScalingScenePath(dir, *s))) {
      return ScalingScenePath(dir, *s).string() + ": not written by " + kScript;
    }
  }
  return "";
}

}  // namespace rbench
