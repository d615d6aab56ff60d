// The bounding-volume hierarchy of the broad phase (see RBoundsTree.h).
#include "pairs/RBoundsTree.h"

#include <algorithm>
#include <cmath>

namespace REngine {

void RBoundsTree::Build(const RBox* boxes, const std::uint32_t* ids, std::size_t count) {
  m_nodes.clear(), m_items.clear(), m_boxes.clear();
  if (count == 0) return;
  m_input = boxes, m_inputIds = ids;
  m_order.resize(count);
  m_centre.resize(3 * count);
  for (std::size_t k = 0; k < count; ++k) {
    m_order[k] = static_cast<std::uint32_t>(k);
    for (int a = 0; a < 3; ++a) {
      // An infinite box (a body whose reach overflowed) has no centre: put it at 0. Where an
      // item sits changes only how fast queries are, never what they find.
      const RScalar c = boxes[k].lo[a] + boxes[k].hi[a];
      m_centre[3 * k + a] = std::isfinite(c) ? c : 0;
    }
  }
  m_nodes.reserve(2 * (count / kLeafSize + 1));
  m_items.reserve(count), m_boxes.reserve(count);
  BuildNode(0, static_cast<std::uint32_t>(count));
  // RefitItems' maps.
  m_parent.assign(m_nodes.size(), kNoNode);
  m_leafOf.resize(m_items.size());
  std::uint32_t largestId = 0;
  for (std::uint32_t id : m_items) largestId = std::max(largestId, id);
  m_placeOf.assign(static_cast<std::size_t>(largestId) + 1, kNoNode);
  for (std::uint32_t k = 0; k < m_nodes.size(); ++k) {
    const RNode& node = m_nodes[k];
    if (node.count == 0) {
      m_parent[k + 1] = k, m_parent[node.first] = k;
      continue;
    }
    for (std::uint32_t place = node.first; place < node.first + node.count; ++place) {
      m_leafOf[place] = k, m_placeOf[m_items[place]] = place;
    }
  }
  m_dirtyMark.assign(m_nodes.size(), 0);
}

std::uint32_t RBoundsTree::BuildNode(std::uint32_t begin, std::uint32_t end) {
  const auto index = static_cast<std::uint32_t>(m_nodes.size());
  m_nodes.emplace_back();
  RBox bounds = m_input[m_order[begin]];
  for (std::uint32_t k = begin + 1; k < end; ++k) Merge(bounds, m_input[m_order[k]]);
  if (end - begin <= kLeafSize) {
    m_nodes[index] = RNode{bounds, static_cast<std::uint32_t>(m_items.size()), end - begin};
    for (std::uint32_t k = begin; k < end; ++k) {
      m_items.push_back(m_inputIds[m_order[k]]);
      m_boxes.push_back(m_input[m_order[k]]);
    }
    return index;
  }
  // Split at the median centre along the axis where the centres spread most.
  RScalar cLo[3], cHi[3];
  for (int a = 0; a < 3; ++a) cLo[a] = cHi[a] = m_centre[3 * m_order[begin] + a];
  for (std::uint32_t k = begin + 1; k < end; ++k) {
    for (int a = 0; a < 3; ++a) {
      const RScalar c = m_centre[3 * m_order[k] + a];
      cLo[a] = std::min(cLo[a], c), cHi[a] = std::max(cHi[a], c);
    }
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (cHi[a] - cLo[a] > cHi[axis] - cLo[axis]) axis = a;
  }
  const std::uint32_t mid = begin + (end - begin) / 2;
  const RScalar* centre = m_centre.data();
  std::nth_element(m_order.begin() + begin, m_order.begin() + mid, m_order.begin() + end,
                   [centre, axis](std::uint32_t x, std::uint32_t y) {
                     const RScalar cx = centre[3 * x + axis], cy = centre[3 * y + axis];
                     return cx < cy || (cx == cy && x < y);
                   });
  BuildNode(begin, mid);  // the left child is the next node
  const std::uint32_t right = BuildNode(mid, end);
  m_nodes[index] = RNode{bounds, right, 0};
  return index;
}

void RBoundsTree::PairSeeds(const RBoundsTree& other, std::size_t want,
                            std::vector<RNodePair>& seeds, std::vector<RNodePair>& scratch) const {
  seeds.clear();
  if (m_nodes.empty() || other.m_nodes.empty()) return;
  const bool self = &other == this;
  seeds.push_back({0, 0});
  // Breadth first, one level at a time, until there are enough starts or none can be split.
  auto push = [&scratch](RNodePair p) { scratch.push_back(p); };
  for (bool split = true; split && seeds.size() < want;) {
    split = false;
    scratch.clear();
    for (const RNodePair& p : seeds) {
      const RStep step = Split(other, self, p, push);
      if (step == RStep::kLeaves) scratch.push_back(p);
      split = split || step == RStep::kSplit;
    }
    std::swap(seeds, scratch);
  }
}

void RBoundsTree::FitNode(std::uint32_t index) {
  RNode& node = m_nodes[index];
  if (node.count > 0) {
    node.box = m_boxes[node.first];
    for (std::uint32_t k = 1; k < node.count; ++k) Merge(node.box, m_boxes[node.first + k]);
  } else {
    node.box = m_nodes[index + 1].box;
    Merge(node.box, m_nodes[node.first].box);
  }
}

void RBoundsTree::Refit(const RBox* byId) {
  for (std::size_t k = 0; k < m_items.size(); ++k) m_boxes[k] = byId[m_items[k]];
  // Depth-first order puts both children after their parent: back to front, every node
  // meets its children already refitted.
  for (std::size_t index = m_nodes.size(); index-- > 0;) FitNode(static_cast<std::uint32_t>(index));
}

void RBoundsTree::RefitItems(const RBox* byId, const std::uint32_t* ids, std::size_t count) {
  if (m_nodes.empty()) return;
  // The changed items' leaves and every node above them are marked, then refitted children
  // first by a walk from the root through the marked nodes alone. The other nodes' boxes
  // are what Refit would give them again: nothing below them changed.
  for (std::size_t k = 0; k < count; ++k) {
    // (An id the tree does not hold has no box in it to refit.)
    const std::uint32_t place = ids[k] < m_placeOf.size() ? m_placeOf[ids[k]] : kNoNode;
    if (place == kNoNode) continue;
    m_boxes[place] = byId[ids[k]];
    for (std::uint32_t node = m_leafOf[place]; node != kNoNode && !m_dirtyMark[node]; node = m_parent[node]) {
      m_dirtyMark[node] = 1;
    }
  }
  if (m_dirtyMark[0]) FitMarked(0);
}

void RBoundsTree::FitMarked(std::uint32_t index) {
  // A median-split tree is at most 30 levels deep: so is this recursion.
  const RNode& node = m_nodes[index];
  if (node.count == 0) {
    if (m_dirtyMark[index + 1]) FitMarked(index + 1);
    if (m_dirtyMark[node.first]) FitMarked(node.first);
  }
  FitNode(index);
  m_dirtyMark[index] = 0;
}

void RBoundsTree::Query(const RBox& box, std::vector<std::uint32_t>& out,
                        std::vector<std::uint32_t>& stack) const {
  if (m_nodes.empty() || !Overlap(m_nodes[0].box, box)) return;
  // Every node on the stack overlaps the box: a child is tested before it is pushed, so
  // the nodes that miss cost a test and no round trip through the stack.
  stack.clear();
  std::uint32_t index = 0;
  for (;;) {
    const RNode& node = m_nodes[index];
    if (node.count > 0) {
      for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
        if (Overlap(m_boxes[k], box)) out.push_back(m_items[k]);
      }
    } else {
      const std::uint32_t left = index + 1, right = node.first;
      const bool inLeft = Overlap(m_nodes[left].box, box), inRight = Overlap(m_nodes[right].box, box);
      if (inLeft) {
        if (inRight) stack.push_back(right);  // after the left subtree, as before
        index = left;
        continue;
      }
      if (inRight) {
        index = right;
        continue;
      }
    }
    if (stack.empty()) return;
    index = stack.back();
    stack.pop_back();
  }
}

RScalar RBoundsTree::InnerArea() const {
  RScalar area = 0;
  for (const RNode& node : m_nodes) {
    if (node.count > 0) continue;
    const RScalar x = node.box.hi[0] - node.box.lo[0], y = node.box.hi[1] - node.box.lo[1],
                  z = node.box.hi[2] - node.box.lo[2];
    area += 2 * (x * y + y * z + z * x);
  }
  return area;
}

}  // namespace REngine
