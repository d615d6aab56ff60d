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
  // A pair of nodes, one of each tree (or of this tree twice: a == b stands for the pairs
  // within that subtree), from which a pair search starts.
  struct RNodePair {
    std::uint32_t a, b;
  };
  // Splits the search for overlapping pairs between this tree and `other` (other == this:
  // the pairs of distinct items of this tree, each once) into about `want` independent
  // starts, dropping node pairs whose boxes are apart. Their searches together find each
  // pair exactly once.
  void PairSeeds(const RBoundsTree& other, std::size_t want, std::vector<RNodePair>& seeds,
                 std::vector<RNodePair>& scratch) const;
  // Calls found(x, y) for every pair of items whose boxes overlap below `start` (x of this
  // tree, y of `other`), in the search's order.
  template <class Found>
  void Pairs(const RBoundsTree& other, RNodePair start, std::vector<RNodePair>& stack,
             const Found& found) const;
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
  // Which of a node pair's nodes to descend: the inner one, the larger when both are.
  static bool SplitFirst(const RNode& a, const RNode& b) {
    if (b.count > 0) return true;
    if (a.count > 0) return false;
    RScalar sa = 0, sb = 0;
    for (int k = 0; k < 3; ++k) sa += a.box.hi[k] - a.box.lo[k], sb += b.box.hi[k] - b.box.lo[k];
    return !(sa < sb);
  }

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

template <class Found>
void RBoundsTree::Pairs(const RBoundsTree& other, RNodePair start, std::vector<RNodePair>& stack,
                        const Found& found) const {
  if (m_nodes.empty() || other.m_nodes.empty()) return;
  const bool self = &other == this;
  stack.clear();
  stack.push_back(start);
  while (!stack.empty()) {
    const RNodePair p = stack.back();
    stack.pop_back();
    const RNode& x = m_nodes[p.a];
    if (self && p.a == p.b) {
      if (x.count > 0) {
        for (std::uint32_t k = x.first; k < x.first + x.count; ++k) {
          for (std::uint32_t l = k + 1; l < x.first + x.count; ++l) {
            if (Overlap(m_boxes[k], m_boxes[l])) found(m_items[k], m_items[l]);
          }
        }
      } else {
        stack.push_back({p.a + 1, x.first});
        stack.push_back({x.first, x.first});
        stack.push_back({p.a + 1, p.a + 1});
      }
      continue;
    }
    const RNode& y = other.m_nodes[p.b];
    if (!Overlap(x.box, y.box)) continue;
    if (x.count > 0 && y.count > 0) {
      for (std::uint32_t k = x.first; k < x.first + x.count; ++k) {
        if (!Overlap(m_boxes[k], y.box)) continue;
        for (std::uint32_t l = y.first; l < y.first + y.count; ++l) {
          if (Overlap(m_boxes[k], other.m_boxes[l])) found(m_items[k], other.m_items[l]);
        }
      }
    } else if (SplitFirst(x, y)) {
      stack.push_back({x.first, p.b});
      stack.push_back({p.a + 1, p.b});
    } else {
      stack.push_back({p.a, y.first});
      stack.push_back({p.a, p.b + 1});
    }
  }
}

}  // namespace REngine
