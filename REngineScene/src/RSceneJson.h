// Private to REngine::Scene: reading a scene's JSON, value by value, each reader given the
// value and its JSON path and failing with both (Invalid, turned into an RSceneError with
// the file name at the API boundary). Used by RScene.cpp (the world and its bodies),
// RSceneActions.cpp (what the game does between steps), RSceneRays.cpp and RSceneJoints.cpp
// (the scene's joints and the joints its actions add).
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RScene.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <initializer_list>
#include <limits>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

namespace REngine::scenejson {

using json = nlohmann::json;

// A problem at a JSON path. Thrown by the readers below and turned into an RSceneError,
// with the file name, at the API boundary, so that no reader needs to know the file.
struct Invalid {
  std::string path;
  std::string problem;
};

[[noreturn]] void Fail(std::string path, std::string problem);
std::string Field(const std::string& path, const std::string& key);
std::string Element(const std::string& path, std::size_t i);
// " (got <value>)", bounded in length and work whatever the value.
std::string Got(const json& j);
// JSON text -> document; duplicate keys and nesting deeper than 64 levels refused.
json ParseJson(const std::string& text);

// The numbers a field accepts, and how an error message states it.
struct Interval {
  RScalar lo, hi;
  bool loOpen;
  const char* text;
};
constexpr Interval kFinite{-kInf, kInf, false, "a finite number"};
constexpr Interval kPositive{0, kInf, true, "a finite number > 0"};
constexpr Interval kNonNegative{0, kInf, false, "a finite number >= 0"};
constexpr Interval kUnit{0, 1, false, "a number in [0, 1]"};

RScalar ReadNumber(const json& j, const std::string& path, const Interval& in);
RScalar ReadPositive(const json& j, const std::string& path);
RScalar ReadUnitInterval(const json& j, const std::string& path);
RScalar ReadNonNegative(const json& j, const std::string& path);
template <int N>
Eigen::Matrix<RScalar, N, 1> ReadVector(const json& j, const std::string& path,
                                        const Interval& in = kFinite) {
  if (!j.is_array() || j.size() != N) {
    Fail(path, "must be an array of " + std::to_string(N) + " numbers" + Got(j));
  }
  Eigen::Matrix<RScalar, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = ReadNumber(j[i], Element(path, i), in);
  return v;
}
RVec3 ReadVec3(const json& j, const std::string& path);
std::uint64_t ReadInteger(const json& j, const std::string& path, std::uint64_t min,
                          std::uint64_t max);
std::uint64_t ReadSteps(const json& j, const std::string& path);
int ReadIterations(const json& j, const std::string& path);
bool ReadBool(const json& j, const std::string& path);
// Filter bits (category, mask): an unsigned 32-bit integer.
std::uint32_t ReadBits(const json& j, const std::string& path);
// A non-empty name without control characters.
std::string ReadName(const json& j, const std::string& path);
// An array of names (an ignore list), each read with ReadName.
std::vector<std::string> ReadNames(const json& j, const std::string& path);
// One of a fixed set of strings, mapped to its value.
template <class T>
T ReadChoice(const json& j, const std::string& path,
             std::initializer_list<std::pair<const char*, T>> choices) {
  if (j.is_string()) {
    for (const auto& [name, value] : choices) {
      if (j.get_ref<const std::string&>() == name) return value;
    }
  }
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "\"" : ", \"") + std::string(c.first) + '"';
  Fail(path, "must be one of " + list + Got(j));
}
RCombineMode ReadRestitutionCombine(const json& j, const std::string& path);
RCombineMode ReadFrictionCombine(const json& j, const std::string& path);
RQuat ReadOrientation(const json& j, const std::string& path);

// A JSON object at a path, whose fields are all known (the format refuses unknown fields
// so that a misspelt one never passes as a default), with typed reads of its fields.
class Object {
 public:
  Object(const json& j, std::string path, std::initializer_list<const char*> fields)
      : m_j(j), m_path(std::move(path)) {
    if (!j.is_object()) {
      Fail(m_path, (m_path.empty() ? "the scene must be a JSON object" : "must be an object") +
                       Got(j));
    }
    AllowOnly(fields);
  }

  // Narrows the known fields once more is known (a shape's fields depend on its type).
  void AllowOnly(std::initializer_list<const char*> fields) const {
    for (const auto& item : m_j.items()) {
      const bool known = std::any_of(fields.begin(), fields.end(),
                                     [&](const char* f) { return item.key() == f; });
      if (!known) {
        std::string list;
        for (const char* f : fields) list += (list.empty() ? "" : ", ") + std::string(f);
        Fail(PathOf(item.key()), "unknown field (the fields here are: " + list + ")");
      }
    }
  }

  std::string PathOf(const std::string& key) const { return Field(m_path, key); }
  bool Has(const char* key) const { return m_j.contains(key); }

  const json& Required(const char* key) const {
    const auto it = m_j.find(key);
    if (it == m_j.end()) Fail(PathOf(key), "required field is missing");
    return *it;
  }

  // read(value, path) of the field, or `fallback` when it is absent.
  template <class T, class Read>
  T Get(const char* key, T fallback, Read read) const {
    const auto it = m_j.find(key);
    return it == m_j.end() ? fallback : T(read(*it, PathOf(key)));
  }

 private:
  const json& m_j;
  std::string m_path;
};

RScalar ReadFiniteNumber(const json& j, const std::string& path);
RBodyLocks ReadLocks(const json& j, const std::string& path);
RShape ReadShape(const json& j, const std::string& path, const RSceneLimits& limits);
// A body, and the names in its "ignore" list (resolved by the caller, once the names it may
// refer to are known).
RBodyDef ReadBody(const json& j, const std::string& path, std::vector<std::string>& ignore,
                  const RSceneLimits& limits);

// The scene's "actions" (RSceneActions.cpp): read, checked against the bodies that exist at
// each step (scene.bodies must be read already), sorted by step.
void ReadActions(const json& j, RScene& scene, const RSceneLimits& limits);

// The scene's "characters" (RSceneCharacters.cpp): read and checked (scene.bodies, the
// settings and the bodies' names must be read already; a character's name is unique among
// the bodies' and characters'), in file order.
void ReadCharacters(const json& j, RScene& scene, const RSceneLimits& limits);
// The scene's "rays" (RSceneRays.cpp): read, checked, sorted by step.
void ReadRays(const json& j, RScene& scene, const RSceneLimits& limits);

// The scene's "joints" (RSceneJoints.cpp): read and checked against the scene's bodies
// (scene.bodies must be read already), in file order.
void ReadJoints(const json& j, RScene& scene, const RSceneLimits& limits);

// A joint object (RSceneJoints.cpp), as in "joints" and in an add_joint action, at `path`:
// every field read and checked as RBodies::AddJoint would, but for its bodies, whose names are
// kept (a, b) for CheckJointBodies: which bodies exist depends on where the joint is made.
// `when` completes the message of a max_distance below the anchors' distance ("as the scene
// starts").
RSceneJoint ReadJoint(const json& j, const std::string& path, const char* when);
// The bodies a joint may name where it is made: name -> whether the body is immovable.
using JointBodies = std::unordered_map<std::string, bool>;
// RRigidBody's rule: static, kinematic, or dynamic with all six axes locked (which it treats
// as kinematic). A joint needs a body that is not.
bool Immovable(const RBodyDef& def);
// Fails at joint.path's "a" or "b" with noBodyNamed(name) for a body not in `bodies`, and as
// AddJoint refuses for the same body twice or two immovable ones.
void CheckJointBodies(const RSceneJoint& joint, const JointBodies& bodies,
                      const std::function<std::string(const std::string&)>& noBodyNamed);

// Equal shapes share one prepared shape: a scene of a thousand equal boxes, or one that
// spawns a thousand missiles, builds their hull once, and its bodies share one copy of it
// (one set of vertices in the cache instead of a thousand).
class ShapeCache {
 public:
  std::shared_ptr<const RPreparedShape> Get(const RShape& s) {
    std::vector<RScalar> key;
    Flatten(s, key);
    auto it = m_cache.find(key);
    if (it == m_cache.end()) it = m_cache.emplace(std::move(key), PrepareShape(s)).first;
    return it->second;
  }

 private:
  // Every field of RShape, a compound's children's too, as numbers: a field left out would
  // merge different shapes.
  static void Flatten(const RShape& s, std::vector<RScalar>& out) {
    out.insert(out.end(), {static_cast<RScalar>(s.type), s.radius, s.halfHeight, s.halfExtents.x(),
                           s.halfExtents.y(), s.halfExtents.z(), static_cast<RScalar>(s.points.size())});
    for (const RVec3& p : s.points) out.insert(out.end(), {p.x(), p.y(), p.z()});
    out.push_back(static_cast<RScalar>(s.triangles.size()));
    for (const auto& t : s.triangles) out.insert(out.end(), {RScalar(t[0]), RScalar(t[1]), RScalar(t[2])});
    out.push_back(static_cast<RScalar>(s.children.size()));
    for (const RCompoundChild& c : s.children) {
      Flatten(c.shape, out);
      out.insert(out.end(), {c.position_S.x(), c.position_S.y(), c.position_S.z(), c.q_SC.w(), c.q_SC.x(),
                             c.q_SC.y(), c.q_SC.z(), c.density});
    }
  }
  using Key = std::vector<RScalar>;
  std::map<Key, std::shared_ptr<const RPreparedShape>> m_cache;
};

}  // namespace REngine::scenejson
