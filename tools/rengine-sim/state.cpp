// rengine-sim --save-state and --load-state (see state.h).
#include "state.h"

#include <REnginePhysics/RWorldState.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

namespace REngine::sim {

namespace {

// FNV-1a, 64 bit.
void Fold(std::uint64_t& h, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < size; ++k) h = (h ^ bytes[k]) * 0x100000001b3ULL;
}

std::string Hex(std::uint64_t v) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

std::vector<char> ReadAll(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw StateError{path + ": cannot open " + what + ": " + std::strerror(errno)};
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw StateError{path + ": cannot read " + what + ": " + std::strerror(errno)};
  return bytes;
}

}  // namespace

StateSave ParseSaveState(const std::string& text) {
  const std::size_t colon = text.find(':');
  StateSave save;
  const char* end = text.data() + (colon == std::string::npos ? 0 : colon);
  const auto [at, ec] = std::from_chars(text.data(), end, save.step);
  if (colon == std::string::npos || colon == 0 || ec != std::errc() || at != end || colon + 1 == text.size()) {
    throw StateError{"--save-state: must be STEP:FILE, STEP an integer >= 0 (got \"" + text + "\")"};
  }
  save.path = text.substr(colon + 1);
  return save;
}

std::uint64_t SceneTag(const std::string& scenePath, double dt) {
  const std::vector<char> text = ReadAll(scenePath, "the scene");
  nlohmann::json scene;
  try {
    scene = nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {
    throw StateError{scenePath + ": cannot read the scene again: " + e.what()};
  }
  // What does not change the world: how long it runs, what is asked of it. The step size is
  // the run's (the scene's or --dt).
  for (const char* key : {"steps", "rays", "dt"}) scene.erase(key);
  const std::string canonical = scene.dump();  // keys sorted, numbers in shortest form
  std::uint64_t h = 0xcbf29ce484222325ULL;
  Fold(h, canonical.data(), canonical.size());
  Fold(h, &dt, sizeof dt);
  return h;
}

std::uint64_t LoadSceneState(const std::string& path, const RScene& scene, std::uint64_t tag,
                             RSceneWorld& world, RIntegrator& integrator) {
  const std::vector<char> file = ReadAll(path, "the state");
  const auto* data = reinterpret_cast<const std::uint8_t*>(file.data());
  RStateInfo info;
  try {
    info = ReadStateInfo(data, file.size());
  } catch (const RStateError& e) {
    throw StateError{path + ": not a state rengine-sim can load: " + e.what()};
  }
  if (info.worldTag != tag) {
    throw StateError{path + ": was saved from another scene, or with another step size (its scene tag is " +
                     Hex(info.worldTag) + ", this run's " + Hex(tag) + ")"};
  }
  if (info.stepCount > scene.steps) {
    throw StateError{path + ": the state is at step " + std::to_string(info.stepCount) + ", beyond the " +
                     std::to_string(scene.steps) + " steps of this run"};
  }
  // The scene's world at that step, by name and order of creation; then the state's bodies.
  try {
    world.ApplyActions(info.stepCount);
  } catch (const RSceneError& e) {
    throw StateError{path + ": the scene's actions up to its step " + std::to_string(info.stepCount) +
                     " cannot be replayed: " + e.what()};
  }
  RLoadOptions options;
  options.worldTag = tag;
  try {
    LoadState(integrator, world.Bodies(), data, file.size(), options);
  } catch (const RStateError& e) {
    throw StateError{path + ": " + e.what()};
  }
  // Guaranteed for a state of this scene; a forged one is refused here rather than run.
  bool same = world.Bodies().Size() == world.Live().size();
  for (RBodyHandle h : world.Live()) same = same && world.Bodies().Contains(h);
  if (!same) {
    throw StateError{path + ": its bodies are not the scene's bodies at step " + std::to_string(info.stepCount)};
  }
  // The joints likewise: those the scene's joints and actions leave at that step, by name.
  if (!world.HoldsExactlyItsJoints()) {
    throw StateError{path + ": its joints are not the scene's joints at step " + std::to_string(info.stepCount)};
  }
  return info.stepCount;
}

bool WriteSceneState(std::FILE* file, const RIntegrator& integrator, const RSceneWorld& world,
                     std::uint64_t tag) {
  const std::vector<std::uint8_t> bytes = SaveState(integrator, world.Bodies(), tag);
  return std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size() && std::fflush(file) == 0;
}

}  // namespace REngine::sim
