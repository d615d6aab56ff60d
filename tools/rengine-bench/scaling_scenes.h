// rengine-bench --scaling's scenes: the files tools/make_scaling_scenes.py writes (debris
// clouds, box piles with sleeping off and on, sparse asteroid fields, each at several body
// counts) and the generation of the files where they are missing. The files are ~55 MB and are never
// committed: they are made in the build directory on first use.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace rbench {

struct ScalingScene {
  const char* name;    // file stem: debris_1000 is debris_1000.json
  const char* series;  // debris, pile_awake, pile_sleep, sparse: one line of the plot per series
  bool quick;          // one of the smallest sizes, which --quick runs
};

// Every scaling scene, in table order (series, then body count): the order of the runs and
// of the CSV.
const std::vector<ScalingScene>& ScalingScenes();

// The scene file of `scene` in `dir`.
std::filesystem::path ScalingScenePath(const std::filesystem::path& dir, const ScalingScene& scene);

// Makes sure every scene of `scenes` has its file in `dir`: when one is missing, runs the
// generator (python3 make_scaling_scenes.py, paths fixed at build time) into a fresh
// directory inside `dir` and moves its files in, so an interrupted run never leaves a
// truncated scene behind. Returns "" on success, else what went wrong.
std::string EnsureScalingScenes(const std::filesystem::path& dir,
                                const std::vector<const ScalingScene*>& scenes);

}  // namespace rbench
