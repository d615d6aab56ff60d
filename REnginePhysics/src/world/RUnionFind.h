// Private to REnginePhysics: union-find over body indices, shared by the island solver
// (islands of rows solved directly) and sleeping (islands that sleep together).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace REngine {

// Disjoint sets of 0 .. n-1 with path halving. The smaller index is always the root, so the
// grouping and each set's representative do not depend on the order of the unions: islands
// come out the same however the contacts were ordered. Reset keeps the capacity (no
// allocation once the world's size is reached).
class RUnionFind {
 public:
  void Reset(std::size_t n) {
    m_parent.resize(n);
    for (std::size_t i = 0; i < n; ++i) m_parent[i] = static_cast<std::uint32_t>(i);
  }
  std::uint32_t Find(std::uint32_t i) {
    while (m_parent[i] != i) i = m_parent[i] = m_parent[m_parent[i]];
    return i;
  }
  void Union(std::uint32_t a, std::uint32_t b) {
    const std::uint32_t x = Find(a), y = Find(b);
    if (x != y) m_parent[std::max(x, y)] = std::min(x, y);
  }

 private:
  std::vector<std::uint32_t> m_parent;
};

}  // namespace REngine
