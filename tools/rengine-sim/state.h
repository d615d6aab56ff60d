// rengine-sim --save-state N:FILE and --load-state FILE (docs/scene-format.md, "The
// rengine-sim command line"): the world's whole state after step N written with SaveState
// (RWorldState.h), and a run started from such a state instead of step 0.
//
// A state belongs to its scene: it is saved under a tag, a hash of the scene file's content
// (parsed JSON, so whitespace and key order do not matter) without the fields that do not
// change the world (`steps`, `rays`), and of the step size the run uses (`dt` or --dt). A
// state saved from another scene, or with another step size, is refused.
//
// Loading replays the scene's actions up to the state's step (so that the scene's world
// knows its bodies by name and in their order of creation), then replaces the world with the
// state, which holds everything those actions did. The run goes on from there: the actions
// after that step, to the scene's `steps`.
#pragma once

#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace REngine::sim {

// The largest state file --load-state reads: 1 GiB. A state is about 0.4 to 0.7 KB a body
// and 0.4 to 0.7 KB a remembered contact (RWorldState.h): the scene loader's largest world,
// 100000 bodies (RSceneLimits), resting in a pile, saves about 0.3 GB.
inline constexpr std::uint64_t kMaxStateBytes = std::uint64_t(1) << 30;

// A state file or option that cannot be used: bad input (exit 2). The message names the
// file or the option.
struct StateError {
  std::string message;
};

// --save-state N:FILE.
struct StateSave {
  std::uint64_t step = 0;
  std::string path;
};
// Throws StateError for text that is not N:FILE (N an integer >= 0, FILE not empty).
StateSave ParseSaveState(const std::string& text);

// The tag states of this scene, run with step size dt, are saved under. Throws StateError
// when the scene file cannot be read again.
std::uint64_t SceneTag(const std::string& scenePath, double dt);

// Reads the state in `path` (a regular file of at most kMaxStateBytes), checks that it is
// this scene's (tag) at a step within its `steps`, replays the scene's actions up to that
// step into `world` (which must have had none applied) and loads the state into `integrator`
// and the world's bodies; then checks that the state holds the bodies and joints the scene
// defines at that step, as the scene defines them (a state whose tag was forged onto another
// scene is refused by the first field that differs, named by the scene's path). Returns that
// step. Throws StateError naming the file and the problem.
std::uint64_t LoadSceneState(const std::string& path, const RScene& scene, std::uint64_t tag,
                             RSceneWorld& world, RIntegrator& integrator);

// Writes the state of `integrator` and the world's bodies to `file`; false when writing
// failed.
bool WriteSceneState(std::FILE* file, const RIntegrator& integrator, const RSceneWorld& world,
                     std::uint64_t tag);

}  // namespace REngine::sim
