// rengine-bench's scenes: each builds a World for a grid point and measures an engine's
// observed run of it against a closed form or a conserved quantity. What each scene is and
// what its `error` means: main.cpp's opening comment (and --help).
#pragma once

#include "engines.h"

#include <vector>

namespace rbench {

struct Scene {
  const char* name;
  bool contacts;   // the solver runs: iterations is a grid axis
  bool expensive;  // --quick runs it at one grid point only (and a shorter time)
  World (*world)(const GridPoint& point);
  Errors (*errors)(Engine& engine);  // an observed run of the engine's world
};

// Every scene, in table order (the order of the CSV and of the runs).
const std::vector<Scene>& AllScenes();

// Reads the reference scene files (scenes/) that `scene` builds its worlds from (once per
// process), so that a missing or bad file is reported (an REngine::RSceneError) before any
// run.
void LoadSceneFiles(const Scene& scene);

}  // namespace rbench
