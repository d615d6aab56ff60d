// rengine-bench --scaling's scenes (scaling_scenes.h): the list and the generator run where
// files are missing.
#include "scaling_scenes.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <system_error>
#include <vector>

extern char** environ;

namespace rbench {

namespace {

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
  static const std::vector<ScalingScene> scenes{
      {"debris_1000", "debris", true},          {"debris_3000", "debris", false},
      {"debris_10000", "debris", false},        {"debris_30000", "debris", false},
      {"pile_1000_awake", "pile_awake", true},  {"pile_3000_awake", "pile_awake", false},
      {"pile_10000_awake", "pile_awake", false}, {"pile_1000_sleep", "pile_sleep", true},
      {"pile_3000_sleep", "pile_sleep", false}, {"pile_10000_sleep", "pile_sleep", false},
      {"sparse_1000", "sparse", true},          {"sparse_5000", "sparse", false},
      {"sparse_20000", "sparse", false},
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
