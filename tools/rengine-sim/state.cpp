// rengine-sim --save-state and --load-state (see state.h).
#include "state.h"

#include <REnginePhysics/RWorldState.h>

#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
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

// A regular file of at most maxBytes, read whole. A directory, a device (/dev/zero never
// ends) or a pipe is refused before reading, and so is a file larger than the limit; a file
// that grows while it is read is cut at the limit and refused too.
std::vector<char> ReadAll(const std::string& path, const char* what, std::uint64_t maxBytes) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) throw StateError{path + ": cannot open " + what + ": " + std::strerror(errno)};
  if (!S_ISREG(info.st_mode)) {
    throw StateError{path + ": cannot read " + what + ": not a regular file (a directory, a device or a pipe)"};
  }
  const auto tooLarge = [&](std::uint64_t size) {
    return StateError{path + ": cannot read " + what + ": it is " + std::to_string(size) + " bytes, more than the " +
                      std::to_string(maxBytes) + " it may be"};
  };
  if (static_cast<std::uint64_t>(info.st_size) > maxBytes) throw tooLarge(static_cast<std::uint64_t>(info.st_size));
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw StateError{path + ": cannot open " + what + ": " + std::strerror(errno)};
  std::vector<char> bytes(static_cast<std::size_t>(info.st_size));
  std::size_t size = std::fread(bytes.data(), 1, bytes.size(), file.get());
  char more[4096];
  while (!std::ferror(file.get()) && !std::feof(file.get())) {
    const std::size_t n = std::fread(more, 1, sizeof more, file.get());
    if (size + n > maxBytes) throw tooLarge(size + n);
    bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(size), more, more + n);
    size += n;
  }
  if (std::ferror(file.get())) throw StateError{path + ": cannot read " + what + ": " + std::strerror(errno)};
  bytes.resize(size);
  return bytes;
}

// What the scene defines of a body (RBodyDef's fields; its shape, kind and mass LoadState
// compares itself) and of a joint, as the scene's world holds them at the state's step:
// a state whose tag was forged onto another scene's file differs in them.
struct SceneBody {
  RBodyHandle handle;
  std::string path;
  RScalar restitution, friction, linearDamping, angularDamping, gravityScale;
  bool responds;
  RBodyLocks locks;
  std::optional<std::uint32_t> id;
  std::uint32_t category, mask;
};
struct SceneJoint {
  RJointHandle handle;
  std::string path;
  RJointDef def;
};

// The first field in which the state's body differs from the scene's, or "".
std::string BodyDifference(const SceneBody& s, const RRigidBody& b) {
  const auto locks = [](const RBodyLocks& l) {
    int bits = 0;
    for (int a = 0; a < 3; ++a) bits |= (l.linear[a] ? 1 : 0) << a | (l.angular[a] ? 1 : 0) << (3 + a);
    return bits;
  };
  if (b.Restitution() != s.restitution) return "restitution";
  if (b.Friction() != s.friction) return "friction";
  if (b.LinearDamping() != s.linearDamping) return "linear_damping";
  if (b.AngularDamping() != s.angularDamping) return "angular_damping";
  if (b.GravityScale() != s.gravityScale) return "gravity_scale";
  if (b.Responds() != s.responds) return "responds";
  if (locks(b.Locks()) != locks(s.locks)) return "locks";
  if (b.Id() != s.id) return "id";
  if (b.Category() != s.category || b.Mask() != s.mask) return "filter";
  return "";
}

// The first field (the scene format's name) in which the state's joint differs, or "".
std::string JointDifference(const RJointDef& s, const RJointDef& j) {
  if (s.type != j.type) return "type";
  if (s.a != j.a) return "a";
  if (s.b != j.b) return "b";
  if (s.anchor_W != j.anchor_W) return "anchor";
  if (s.hasAnchorB != j.hasAnchorB || (s.hasAnchorB && s.anchorB_W != j.anchorB_W)) return "anchor_b";
  if (s.axis_W != j.axis_W) return "axis";
  if (s.hasLimits != j.hasLimits || (s.hasLimits && (s.lower != j.lower || s.upper != j.upper))) return "limits";
  if (s.minDistance != j.minDistance) return "min_distance";
  if (s.maxDistance != j.maxDistance) return "max_distance";
  if (s.motor.enabled != j.motor.enabled ||
      (s.motor.enabled && (s.motor.speed != j.motor.speed || s.motor.maxForce != j.motor.maxForce))) {
    return "motor";
  }
  if (s.collideConnected != j.collideConnected) return "collide_connected";
  return "";
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
  const std::vector<char> text = ReadAll(scenePath, "the scene", RSceneLimits{}.maxFileBytes);
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
  const std::vector<char> file = ReadAll(path, "the state", kMaxStateBytes);
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
  // What the scene defines at that step, by the scene's paths: compared with the state's below.
  std::unordered_map<std::string, std::string> bodyPath;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) bodyPath[scene.bodies[i].name] = "bodies[" + std::to_string(i) + "]";
  std::vector<const RSceneJoint*> namedJoints;
  for (const RSceneJoint& j : scene.joints) namedJoints.push_back(&j);
  for (const RSceneAction& a : scene.actions) {
    if (a.step > info.stepCount) break;
    if (a.verb == RSceneAction::Verb::kAdd) bodyPath[a.body] = a.path + ".add";
    if (a.verb == RSceneAction::Verb::kAddJoint) namedJoints.push_back(&a.joint);
  }
  std::vector<SceneBody> sceneBodies;
  for (RBodyHandle h : world.Live()) {
    const RRigidBody& b = world.Bodies()[h];
    sceneBodies.push_back({h, bodyPath[b.Name()], b.Restitution(), b.Friction(), b.LinearDamping(),
                           b.AngularDamping(), b.GravityScale(), b.Responds(), b.Locks(), b.Id(), b.Category(),
                           b.Mask()});
  }
  std::vector<SceneJoint> sceneJoints;
  for (const RSceneJoint* j : namedJoints) {
    const RJointHandle h = world.FindJoint(j->name);
    // A name an add_joint takes again after its first joint went: the later joint's.
    if (h.IsValid() && world.Bodies().ContainsJoint(h)) {
      sceneJoints.erase(std::remove_if(sceneJoints.begin(), sceneJoints.end(),
                                       [h](const SceneJoint& s) { return s.handle == h; }),
                        sceneJoints.end());
      sceneJoints.push_back({h, j->path, world.Bodies().Joint(h).def});
    }
  }
  RLoadOptions options;
  options.worldTag = tag;
  options.characters = &world.Characters();
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
  // The same bodies and joints, as the scene defines them (a forged tag: another scene's
  // limits, motors or materials run silently with the state's values otherwise).
  for (const SceneBody& s : sceneBodies) {
    const std::string field = BodyDifference(s, world.Bodies()[s.handle]);
    if (!field.empty()) {
      throw StateError{path + ": " + s.path + "." + field + ": the state's body \"" + world.Bodies()[s.handle].Name() +
                       "\" differs from the scene's (a state of another scene)"};
    }
  }
  for (const SceneJoint& s : sceneJoints) {
    if (!world.Bodies().ContainsJoint(s.handle)) {
      throw StateError{path + ": " + s.path + ": the state does not hold this joint of the scene"};
    }
    const std::string field = JointDifference(s.def, world.Bodies().Joint(s.handle).def);
    if (!field.empty()) {
      throw StateError{path + ": " + s.path + "." + field +
                       ": the state's joint differs from the scene's (a state of another scene)"};
    }
  }
  return info.stepCount;
}

bool WriteSceneState(std::FILE* file, const RIntegrator& integrator, const RSceneWorld& world,
                     std::uint64_t tag) {
  std::vector<std::uint8_t> bytes;
  SaveState(integrator, world.Bodies(), world.Characters(), bytes, tag);
  return std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size() && std::fflush(file) == 0;
}

}  // namespace REngine::sim
