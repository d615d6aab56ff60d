// Private to REnginePhysics: a bounding-volume hierarchy over axis-aligned boxes, the broad
// phase's structure (and, later, the queries'). Built top-down in O(n log n): each node's
// items are split at the median of their box centres along the longest axis, ties broken by
// item id, so the same boxes always give the same tree. Leaves hold up to kLeafSize items;
// nodes and item boxes sit in contiguous arrays in depth-first order.
#pragma once

#include <REngineMath/RMath.h>

#include <cstdint>
#include <vector>

namespace REngine {

class RBoundsTree {
 public:
  // An axis-aligned box, world, m.
  struct RBox {
    RScalar lo[3];
    RScalar hi[3];
  };

  // Builds the tree over `count` boxes; item k has id ids[k] (what queries report). Keeps
  // the arrays' capacity between builds.
  void Build(const RBox* boxes, const std::uint32_t* ids, std::size_t count);
  // New boxes for the same items, the tree's shape kept: byId[id] is item id's box. O(n).
  void Refit(const RBox* byId);
  void Clear() { m_nodes.clear(), m_items.clear(), m_boxes.clear(); }
  std::size_t Size() const { return m_items.size(); }

  // Appends to `out` the id of every item whose box overlaps `box` (closed intervals) and
  // whose id is above `after` (the pair sweep asks body i for its partners j > i: a subtree
  // whose largest id is not above it is skipped whole), in the tree's order.
  void Query(const RBox& box, std::vector<std::uint32_t>& out, std::int64_t after = -1) const {
    Query(box, out, m_stack, after);
  }
  // The same with the caller's traversal stack: queries from several threads at once.
  void Query(const RBox& box, std::vector<std::uint32_t>& out, std::vector<std::uint32_t>& stack,
             std::int64_t after = -1) const;

 private:
  static constexpr std::uint32_t kLeafSize = 4;
  struct RNode {
    RBox box;
    std::uint32_t first;  // leaf: first item; inner: index of the right child (left: next)
    std::uint32_t count;  // leaf: items (> 0); inner: 0
    std::uint32_t maxId;  // the largest id below it
  };
  static bool Overlap(const RBox& a, const RBox& b) {
    return a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1] &&
           a.lo[2] <= b.hi[2] && b.lo[2] <= a.hi[2];
  }
  std::uint32_t BuildNode(std::uint32_t begin, std::uint32_t end);

  std::vector<RNode> m_nodes;
  std::vector<std::uint32_t> m_items;  // ids, in leaf order
  std::vector<RBox> m_boxes;           // the items' boxes, in leaf order
  // Build scratch: item order and box centres (twice: sums of lo and hi).
  std::vector<std::uint32_t> m_order;
  std::vector<RScalar> m_centre;
  const RBox* m_input = nullptr;
  const std::uint32_t* m_inputIds = nullptr;
  mutable std::vector<std::uint32_t> m_stack;
};

}  // namespace REngine
