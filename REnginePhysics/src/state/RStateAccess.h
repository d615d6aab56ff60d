// Private to REnginePhysics: the state's records (RStateAccess, which reaches the state of
// bodies, containers and integrators through body/RBodyAccess.h). RStateRecords.cpp writes
// and reads each record; RWorldState.cpp saves and loads a whole world with them
// (RWorldState.h), checking everything before it replaces anything.
#pragma once

#include <REnginePhysics/RWorldState.h>

#include "state/RStateFormat.h"
#include "world/RWorldStep.h"

#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace REngine {

namespace state {


// A body's kind as the state writes it.
enum : std::uint8_t { kDynamic = 0, kStatic = 1, kKinematic = 2 };

// The key a body's shape is saved under: the checksum of its definition (RShape) written as
// a record. Equal shapes prepared apart (two scenes, two spawns) have one key.
inline void WriteShapeRecord(RWriter& w, const RShape& shape) {
  w.U8(static_cast<std::uint8_t>(shape.type));
  switch (shape.type) {
    case RShapeType::kSphere: w.F64(shape.radius); break;
    case RShapeType::kBox: w.Vec3(shape.halfExtents); break;
    case RShapeType::kCapsule:
    case RShapeType::kCylinder: w.F64(shape.radius), w.F64(shape.halfHeight); break;
    case RShapeType::kHull:
      w.U64(shape.points.size());
      for (const RVec3& p : shape.points) w.Vec3(p);
      break;
    case RShapeType::kMesh:
      w.U64(shape.points.size());
      for (const RVec3& p : shape.points) w.Vec3(p);
      w.U64(shape.triangles.size());
      for (const auto& t : shape.triangles) w.U32(t[0]), w.U32(t[1]), w.U32(t[2]);
      break;
    case RShapeType::kCompound:
      w.U64(shape.children.size());
      for (const RCompoundChild& c : shape.children) {
        WriteShapeRecord(w, c.shape);
        w.Vec3(c.position_S);
        w.F64(c.q_SC.w()), w.F64(c.q_SC.x()), w.F64(c.q_SC.y()), w.F64(c.q_SC.z());
        w.F64(c.density);
      }
      break;
  }
}

inline std::uint64_t ShapeKey(const RShape& shape) {
  std::vector<std::uint8_t> bytes;
  RWriter w(bytes);
  WriteShapeRecord(w, shape);
  return Checksum(bytes.data(), bytes.size());
}

// Keys of prepared shapes, each computed once however many bodies share the shape.
class RShapeKeys {
 public:
  std::uint64_t Of(const std::shared_ptr<const RPreparedShape>& prepared) {
    const auto it = m_keys.find(prepared.get());
    if (it != m_keys.end()) return it->second;
    const std::uint64_t key = ShapeKey(prepared->shape);
    m_keys.emplace(prepared.get(), key);
    return key;
  }

 private:
  std::unordered_map<const RPreparedShape*, std::uint64_t> m_keys;
};

inline std::string Hex(std::uint64_t v) {
  char text[24];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

inline std::string Indexed(const char* name, std::size_t i) { return std::string(name) + "[" + std::to_string(i) + "]"; }

inline std::string HandleText(RBodyHandle h) {
  return "(" + std::to_string(h.index) + ", " + std::to_string(h.generation) + ")";
}

}  // namespace state

// Every record of the format, in one place: what is written is read back field for field in
// the same order (a field added to a class that carries between steps belongs here, and in
// the round-trip tests, tests/state/state_test.cpp).
struct RStateAccess {
  using RReader = state::RReader;
  using RWriter = state::RWriter;
  // serialOwned(handle, serial): whether that body is in the container with that serial.
  using RSerialOwned = std::function<bool(RBodyHandle, std::uint64_t)>;

  // ---- the integrator -------------------------------------------------------------------

  // The integrator's memory as read, before it replaces the integrator's.
  struct RSavedStep {
    RWorldSettings settings;
    std::uint64_t stepCount = 0, warmBodyCount = 0, sleepBodyCount = 0;
    bool wakeAll = false;
    RVec3 sleepGravity_W = RVec3::Zero();
    std::optional<RNonFiniteBody> nonFinite;
    std::vector<RWarmStart> warm;
    std::vector<RManifoldMemory> manifolds;
    std::vector<std::uint8_t> manifoldSerials;  // per manifold: bit 0 A's serial was its body's, bit 1 B's
    std::vector<RContactEventLog::RTouchingPair> touching;
    std::vector<RContactMaterials::RRemembered> materials;
  };

  static void WriteSettings(RWriter& w, const RWorldSettings& s);

  static RWorldSettings ReadSettings(RReader& r);

  static void WriteManifold(RWriter& w, const RContactManifold& m);

  static RContactManifold ReadManifold(RReader& r);

  static void WriteStep(RWriter& w, const RWorldStep& s, const RSerialOwned& serialOwned);

  static RBodyHandle ReadHandle(RReader& r, const char* field);

  static RSavedStep ReadStep(RReader& r);

  // ---- bodies ---------------------------------------------------------------------------
  static void WriteJacobi(RWriter& w, const RJacobiSnCnDn& j);
  static RJacobiSnCnDn ReadJacobi(RReader& r, const char* field, bool check);

  static void WriteRotation(RWriter& w, const RFreeRotation& f);

  static void ReadRotation(RReader& r, RFreeRotation& f);

  static std::uint8_t WorldOf(const RRigidBody& b, const RWorldStep& s);

  static void WriteBody(RWriter& w, const RRigidBody& b, std::uint64_t shapeKey, std::uint8_t world);

  // The shapes a load can rebuild bodies with, by key.
  using RShapeCatalog = std::unordered_map<std::uint64_t, std::shared_ptr<const RPreparedShape>>;

  static RRigidBody ReadBody(RReader& r, const RShapeCatalog& shapes, std::uint64_t& shapeKey,
                             std::uint64_t worldId, std::uint64_t foreignId);

  // ---- the container --------------------------------------------------------------------

  // What a load builds before it replaces anything.
  struct RSavedBodies {
    std::vector<RRigidBody> bodies;
    std::vector<std::uint64_t> shapeKeys;
    std::vector<RBodyHandle> handles;          // RBodies only
    std::vector<std::uint32_t> generation, denseOfSlot, free, wakeIslands;
    std::vector<RVec3> wakeBoxes;
    std::size_t enabled = 0;
    bool wakeAll = false;
    bool plainVector = false;
    // RBodies only: the joints and their slot table (RStateJoints.cpp).
    std::vector<RJoint> joints;
    std::vector<RJointHandle> jointHandles;
    std::vector<std::uint32_t> jointGeneration, jointDenseOfSlot, jointFree;
  };
  static void WriteJoints(RWriter& w, const RBodies& c);
  static void ReadJoints(RReader& r, RSavedBodies& out);
  static void CommitJoints(RBodies& bodies, RSavedBodies& saved);

  // The checks that span records (RStateChecks.cpp): indices in range, handles issued.
  static void CheckReferences(const RSavedStep& step, const RSavedBodies& saved);

  static void WriteBodies(RWriter& w, const RWorldStep& s, const std::vector<RRigidBody>& bodies);

  static void WriteContainer(RWriter& w, const RWorldStep& s, const RBodies& c);

  static void WriteContainer(RWriter& w, const RWorldStep& s, const std::vector<RRigidBody>& c);

  static RSavedBodies ReadContainer(RReader& r, const RShapeCatalog& shapes, std::uint64_t worldId,
                                    std::uint64_t foreignId);

  // ---- save -----------------------------------------------------------------------------
  template <class Container, class SerialOwned>
  static void Save(const RIntegrator& integrator, const Container& bodies, std::vector<std::uint8_t>& out,
                   std::uint64_t worldTag, const SerialOwned& serialOwned,
                   const std::vector<RCharacter>* characters = nullptr);

  // ---- load -----------------------------------------------------------------------------
  static RReader Open(const std::uint8_t* data, std::size_t size);

  static RShapeCatalog Catalog(const std::vector<RRigidBody>& bodies, const RLoadOptions& options);

  template <class Commit>
  static void Load(RIntegrator& integrator, const std::vector<RRigidBody>& target, const std::uint8_t* data,
                   std::size_t size, const RLoadOptions& options, bool plainVector, const Commit& commit);

  static std::uint64_t SerialAt(const RSavedBodies& saved, RBodyHandle h);

  static void LoadInto(RIntegrator& integrator, RBodies& bodies, const std::uint8_t* data, std::size_t size,
                       const RLoadOptions& options);

  static void LoadInto(RIntegrator& integrator, std::vector<RRigidBody>& bodies, const std::uint8_t* data,
                       std::size_t size, const RLoadOptions& options);

  static RStateInfo Info(const std::uint8_t* data, std::size_t size);
};

}  // namespace REngine
