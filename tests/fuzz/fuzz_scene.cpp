// The scene loader on arbitrary text: it either loads (and the bodies can be created) or
// throws RSceneError. Anything else (a crash, another exception, a hang, memory without
// bound) is a defect. A scene with joints that loads also makes them: the loader checks all
// that RBodies::AddJoint does, so a joint refused by the world (an RSceneError named
// "joints[...]" from RSceneWorld) is a defect too. So is an add_joint or remove_joint action
// the world cannot apply: every action is applied, without steps between them (the loader's
// checks do not depend on where the bodies stand).
#include <REnginePhysics/RScene.h>

#include <algorithm>
#include <cstdint>
#include <string>

namespace {

bool JointVerb(const REngine::RSceneAction& a) {
  return a.verb == REngine::RSceneAction::Verb::kAddJoint || a.verb == REngine::RSceneAction::Verb::kRemoveJoint;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const REngine::RScene scene = REngine::ParseScene(text, "fuzz.json");
    const bool jointActions = std::any_of(scene.actions.begin(), scene.actions.end(), JointVerb);
    if (scene.joints.empty() && !jointActions) {
      (void)REngine::CreateBodies(scene);
    } else {
      try {
        REngine::RSceneWorld world(scene);
        if (jointActions) world.ApplyActions(scene.actions.back().step);
      } catch (const REngine::RSceneError& e) {
        const std::string& path = e.JsonPath();
        if (path.rfind("joints", 0) == 0 || path.find("_joint") != std::string::npos) __builtin_trap();
        throw;
      }
    }
  } catch (const REngine::RSceneError&) {
  }
  return 0;
}
