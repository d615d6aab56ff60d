// The reference scenes (the repository's scenes/, RENGINE_SCENES at build time), by
// name: what the tests, rengine-bench and bench_bullet run and pin their figures on.
// LoadReferenceScene needs REngine::Scene; ReferenceScenePath needs nothing but the definition.
#pragma once

#include <REnginePhysics/RScene.h>

#include <string>

namespace REngine::test {

// The file of the reference scene `name` ("box_stack_10" for box_stack_10.json).
inline std::string ReferenceScenePath(const std::string& name) {
  return std::string(RENGINE_SCENES) + "/" + name + ".json";
}

// LoadScene of the reference scene `name`; throws RSceneError as LoadScene does.
inline RScene LoadReferenceScene(const std::string& name) { return LoadScene(ReferenceScenePath(name)); }

}  // namespace REngine::test
