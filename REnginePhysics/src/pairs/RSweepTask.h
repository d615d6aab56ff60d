// Private to REnginePhysics: the pair sweep's per-task scratch and outputs (RSweepTask) and
// an entry of its manifold memory (RManifoldMemory), the types the pair sweep (RPairSweep)
// and the broad phase (RBroadPhase, which works in the tasks' scratch) share. The pair sweep
// owns the tasks and the memory; a task keeps its vectors' capacity between steps.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RIntegrator.h>

#include "pairs/RBoundsTree.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace REngine {

// Manifold memory (RShortcuts::contactReuse): each contact's manifold in its A frame with
// the relative pose it was computed at, in the sweep's (i, then j) order, kept for the
// next step's sweep. The margins between keptMax and droppedMin keep the same points.
struct RManifoldMemory {
  std::uint32_t i = 0, j = 0;      // dense indices, the sweep's order
  RBodyHandle handleA, handleB;    // identity (A: the lower slot)
  std::uint64_t serialA = 0, serialB = 0;  // and which bodies (RRigidBody::Serial)
  RRelativePose X;                 // B's pose in A's frame when it was computed
  RContactManifold manifold_A;     // in A's frame
  RScalar keptMax = 0, droppedMin = 0;  // m
  // The contact solver's block matrix and its minimum-norm inverse, when computed for
  // this manifold (BlockInverse): kept while the matrix stays within 1e-12 of it.
  bool hasInverse = false;
  Eigen::Matrix<RScalar, 4, 4> K = Eigen::Matrix<RScalar, 4, 4>::Zero(), pinv = Eigen::Matrix<RScalar, 4, 4>::Zero();
};

// The pair sweep's work, cut into tasks (see RPairSweep::DetectPairs): each task's scratch
// and outputs, kept between steps so that no step allocates.
struct RSweepTask {
  std::vector<RScalar> near;               // one body's candidates, lim^2 - d^2 (m^2)
  std::vector<std::uint32_t> candidates;   // those with lim^2 - d^2 >= 0
  std::vector<RBoundsTree::RNodePair> nodeStack;  // the tree's pair search
  std::vector<std::uint32_t> query, queryStack;   // the tree's queries
  std::vector<std::uint32_t> moved;               // the broad phase: bodies that left their fat boxes
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // stage 1: spheres touch (i < j)
  std::vector<RContact> contacts;          // stage 2: contacts, in pair order
  std::size_t contactsAt = 0;              // where they go in the step's contacts (and contact memory)
  std::size_t manifoldsAt = 0;             // where its manifolds go in the manifold memory
  // Its entries written over last step's in place: inPlace of them from manifoldsFrom on
  // (the rest in manifolds).
  std::size_t manifoldsFrom = 0, inPlace = 0;
  std::vector<std::uint32_t> wake;         // stage 2: sleeping islands touched
  std::vector<RManifoldMemory> manifolds;  // stage 2: this step's manifold memory
  std::vector<std::uint32_t> contactMemory;  // stage 2: per contact, its entry in manifolds
  // Stage 2: its contacts between a moving body and an immovable one, both responding
  // (indices in contacts), which the covered-feature rule reads.
  std::vector<std::uint32_t> immovable;
  std::uint64_t sphereTests = 0, rejectedFilter = 0, rejectedBoxes = 0, narrowPhase = 0, reused = 0;
};

}  // namespace REngine
