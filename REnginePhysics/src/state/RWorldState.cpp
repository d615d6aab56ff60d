// Save and load (RWorldState.h): a world's state sealed into bytes, and read back whole,
// checked against the loading world, and only then put in its place (the records:
// RStateRecords.cpp).
#include "state/RStateAccess.h"
#include "body/RBodyAccess.h"
#include "state/RStateCharacters.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace REngine {

using namespace state;


template <class Container, class SerialOwned>
void RStateAccess::Save(const RIntegrator& integrator, const Container& bodies, std::vector<std::uint8_t>& out,
                 std::uint64_t worldTag, const SerialOwned& serialOwned,
                 const std::vector<RCharacter>* characters) {
  out.clear();
  out.resize(state::kHeaderBytes);
  RWriter w(out);
  w.U64(worldTag);
  WriteStep(w, *Core(integrator).m_w, serialOwned);
  WriteContainer(w, *Core(integrator).m_w, bodies);
  WriteCharacters(w, characters);
  state::Seal(out);
}


// The header checked; returns a reader at the payload's start.
RReader RStateAccess::Open(const std::uint8_t* data, std::size_t size) {
  if (size == 0) throw RStateError("header.magic", "is not a REngine world state (0 bytes)");
  if (std::memcmp(data, state::kMagic, std::min(size, sizeof state::kMagic)) != 0) {
    throw RStateError("header.magic", "is not a REngine world state (its first bytes are not \\x89RSTATE\\n)");
  }
  if (size < state::kHeaderBytes) {
    throw RStateError("header", "the state ends at byte " + std::to_string(size) + ", inside its " +
                                    std::to_string(state::kHeaderBytes) + "-byte header (cut short)");
  }
  const std::uint32_t version = static_cast<std::uint32_t>(state::LoadU64(data + state::kVersionAt) & 0xffffffffu);
  if (version != state::kVersion) {
    throw RStateError("header.version", "is " + std::to_string(version) + "; this build reads version " +
                                            std::to_string(state::kVersion));
  }
  const std::uint32_t reserved = static_cast<std::uint32_t>(state::LoadU64(data + state::kVersionAt) >> 32);
  if (reserved != 0) throw RStateError("header.reserved", "must be 0");
  const std::uint64_t length = state::LoadU64(data + state::kLengthAt);
  if (length != size - state::kHeaderBytes) {
    throw RStateError("header.length", "says " + std::to_string(length) + " bytes of payload, and " +
                                           std::to_string(size - state::kHeaderBytes) +
                                           " follow the header (cut short or padded)");
  }
  const std::uint64_t checksum = state::Checksum(data + state::kHeaderBytes, size - state::kHeaderBytes);
  if (checksum != state::LoadU64(data + state::kChecksumAt)) {
    throw RStateError("header.checksum", "does not match the payload (the state was altered or corrupted)");
  }
  return RReader(data, size, state::kHeaderBytes);
}

// The shapes of every body the loading container holds (enabled or not) and the options'.
RStateAccess::RShapeCatalog RStateAccess::Catalog(const std::vector<RRigidBody>& bodies, const RLoadOptions& options) {
  RShapeCatalog catalog;
  RShapeKeys keys;
  for (const RRigidBody& b : bodies) catalog.emplace(keys.Of(Core(b).m_prepared), Core(b).m_prepared);
  for (const auto& shape : options.shapes) {
    if (shape) catalog.emplace(keys.Of(shape), shape);
  }
  return catalog;
}

// Reads everything, checks it against the loading world, then (nothing having thrown)
// replaces the world's memory and bodies.
template <class Commit>
void RStateAccess::Load(RIntegrator& integrator, const std::vector<RRigidBody>& target, const std::uint8_t* data,
                 std::size_t size, const RLoadOptions& options, bool plainVector, const Commit& commit) {
  RReader r = Open(data, size);
  const std::uint64_t tag = r.U64("world_tag");
  if (tag != options.worldTag) {
    r.Fail("world_tag", "is " + Hex(tag) + ", the loading world's " + Hex(options.worldTag) +
                            ": a state saved from another world");
  }
  RSavedStep step = ReadStep(r);
  RWorldStep& w = *Core(integrator).m_w;
  const std::uint64_t foreignId = NextCacheStamp();
  RSavedBodies saved = ReadContainer(r, Catalog(target, options), w.m_sleep.WorldId(), foreignId);
  std::vector<RCharacter> characters = ReadCharacters(r, options.characters);
  if (r.Left() != 0) {
    throw RStateError("payload", std::to_string(r.Left()) + " bytes follow the last character (corrupt)");
  }
  if (saved.plainVector != plainVector) {
    throw RStateError("container.kind",
                      plainVector ? "is an RBodies': it loads into an RBodies, not a plain vector"
                                  : "is a plain vector's: it loads into a plain vector, not an RBodies");
  }
  CheckReferences(step, saved);
  // The manifolds name bodies by their place among the stepped ones; their serials are
  // the rebuilt bodies' where they were the saved bodies'.
  for (std::size_t k = 0; k < step.manifolds.size(); ++k) {
    RManifoldMemory& m = step.manifolds[k];
    if (m.j >= saved.enabled) {
      throw RStateError(Indexed("manifolds", k) + ".j",
                        "is beyond the " + std::to_string(saved.enabled) + " stepped bodies");
    }
    m.serialA = (step.manifoldSerials[k] & 1) ? SerialAt(saved, m.handleA) : 0;
    m.serialB = (step.manifoldSerials[k] & 2) ? SerialAt(saved, m.handleB) : 0;
  }
  commit(saved);
  if (options.characters) options.characters->swap(characters);
  // The integrator, now that nothing can throw: its settings (but its own threads), memory
  // and step count; its last step's outputs and the broad phase's lists emptied; a new
  // cache stamp, since every body's world form is to be recomputed.
  const int threads = w.m_settings.threads;
  w.m_settings = step.settings;
  w.m_settings.threads = threads;
  w.m_stepCount = step.stepCount;
  w.m_sleep.RestoreForLoad(RLoadKey{}, {step.sleepBodyCount, step.wakeAll, step.sleepGravity_W});
  w.m_motion.RestoreForLoad(RLoadKey{}, std::move(step.nonFinite));
  w.m_solver.RestoreForLoad(RLoadKey{}, std::move(step.warm), static_cast<std::size_t>(step.warmBodyCount));
  w.m_sweep.RestoreForLoad(RLoadKey{}, std::move(step.manifolds));
  w.m_eventLog.RestoreForLoad(RLoadKey{}, std::move(step.touching));
  w.m_materials.Restore(std::move(step.materials));
  w.m_cacheStamp = NextCacheStamp();
  w.m_profile = RStepProfile{};
  w.m_broad.Invalidate();
}

std::uint64_t RStateAccess::SerialAt(const RSavedBodies& saved, RBodyHandle h) {
  if (saved.plainVector) {
    return h.generation == 0 && h.index < saved.bodies.size() ? saved.bodies[h.index].Serial() : 0;
  }
  if (h.index >= saved.denseOfSlot.size() || saved.generation[h.index] != h.generation) return 0;
  const std::uint32_t d = saved.denseOfSlot[h.index];
  return d < saved.bodies.size() ? saved.bodies[d].Serial() : 0;
}

void RStateAccess::LoadInto(RIntegrator& integrator, RBodies& bodies, const std::uint8_t* data, std::size_t size,
                     const RLoadOptions& options) {
  Load(integrator, Core(bodies).m_slots.items, data, size, options, false, [&bodies](RSavedBodies& saved) {
    // Another world's state names a body the container holds as another body.
    RShapeKeys keys;
    for (std::size_t d = 0; d < saved.bodies.size(); ++d) {
      const RBodyHandle h = saved.handles[d];
      const RRigidBody* found = bodies.Find(h);
      if (!found) continue;
      const RBodyCore* now = &Core(*found);
      const RBodyCore& then = Core(saved.bodies[d]);
      const bool same = now->m_name == then.m_name && keys.Of(now->m_prepared) == saved.shapeKeys[d] &&
                        found->Kind() == saved.bodies[d].Kind() &&
                        std::memcmp(&now->m_mass, &then.m_mass, sizeof then.m_mass) == 0;
      if (!same) {
        throw RStateError(Indexed("bodies", d), "the loading container holds handle " + HandleText(h) + " as \"" +
                                                    now->m_name + "\", the state as \"" + then.m_name +
                                                    "\" with another shape, kind or mass: a state of another world");
      }
    }
    Core(bodies).m_slots.items.swap(saved.bodies);
    Core(bodies).m_slots.handles.swap(saved.handles);
    Core(bodies).m_slots.generation.swap(saved.generation);
    Core(bodies).m_slots.denseOfSlot.swap(saved.denseOfSlot);
    Core(bodies).m_slots.free.swap(saved.free);
    Core(bodies).m_wakeIslands.swap(saved.wakeIslands);
    Core(bodies).m_enabled = saved.enabled;
    Core(bodies).m_wakeAll = saved.wakeAll;
    Core(bodies).m_wakeBoxes.swap(saved.wakeBoxes);
    CommitJoints(bodies, saved);
    Core(bodies).LayoutChanged();  // queries' trees are rebuilt
  });
}

void RStateAccess::LoadInto(RIntegrator& integrator, std::vector<RRigidBody>& bodies, const std::uint8_t* data,
                     std::size_t size, const RLoadOptions& options) {
  Load(integrator, bodies, data, size, options, true, [&bodies](RSavedBodies& saved) { bodies.swap(saved.bodies); });
}

RStateInfo RStateAccess::Info(const std::uint8_t* data, std::size_t size) {
  RReader r = Open(data, size);
  RStateInfo info;
  info.version = state::kVersion;
  info.worldTag = r.U64("world_tag");
  RSavedStep step = ReadStep(r);
  info.stepCount = step.stepCount;
  r.SetRecord("container");
  const std::uint8_t kind = r.U8("kind");
  if (kind > 1) r.Fail("kind", "must be 0 (RBodies) or 1 (a plain vector)");
  info.plainVector = kind == 1;
  if (!info.plainVector) {
    const std::size_t slots = r.Count("slots", 4);
    for (std::size_t k = 0; k < slots; ++k) r.U32("generations");
    const std::size_t free = r.Count("free", 4);
    for (std::size_t k = 0; k < free; ++k) r.U32("free");
    r.U64("enabled");
  }
  info.bodyCount = r.U64("bodies");
  return info;
}

std::vector<std::uint8_t> SaveState(const RIntegrator& integrator, const RBodies& bodies, std::uint64_t worldTag) {
  std::vector<std::uint8_t> out;
  SaveState(integrator, bodies, out, worldTag);
  return out;
}

void SaveState(const RIntegrator& integrator, const RBodies& bodies, std::vector<std::uint8_t>& out,
               std::uint64_t worldTag) {
  RStateAccess::Save(integrator, bodies, out, worldTag, [&bodies](RBodyHandle h, std::uint64_t serial) {
    const RRigidBody* b = bodies.Find(h);
    return b && b->Serial() == serial;
  });
}

void SaveState(const RIntegrator& integrator, const RBodies& bodies, const std::vector<RCharacter>& characters,
               std::vector<std::uint8_t>& out, std::uint64_t worldTag) {
  RStateAccess::Save(
      integrator, bodies, out, worldTag,
      [&bodies](RBodyHandle h, std::uint64_t serial) {
        const RRigidBody* b = bodies.Find(h);
        return b && b->Serial() == serial;
      },
      &characters);
}

std::vector<std::uint8_t> SaveState(const RIntegrator& integrator, const std::vector<RRigidBody>& bodies,
                                    std::uint64_t worldTag) {
  std::vector<std::uint8_t> out;
  RStateAccess::Save(integrator, bodies, out, worldTag, [&bodies](RBodyHandle h, std::uint64_t serial) {
    return h.generation == 0 && h.index < bodies.size() && bodies[h.index].Serial() == serial;
  });
  return out;
}

RStateInfo ReadStateInfo(const std::uint8_t* state, std::size_t size) { return RStateAccess::Info(state, size); }

void LoadState(RIntegrator& integrator, RBodies& bodies, const std::uint8_t* state, std::size_t size,
               const RLoadOptions& options) {
  RStateAccess::LoadInto(integrator, bodies, state, size, options);
}

void LoadState(RIntegrator& integrator, RBodies& bodies, const std::vector<std::uint8_t>& state,
               const RLoadOptions& options) {
  RStateAccess::LoadInto(integrator, bodies, state.data(), state.size(), options);
}

void LoadState(RIntegrator& integrator, std::vector<RRigidBody>& bodies, const std::vector<std::uint8_t>& state,
               const RLoadOptions& options) {
  RStateAccess::LoadInto(integrator, bodies, state.data(), state.size(), options);
}

}  // namespace REngine
