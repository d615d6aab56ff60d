// Private to REnginePhysics: a large joint island's equality rows solved exactly as one
// sparse system (RJointSystem.h's FactorBlocks and JointPass, past kJointBlockRows rows).
//
// Why not the rows' own matrix J M^-1 J^T, as the skyline block does for smaller islands: a
// body in many joints (the hub of a star, a ship's frame carrying a hundred parts) couples
// every pair of its rows, so that matrix is dense however sparse the joints are, and its
// factor costs O(m^3). Kept as unknowns of their own, the bodies' velocity changes y turn it
// into the saddle-point system
//
//     [ -M   J^T ] [ y ]   [  0  ]
//     [  J   R   ] [ x ]   [ rhs ]      (R: the ridge, and couplings through locked bodies)
//
// whose matrix has a nonzero per row and body touched: linear in the joints for a star, a
// chain or a mesh. With -M negative and R positive definite it is quasi-definite, so an
// LDL^T factor exists for every symmetric ordering (Vanderbei 1995), and the ordering can be
// chosen for sparsity alone: Eigen's approximate minimum degree. The factor is Eigen's
// simplicial LDL^T (a well-kept implementation, not a hand-written one); the ordering and
// the symbolic factor are kept while the entries' pattern stays the same, as it does from
// step to step, so a step refactors numbers only.
#pragma once

#include <REngineMath/RMath.h>

#include <memory>
#include <vector>

namespace REngine::joints {

class RJointSparse {
 public:
  RJointSparse();
  ~RJointSparse();
  RJointSparse(const RJointSparse&) = delete;
  RJointSparse& operator=(const RJointSparse&) = delete;

  // A new system of `size` unknowns; Add gives its entries (either triangle, duplicates
  // summed), always in the same order for the same structure.
  void Begin(int size);
  void Add(int row, int column, RScalar value) {
    m_r.push_back(row), m_c.push_back(column), m_v.push_back(value);
  }
  // Factors the system; false when it could not (a zero pivot, non-finite entries).
  bool Factor();
  // Solves for the unknowns 0 .. n with right-hand side rhs there (0 for the rest): rhs is
  // overwritten with the answer.
  void Solve(RScalar* rhs, int n);

 private:
  struct RImpl;
  std::unique_ptr<RImpl> m_impl;
  int m_size = 0;
  std::vector<int> m_r, m_c;
  std::vector<RScalar> m_v;
};

// Scratch that holds an RJointSparse made on first use; copies start empty (a copy of the
// world's scratch needs none of its contents).
class RJointSparseSlot {
 public:
  RJointSparseSlot() = default;
  RJointSparseSlot(const RJointSparseSlot&) {}
  RJointSparseSlot& operator=(const RJointSparseSlot&) { return *this; }
  RJointSparseSlot(RJointSparseSlot&&) noexcept = default;
  RJointSparseSlot& operator=(RJointSparseSlot&&) noexcept = default;
  RJointSparse& Get() {
    if (!m_p) m_p = std::make_unique<RJointSparse>();
    return *m_p;
  }

 private:
  std::unique_ptr<RJointSparse> m_p;
};

}  // namespace REngine::joints
