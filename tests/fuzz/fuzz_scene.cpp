// The scene loader on arbitrary text: it either loads (and the bodies can be created) or
// throws RSceneError. Anything else (a crash, another exception, a hang, memory without
// bound) is a defect.
#include <REnginePhysics/RScene.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const REngine::RScene scene = REngine::ParseScene(text, "fuzz.json");
    (void)REngine::CreateBodies(scene);
  } catch (const REngine::RSceneError&) {
  }
  return 0;
}
