// RSlotHandle and RSlotMap: stable names over dense storage, as Box2D's and Jolt's bodies are
// named. RBodies keeps its bodies and its joints in one each (RBodyHandle, RJointHandle).
//
// A handle is a slot index and the slot's generation. The items sit densely in the order the
// calls made (a removed item's place is taken by the one moved into it), and every slot knows
// its item's dense position. Removing bumps the slot's generation, so the old handle goes
// stale; freed slots are reused last-freed first, and a slot whose generation would wrap is
// retired, never reused, so that a stale handle can never name a new item.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace REngine {

// A name in an RSlotMap: slot index and generation. Default-constructed: invalid. Tag keeps
// a body's handle and a joint's apart (RBodyHandle, RJointHandle).
template <class Tag>
struct RSlotHandle {
  static constexpr std::uint32_t kInvalidIndex = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t index = kInvalidIndex;
  std::uint32_t generation = 0;
  bool IsValid() const { return index != kInvalidIndex; }
  friend bool operator==(RSlotHandle a, RSlotHandle b) {
    return a.index == b.index && a.generation == b.generation;
  }
  friend bool operator!=(RSlotHandle a, RSlotHandle b) { return !(a == b); }
  // By slot, then generation.
  friend bool operator<(RSlotHandle a, RSlotHandle b) {
    return a.index < b.index || (a.index == b.index && a.generation < b.generation);
  }
};

// Dense items named by handles. The container that holds one (RBodies) decides what an item
// is and when it moves; the saved-state code reads and restores the vectors as they are.
template <class T, class Handle>
struct RSlotMap {
  static constexpr std::uint32_t kFree = std::numeric_limits<std::uint32_t>::max();

  std::vector<T> items;                  // dense
  std::vector<Handle> handles;           // dense position -> handle
  std::vector<std::uint32_t> generation;   // per slot: bumped when its item is removed
  std::vector<std::uint32_t> denseOfSlot;  // per slot: dense position (kFree: free)
  std::vector<std::uint32_t> free;         // free slots, reused last-freed first

  bool Contains(Handle h) const {
    return h.index < generation.size() && generation[h.index] == h.generation &&
           denseOfSlot[h.index] != kFree;
  }
  std::size_t Size() const { return items.size(); }

  // Appends the item at the end of the dense storage and names it.
  Handle Insert(T item) {
    Handle h;
    if (!free.empty()) {
      h.index = free.back();
      free.pop_back();
      h.generation = generation[h.index];
    } else {
      h.index = static_cast<std::uint32_t>(generation.size());
      generation.push_back(0);
      denseOfSlot.push_back(kFree);
    }
    denseOfSlot[h.index] = static_cast<std::uint32_t>(items.size());
    items.push_back(std::move(item));
    handles.push_back(h);
    return h;
  }
  // Exchanges two dense positions (their handles follow).
  void SwapDense(std::uint32_t i, std::uint32_t j) {
    if (i == j) return;
    std::swap(items[i], items[j]);
    std::swap(handles[i], handles[j]);
    denseOfSlot[handles[i].index] = i;
    denseOfSlot[handles[j].index] = j;
  }
  // Removes the last dense item: its handle goes stale, its slot is freed (or retired).
  void PopBack() {
    const Handle h = handles.back();
    items.pop_back();
    handles.pop_back();
    denseOfSlot[h.index] = kFree;
    if (++generation[h.index] != 0) free.push_back(h.index);
  }
  void Reserve(std::size_t n) {
    items.reserve(n), handles.reserve(n), generation.reserve(n), denseOfSlot.reserve(n);
  }
};

}  // namespace REngine
