// Private to REnginePhysics: a bounding-volume hierarchy over axis-aligned boxes, the broad
// phase's structure (and, later, the queries'). Built top-down in O(n log n): each node's
// items are split at the median of their box centres along the longest axis, ties broken by
// item id, so the same boxes always give the same tree. Leaves hold up to kLeafSize items;
// nodes and item boxes sit in contiguous arrays in depth-first order.
#pragma once

#include <REngineMath/RMath.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace REngine {

class RBoundsTree {
 public:
  // An axis-aligned box, world, m.
  struct RBox {
    RScalar lo[3];
    RScalar hi[3];
  };

  // Whether two boxes overlap (closed intervals). All six comparisons, no short cut: a
  // search's tests go either way unpredictably, and one branch mispredicted costs more than
  // the six compares.
  static bool Overlap(const RBox& a, const RBox& b) {
    return (a.lo[0] <= b.hi[0]) & (b.lo[0] <= a.hi[0]) & (a.lo[1] <= b.hi[1]) & (b.lo[1] <= a.hi[1]) &
           (a.lo[2] <= b.hi[2]) & (b.lo[2] <= a.hi[2]);
  }

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
  // The same for a few items whose boxes changed, ids[0 .. count), every other item's box
  // as it was: only their leaves and the nodes above them are refitted, in the order Refit
  // takes them, so the tree is Refit's to the bit. O(count log n).
  void RefitItems(const RBox* byId, const std::uint32_t* ids, std::size_t count);

  // Appends to `out` the id of every item whose box overlaps `box` (closed intervals), in
  // the tree's order; `stack` is the caller's traversal scratch (queries from several
  // threads at once). For queries (rays, overlaps) between steps.
  void Query(const RBox& box, std::vector<std::uint32_t>& out, std::vector<std::uint32_t>& stack) const;

  // A segment through the tree, for ray and shape casts: the points origin + t dir with t in
  // [0, tMax], each node's and item's box grown by grow[a] on both sides along axis a (a
  // swept box's half extents; zero for a ray). Calls visit(id, tMax) for every item whose
  // grown box the segment meets, nearer nodes first; visit returns the new tMax, so a search
  // for the nearest hit shrinks it and skips every node that starts beyond it (a node entered
  // exactly at tMax is still visited: ties are the caller's to break). dir need not be unit
  // and may have zero components. The slab test is conservative only up to rounding: callers
  // pad item boxes by more than the rounding of their coordinates (RQueries does). No
  // scratch: the traversal stack is a fixed array (the tree is at most 30 levels deep).
  template <class Visit>
  void Ray(const RScalar origin[3], const RScalar dir[3], RScalar tMax, const RScalar grow[3],
           const Visit& visit) const;
  // Sum of the inner nodes' box surface areas, m^2: the expected cost of a query through the
  // tree, up to a factor. A refitted tree whose cost has grown well beyond its cost when
  // built is worth building again.
  RScalar InnerArea() const;

 private:
  static constexpr std::uint32_t kLeafSize = 4;
  struct RNode {
    RBox box;
    std::uint32_t first;  // leaf: first item; inner: index of the right child (left: next)
    std::uint32_t count;  // leaf: items (> 0); inner: 0
  };
  static void Merge(RBox& box, const RBox& other) {
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = std::min(box.lo[a], other.lo[a]);
      box.hi[a] = std::max(box.hi[a], other.hi[a]);
    }
  }
  std::uint32_t BuildNode(std::uint32_t begin, std::uint32_t end);
  // A node's box from its items' (a leaf) or its children's boxes (an inner node).
  void FitNode(std::uint32_t index);
  // RefitItems' walk: the marked nodes below and at `index` (marked), children first.
  void FitMarked(std::uint32_t index);
  struct RRayEntry {  // Ray's stack: a node and where the segment enters its box
    std::uint32_t node;
    RScalar tEnter;
  };
  // One step of the pair search from node pair p (see Pairs): kApart when the nodes' boxes
  // are apart, kLeaves when the pair is to be searched item by item (two leaves, or, with
  // self, one leaf with itself), kSplit after handing its children to push: the inner node
  // is descended, the larger when both are; within one subtree (a == b, self), its two
  // children each with itself and with each other.
  enum class RStep { kApart, kLeaves, kSplit };
  template <class Push>
  RStep Split(const RBoundsTree& other, bool self, RNodePair p, const Push& push) const {
    const RNode& x = m_nodes[p.a];
    if (self && p.a == p.b) {
      if (x.count > 0) return RStep::kLeaves;
      push(RNodePair{p.a + 1, x.first}), push(RNodePair{x.first, x.first});
      push(RNodePair{p.a + 1, p.a + 1});
      return RStep::kSplit;
    }
    const RNode& y = other.m_nodes[p.b];
    if (!Overlap(x.box, y.box)) return RStep::kApart;
    if (x.count > 0 && y.count > 0) return RStep::kLeaves;
    RScalar sx = 0, sy = 0;
    for (int k = 0; k < 3; ++k) sx += x.box.hi[k] - x.box.lo[k], sy += y.box.hi[k] - y.box.lo[k];
    if (y.count > 0 || (x.count == 0 && !(sx < sy))) {
      push(RNodePair{x.first, p.b}), push(RNodePair{p.a + 1, p.b});
    } else {
      push(RNodePair{p.a, y.first}), push(RNodePair{p.a, p.b + 1});
    }
    return RStep::kSplit;
  }

  std::vector<RNode> m_nodes;
  std::vector<std::uint32_t> m_items;  // ids, in leaf order
  std::vector<RBox> m_boxes;           // the items' boxes, in leaf order
  // For RefitItems: each node's parent (the root's: kNoNode), each item's leaf (in leaf
  // order), each id's place in leaf order (kNoNode for ids not in the tree); and its scratch.
  static constexpr std::uint32_t kNoNode = 0xffffffffu;
  std::vector<std::uint32_t> m_parent, m_leafOf, m_placeOf;
  std::vector<char> m_dirtyMark;
  // Build scratch: item order and box centres (twice: sums of lo and hi).
  std::vector<std::uint32_t> m_order;
  std::vector<RScalar> m_centre;
  const RBox* m_input = nullptr;
  const std::uint32_t* m_inputIds = nullptr;
};

template <class Visit>
void RBoundsTree::Ray(const RScalar origin[3], const RScalar dir[3], RScalar tMax,
                      const RScalar grow[3], const Visit& visit) const {
  if (m_nodes.empty() || !(tMax >= 0)) return;
  // The slab test without branches (Williams et al. 2005, with Barnes' NaN rule): per axis
  // 1/dir, infinite for a zero component; the near side of each slab is chosen by its sign,
  // and the grown box's sides are folded into the origin. A zero component whose origin lies
  // outside the slab gives +inf as its entry (a miss); one exactly on a side gives 0 * inf =
  // NaN, which max/min written as below ignore (the side counts as inside). Rounding is
  // monotone, so a node's interval always holds each of its items' intervals.
  RScalar inv[3], oNear[3], oFar[3];
  int nearSide[3], farSide[3];
  for (int a = 0; a < 3; ++a) {
    // 1/dir as IEEE division gives it, the infinity of a zero written out (the sanitizers
    // treat a division by zero as an error).
    inv[a] = dir[a] != 0 ? 1 / dir[a] : std::copysign(std::numeric_limits<RScalar>::infinity(), dir[a]);
    const bool neg = std::signbit(inv[a]);
    nearSide[a] = neg ? 3 + a : a, farSide[a] = neg ? a : 3 + a;
    oNear[a] = neg ? origin[a] - grow[a] : origin[a] + grow[a];
    oFar[a] = neg ? origin[a] + grow[a] : origin[a] - grow[a];
  }
  auto clip = [&](const RBox& b, RScalar limit, RScalar& enter) {
    const RScalar* side = &b.lo[0];  // lo[0..2] then hi[0..2]
    RScalar t0 = 0, t1 = limit;
    for (int a = 0; a < 3; ++a) {
      const RScalar tn = (side[nearSide[a]] - oNear[a]) * inv[a];
      const RScalar tf = (side[farSide[a]] - oFar[a]) * inv[a];
      t0 = tn > t0 ? tn : t0;  // NaN: keeps t0
      t1 = tf < t1 ? tf : t1;  // NaN: keeps t1
    }
    enter = t0;
    return t0 <= t1;
  };
  // Depth-first, the nearer child first; a median-split tree over fewer than 2^31 items is
  // at most 30 levels deep, and the stack holds at most one entry per level and one more.
  RRayEntry stack[64];
  int top = 0;
  RScalar enter = 0;
  if (!clip(m_nodes[0].box, tMax, enter)) return;
  stack[top++] = {0, enter};
  while (top > 0) {
    const RRayEntry e = stack[--top];
    if (e.tEnter > tMax) continue;  // a nearer hit was found after this node was pushed
    const RNode& node = m_nodes[e.node];
    if (node.count > 0) {
      for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
        if (clip(m_boxes[k], tMax, enter)) tMax = visit(m_items[k], tMax);
      }
      continue;
    }
    const std::uint32_t left = e.node + 1, right = node.first;
    RScalar tl = 0, tr = 0;
    const bool hl = clip(m_nodes[left].box, tMax, tl), hr = clip(m_nodes[right].box, tMax, tr);
    if (hl && hr) {
      if (tl <= tr) {
        stack[top++] = {right, tr}, stack[top++] = {left, tl};
      } else {
        stack[top++] = {left, tl}, stack[top++] = {right, tr};
      }
    } else if (hl) {
      stack[top++] = {left, tl};
    } else if (hr) {
      stack[top++] = {right, tr};
    }
  }
}

template <class Found>
void RBoundsTree::Pairs(const RBoundsTree& other, RNodePair start, std::vector<RNodePair>& stack,
                        const Found& found) const {
  if (m_nodes.empty() || other.m_nodes.empty()) return;
  const bool self = &other == this;
  stack.clear();
  stack.push_back(start);
  auto push = [&stack](RNodePair p) { stack.push_back(p); };
  while (!stack.empty()) {
    const RNodePair p = stack.back();
    stack.pop_back();
    if (Split(other, self, p, push) != RStep::kLeaves) continue;
    const RNode& x = m_nodes[p.a];
    if (self && p.a == p.b) {
      for (std::uint32_t k = x.first; k < x.first + x.count; ++k) {
        for (std::uint32_t l = k + 1; l < x.first + x.count; ++l) {
          if (Overlap(m_boxes[k], m_boxes[l])) found(m_items[k], m_items[l]);
        }
      }
      continue;
    }
    const RNode& y = other.m_nodes[p.b];
    for (std::uint32_t k = x.first; k < x.first + x.count; ++k) {
      if (!Overlap(m_boxes[k], y.box)) continue;
      for (std::uint32_t l = y.first; l < y.first + y.count; ++l) {
        if (Overlap(m_boxes[k], other.m_boxes[l])) found(m_items[k], other.m_items[l]);
      }
    }
  }
}

}  // namespace REngine
