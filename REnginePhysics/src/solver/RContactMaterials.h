// Private to REnginePhysics: each contact's material for the solver (RContactSettings:
// friction, restitution, relative surface velocity, enabled), decided when the pair's
// contact is new (one-way bodies, then the game's RContactCallback) and kept while the pair
// stays in contact. Off (no callback and no one-way body in a contact): nothing is kept, and
// the solver combines the bodies' coefficients as it always has.
#pragma once

#include <REnginePhysics/RIntegrator.h>

#include "world/RStepBodies.h"

#include <cstdint>
#include <vector>

namespace REngine {

class RContactMaterials {
 public:
  // A pair's settings while it stays in contact, by handles (a has the lower slot).
  struct RRemembered {
    RBodyHandle a, b;
    RContactSettings settings;
  };

  void SetCallback(RContactCallback callback, void* user) { m_callback = callback, m_user = user; }
  // Before the solver, on the stepping thread: each contact's settings (the remembered ones
  // of a pair in contact last step, else decided now), and the memory for the next step.
  // Throws RError naming the field for settings the callback left out of range.
  void Prepare(const RStepBodies& bodies, const std::vector<RContact>& contacts, const RWorldSettings& settings);
  // Whether the solver must read At() this step (else: the bodies' combined coefficients).
  bool Active() const { return m_active; }
  const RContactSettings& At(std::uint32_t contact) const { return m_perContact[contact]; }

  // Save, load and snapshots (src/state): the memory, sorted by (a, b).
  const std::vector<RRemembered>& Memory() const { return m_memory; }
  void Restore(std::vector<RRemembered> memory) { m_memory = std::move(memory); }

 private:
  RContactCallback m_callback = nullptr;
  void* m_user = nullptr;
  bool m_active = false;
  std::vector<RRemembered> m_memory, m_next;
  std::vector<RContactSettings> m_perContact;
};

}  // namespace REngine
