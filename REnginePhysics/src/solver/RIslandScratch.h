// Private to REnginePhysics: one task's scratch for the islands it solves (RIslandScratch),
// shared by the contact solver's direct solve of an island's rows (RIslandSolver.cpp) and
// the joint solver's blocks, end rows, impacts and geometric stiffness (joints/). The
// contact solver owns one per task (solver/RContactSolver.h) and hands it to each island it
// solves, the joint solver's functions included: islands are solved side by side, each on
// its task's scratch. Plain fields: each island's functions fill what they read, but for
// the marks and the stiffness, kept at kNone and 0 between uses. Every vector keeps its
// capacity from island to island and from step to step.
#pragma once

#include <REngineMath/RMath.h>

#include "joints/RJointSparse.h"
#include "joints/RJointTypes.h"
#include "world/RUnionFind.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace REngine {

struct RIslandScratch {
  // The island's bodies' velocities before its warm start (m/s, rad/s, world), put back
  // when the warm start would raise their kinetic energy.
  std::vector<RVec3> warmV, warmW;
  // One island's direct solve: its rows and the dense scratch (RContactSolver::kDirectRows^2
  // at most).
  std::vector<std::uint32_t> index;  // the island's rows
  std::vector<RScalar> K, L, b, x, invDiag, residual;
  std::vector<int> map, envelope, lo, hi, columnsFrom, columnsTo;
  std::vector<std::pair<int, int>> runs;  // the island's manifolds: [first, last)
  std::vector<char> active;
  std::vector<char> dropped;  // taken out of the active set for pulling, in this solve
  bool kReady = false;
  // The island's friction patch groups' normal blocks: each group's minimum-norm inverse, at
  // RBlock::groupSlot times kGroupRows^2 (RPatchGroups.cpp).
  std::vector<RScalar> groupPinv;
  // The island's joints (RJoints.cpp): their equality rows (indices into the rows), the
  // group of them solved as one block ([first, last) of eq), its skyline factor, the end
  // of the step's rows and bodies.
  std::vector<std::uint32_t> eq, eqFirst, eqOffset;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> eqGroups;
  std::vector<char> eqGroupOk;  // factored (else its rows are solved one at a time)
  // Past RJointSolver's kJointBlockRows rows the one group is solved as a sparse system
  // (RJointSparse.h): its explicit bodies (the island's movable bodies without locks), and
  // the (body, row) links of the others, whose rows couple directly.
  bool eqSparse = false;
  joints::RJointSparseSlot sparse;
  std::vector<std::uint32_t> sparseBodies;
  std::vector<std::uint64_t> sparseLinks;
  // Whether the sparse block's rows are a forest of joints (equality rows only, no loop
  // through bodies or the immovable ones): then they have no self-stress to take out.
  bool eqForest = false;
  RUnionFind sparseSets;
  std::vector<char> jointActive;  // per row: in the block (equality, pushing limit, motor within its force)
  bool blockStale = true;         // the block's factor is not the active set's
  std::vector<RScalar> eqL, eqInvDiag, eqRhs, eqNull, eqRidge;  // (eqRidge: per group)
  std::vector<std::uint32_t> jointBodies;  // the island's movable joint bodies
  // Per solver body (mark) and per end body (endMark): scratch, kNone between uses.
  std::vector<std::uint32_t> mark, endMark;
  std::vector<RJointRow> endRows;
  std::vector<RJointRow> impactRows;  // the joints' rows in the impact phase
  std::vector<std::uint32_t> endContacts;  // the contact rows solved with the joints at the end
  std::vector<std::uint32_t> endPatches;   // their manifolds (blocks) whose friction is solved with them
  // Per row: its error at the start of the step, and as predicted at the end.
  std::vector<RScalar> startC, jointC;
  std::vector<RJointEndBody> endBodies;
  // The joints' geometric stiffness (RJointStiffness.cpp): per solver body, the rotational
  // inertia added while an unresolved island is solved (kg m^2, 0 else); per joint body,
  // its inverse inertia and spin kept meanwhile.
  std::vector<RScalar> stiffness;
  bool stiffened = false;
  std::vector<RMat3> keptInvI;
  std::vector<RVec3> keptW;
  // The rounds of an island whose joint body turns fast (RJointTurning.cpp): the block rows
  // (indices into the island's joint rows) and each row's place among them (kNone: not one),
  // the derivatives of their end errors with respect to their bodies' velocities (4 a row:
  // a linear, angular; b linear, angular), the errors' response to their impulses (row-major)
  // and the impulses that take the errors out.
  std::vector<std::uint32_t> turnRows, turnPlace;
  std::vector<RVec3> turnD;
  std::vector<RScalar> turnG, turnY;
  // Whether the island has a motor whose turn the rounds hold (RJointMotors.cpp).
  bool jointMotors = false;
};

}  // namespace REngine
