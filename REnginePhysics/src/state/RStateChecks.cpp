// The checks of a state that span records (RStateAccess, RStateAccess.h): every index a
// record keeps into another (a sleeping body's island, a remembered pair's slots) in range,
// and every handle one names a handle the container issued; run on the temporaries before
// the world is touched. A forged index would have the next step write out of bounds (a
// sleeping body's island marks a slot's entry when something touches it).
#include "state/RStateAccess.h"
#include "body/RBodyAccess.h"

#include <string>
#include <vector>

namespace REngine {

using namespace state;

namespace {

// The handles a container issued: those of its live bodies and every earlier generation of
// a slot (a body removed since, which a remembered pair may still name). A retired slot
// (its generation wrapped) issued them all.
class RIssued {
 public:
  explicit RIssued(const RStateAccess::RSavedBodies& saved) : m_saved(saved) {
    m_free.assign(saved.generation.size(), 0);
    for (std::uint32_t slot : saved.free) m_free[slot] = 1;
  }
  bool operator()(RBodyHandle h) const {
    if (m_saved.plainVector) return h.generation == 0;  // a plain vector's: (index, 0)
    if (h.index >= m_saved.generation.size()) return false;
    const std::uint32_t now = m_saved.generation[h.index];
    const bool live = m_saved.denseOfSlot[h.index] < m_saved.bodies.size();
    const bool retired = !live && !m_free[h.index] && now == 0;
    return h.generation < now || (h.generation == now && live) || retired;
  }

 private:
  const RStateAccess::RSavedBodies& m_saved;
  std::vector<char> m_free;
};

}  // namespace

void RStateAccess::CheckReferences(const RSavedStep& step, const RSavedBodies& saved) {
  // Island ids are slots (a plain vector's: indices). An RBodies' slot table never shrinks,
  // so every id it gave is below its size. A plain vector's bodies may have been erased since
  // the last step: then its count differs from the one the step saw, and the next step wakes
  // everything before any id is used.
  const std::size_t n = saved.bodies.size();
  const std::size_t slots = saved.plainVector ? n : saved.generation.size();
  const bool idsUsed = !saved.plainVector || step.sleepBodyCount == n;
  const std::uint32_t none = RBodyCore::kNoIsland;
  for (std::size_t d = 0; d < n; ++d) {
    const RBodyCore& b = Core(saved.bodies[d]);
    const std::string at = Indexed("bodies", d);
    if (b.m_sleeping || b.m_sleepIsland != none) {
      // Only dynamic bodies join islands; a departing (disabled) body leaves its island.
      if (b.Immovable()) {
        throw RStateError(at + (b.m_sleeping ? ".sleeping" : ".island"),
                          "a static or kinematic body never sleeps and has no island");
      }
      if (d >= saved.enabled) {
        throw RStateError(at + (b.m_sleeping ? ".sleeping" : ".island"),
                          "a disabled body never sleeps and has no island");
      }
    }
    if (b.m_sleeping && b.m_sleepIsland == none) {
      throw RStateError(at + ".island", "a sleeping body must name the island it sleeps with");
    }
    if (b.m_sleepIsland != none && idsUsed && b.m_sleepIsland >= slots) {
      throw RStateError(at + ".island", "is " + std::to_string(b.m_sleepIsland) + ", beyond the " +
                                            std::to_string(slots) + " slots island ids are taken from");
    }
    if (!saved.plainVector && b.m_slot != none && b.m_slot >= slots) {
      throw RStateError(at + ".slot", "is " + std::to_string(b.m_slot) + ", beyond the " +
                                          std::to_string(slots) + " slots of the container");
    }
  }
  for (std::size_t k = 0; k < saved.wakeIslands.size(); ++k) {
    if (saved.wakeIslands[k] >= slots) {
      throw RStateError(Indexed("container.wake_islands", k),
                        "is " + std::to_string(saved.wakeIslands[k]) + ", beyond the " + std::to_string(slots) +
                            " slots island ids are taken from");
    }
  }
  // Remembered pairs name bodies the container holds or held.
  const RIssued issued(saved);
  for (std::size_t k = 0; k < step.warm.size(); ++k) {
    const RWarmStart& w = step.warm[k];
    const RBodyHandle a{static_cast<std::uint32_t>(w.pair >> 32), w.genA};
    const RBodyHandle b{static_cast<std::uint32_t>(w.pair & 0xffffffffu), w.genB};
    if (!issued(a) || !issued(b)) {
      throw RStateError(Indexed("warm_starts", k) + ".pair",
                        "names " + HandleText(a) + " and " + HandleText(b) + ", a body the container never held");
    }
  }
  for (std::size_t k = 0; k < step.manifolds.size(); ++k) {
    const RManifoldMemory& m = step.manifolds[k];
    if (!issued(m.handleA)) {
      throw RStateError(Indexed("manifolds", k) + ".handle_a", HandleText(m.handleA) + " names a body the container never held");
    }
    if (!issued(m.handleB)) {
      throw RStateError(Indexed("manifolds", k) + ".handle_b", HandleText(m.handleB) + " names a body the container never held");
    }
  }
  for (std::size_t k = 0; k < step.touching.size(); ++k) {
    const RContactEventLog::RTouchingPair& t = step.touching[k];
    if (!issued(t.a)) {
      throw RStateError(Indexed("touching", k) + ".handle_a", HandleText(t.a) + " names a body the container never held");
    }
    if (!issued(t.b)) {
      throw RStateError(Indexed("touching", k) + ".handle_b", HandleText(t.b) + " names a body the container never held");
    }
  }
}

}  // namespace REngine
