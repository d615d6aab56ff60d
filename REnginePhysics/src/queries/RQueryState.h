// Private to REnginePhysics: what an RQueries keeps between queries (RQueries.h). Each
// enabled body's query form (pose as a matrix, shape, handle, category: what the narrow
// phase of a query reads, packed so that a query touches no RRigidBody until it has a hit
// for the game's callback), the world boxes, the tree over them, and scratch.
#pragma once

#include <REnginePhysics/RQueries.h>

#include "pairs/RBoundsTree.h"

#include <cstdint>
#include <vector>

namespace REngine {

struct RQueryProxy {
  RMat3 R_WB = RMat3::Identity();  // body frame -> world
  RVec3 x_W = RVec3::Zero();       // centre of mass, world, m
  RConvexShape shape;              // body frame
  RBodyHandle handle;
  std::uint32_t category = 0;
  std::uint64_t serial = 0;  // the body's RRigidBody::Serial when `shape` was taken
};

// A box about a body's centre of mass that holds its shape, body frame, m.
struct RLocalBox {
  RVec3 center_B = RVec3::Zero();
  RVec3 half_B = RVec3::Zero();
};

struct RQueryState {
  // The stamps the proxies were made at (RBodies::LayoutStamp, PoseStamp, BodyEditCount):
  // NextCacheStamp never returns 0, so a new state matches no container.
  std::uint64_t layout = 0, pose = 0, edits = 0;
  bool fresh = true;
  // The same for the tree (which is only built when a query wants it).
  std::uint64_t treeLayout = 0, treePose = 0, treeEdits = 0;
  std::vector<RQueryProxy> proxies;  // the enabled bodies, in dense order
  std::vector<RLocalBox> local;      // per proxy
  std::vector<RBoundsTree::RBox> boxes;  // per proxy: world, padded (see WorldBox)
  std::vector<std::uint32_t> ids;        // 0 .. n - 1: tree items are dense indices
  RBoundsTree tree;
  RScalar builtArea = 0;  // the tree's InnerArea when last built
  std::uint64_t builds = 0, refits = 0;

  // Scratch, kept for its capacity.
  std::vector<std::uint32_t> candidates, stack;
  // OverlapBox's box, kept while its half extents stay the same.
  RVec3 boxHalf = RVec3::Constant(-1);
  RConvexPolyhedron boxPolyhedron;

  // Brings the proxies (and, with useTree, the tree) to the bodies' present state.
  void Sync(const RBodies& bodies, bool useTree);
};

// The local box of a shape: its polyhedron's vertex bounds, or a sphere's cube.
RLocalBox LocalBoxOf(const RConvexShape& shape);
// A prepared shape as the narrow phase sees it, in its body frame B (a query's cast shape, a
// character's).
RConvexShape ConvexShapeOf(const RPreparedShape& prepared);
// The world box of a shape at (R_WB, x_W): the local box turned (|R| times the half
// extents) and cut by the bounding sphere, then padded by 2e-9 of the bounding radius and
// 1e-14 of the largest coordinate. The padding is what lets the tree skip a body only when
// every answer about it would be "no": it is beyond the rounding of the box and of the
// tree's slab tests at those coordinates, and beyond the touching band within which the
// narrow phase calls shapes touching (1e-9 of the two radii summed), so a shape cast or
// overlap that reports a touch always finds both boxes overlapping.
RBoundsTree::RBox WorldBox(const RLocalBox& local, RScalar boundingRadius, const RMat3& R_WB,
                           const RVec3& x_W);

}  // namespace REngine
