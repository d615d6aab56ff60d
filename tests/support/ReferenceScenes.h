// The shared reference scenes (../shared/scenes, RENGINE_SHARED_SCENES at build time), by
// name: what the tests, rengine-bench and bench_bullet run and pin their figures on.
// LoadSharedScene needs REngine::Scene; SharedScenePath needs nothing but the definition.
#pragma once

#include <REnginePhysics/RScene.h>

#include <string>

namespace REngine::test {

// The file of the shared scene `name` ("box_stack_10" for box_stack_10.json).
inline std::string SharedScenePath(const std::string& name) {
  return std::string(RENGINE_SHARED_SCENES) + "/" + name + ".json";
}

// LoadScene of the shared scene `name`; throws RSceneError as LoadScene does.
inline RScene LoadSharedScene(const std::string& name) { return LoadScene(SharedScenePath(name)); }

}  // namespace REngine::test
