// rengine-bench --scaling: ms/step against body count for REngine, Bullet and Jolt in the
// same run, on the scaling scenes (scaling_scenes.h); Bullet where it was found at build time,
// Jolt where CMake was given REngine_JOLT_DIR. tools/plot_scaling.py draws the CSV.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rbench {

struct ScalingOptions {
  std::vector<std::string> scenes;  // from ScalingScenes(); empty: all (--quick: the smallest)
  std::string sceneDir;             // where the scene files are, or are generated
  std::string csvPath;
  int repeats = 3;                  // interleaved timed runs per scene and engine (median kept)
  std::uint64_t steps = 0;          // 0: each scene's own (300)
  // REngine's broad phase (the scene key solver.broadphase): on, off (the all-pairs reference
  // loop), or both (two REngine rows per scene, timed in the same interleaving).
  enum class BroadPhase { kOn, kOff, kBoth } broadPhase = BroadPhase::kOn;
  // REngine's and Jolt's thread counts (RWorldSettings::threads; Jolt's job system with one
  // worker fewer, the caller being the other): one row per count and broad-phase setting,
  // timed in the same interleaving. Bullet runs on one thread whatever this says.
  std::vector<int> threads = {1};
  // --model-threads: REngine's step modelled on these thread counts from one thread's task
  // timings (thread_model.h), per scene, medians of `repeats` runs; written to modelCsvPath.
  std::vector<int> modelThreads;
  std::string modelCsvPath;
  bool quick = false;          // smoke test: the smallest scenes, 10 steps, 1 run
  bool generateOnly = false;   // make the missing scene files, run nothing
};

// Runs the scaling series, prints the table and writes the CSV. Returns the exit code: 0,
// 1 when a run failed (a body became non-finite, REngine's repeats disagree, Jolt dropped
// contacts), 2 bad input (an unknown scene, a scene file that cannot be made or read, the
// CSV path).
int RunScaling(const ScalingOptions& options);

// The scene names, comma-separated, for --help and error messages.
std::string ScalingSceneNames();

}  // namespace rbench
