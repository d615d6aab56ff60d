// The scene loader on arbitrary text: it either loads (and the bodies can be created) or
// throws RSceneError. Anything else (a crash, another exception, a hang, memory without
// bound) is a defect. A scene with joints that loads also makes them: the loader checks all
// that RBodies::AddJoint does, so a joint refused by the world (an RSceneError named
// "joints[...]" from RSceneWorld) is a defect too.
#include <REnginePhysics/RScene.h>

#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const REngine::RScene scene = REngine::ParseScene(text, "fuzz.json");
    if (scene.joints.empty()) {
      (void)REngine::CreateBodies(scene);
    } else {
      try {
        const REngine::RSceneWorld world(scene);
      } catch (const REngine::RSceneError& e) {
        if (e.JsonPath().rfind("joints", 0) == 0) __builtin_trap();
        throw;
      }
    }
  } catch (const REngine::RSceneError&) {
  }
  return 0;
}
