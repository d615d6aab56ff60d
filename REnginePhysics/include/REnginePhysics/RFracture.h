// Fracture: a body broken into convex pieces, each a new body, conserving what physics
// conserves.
//
//   RFractureDef cut;
//   cut.sites_S = {{-0.3, 0, 0}, {0.2, 0.1, 0}, {0, -0.2, 0.3}};  // in the body's shape frame
//   std::vector<RBodyHandle> pieces = Fracture(bodies, rock, cut);  // `rock` is gone
//
// The pieces. Each site's Voronoi cell within the shape: the points of the shape nearer to
// that site than to any other (the shape's faces and the bisecting planes of the sites, their
// corners found plane by plane, exact to rounding), made a hull (its own prepared shape).
// Cells that hold no solid (a site whose cell is cut away to a sliver) give no piece. The
// cells tile the shape: their volumes sum to its volume, and at the parent's density their
// masses to its mass, to rounding.
//
// Conservation. Every piece starts with the parent's rigid velocity field: its centre of mass
// moving at v + w x r (r from the parent's centre to its own), turning at the same w. Momentum,
// angular momentum and kinetic energy are then the parent's to rounding (the pieces' inertias
// about the parent's centre sum to the parent's: the parallel axis theorem).
//
// What each piece keeps of the parent: kind, material (restitution, friction), responds,
// filter bits, drag, gravity scale, locks and user data; its name is the parent's with "#i"
// (i the site's index). The parent is removed (RBodies::Remove: its joints go, its contacts end
// with events at the next step).
//
// Shapes: boxes and hulls (a compound or round shape is refused: a polyhedral cut of a sphere
// would not keep its mass). Sites are in the parent's shape frame S, m, inside the shape,
// finite, no two closer than 1e-6 of the shape's size.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RConvexPolyhedron.h>
#include <REnginePhysics/RError.h>

#include <vector>

namespace REngine {

// A fracture that cannot be made: which field ("sites[3]", "shape", "body") and why. The
// bodies are left as they were.
class RFractureError : public RError {
 public:
  using RError::RError;
};

struct RFractureDef {
  std::vector<RVec3> sites_S;  // one piece per site (at most kMaxSites)
  static constexpr std::size_t kMaxSites = 256;
};

// Breaks `body` (a box or hull) into the Voronoi cells of the sites. Returns the pieces'
// handles in site order (sites whose cell is empty have none). Throws RHandleError for a
// stale handle and RFractureError for a definition it refuses.
std::vector<RBodyHandle> Fracture(RBodies& bodies, RBodyHandle body, const RFractureDef& def);

// The corners of each site's cell within a convex polyhedron given by its vertices (the
// geometry of Fracture, in one frame): per site, its cell's corners (empty: no solid cell).
std::vector<std::vector<RVec3>> VoronoiCells(const std::vector<RVec3>& vertices, const std::vector<RPlane>& faces,
                                             const std::vector<RVec3>& sites);

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_FRACTURE(X) \
  X(RFractureDef)
RENGINE_ABI_CHECK(kFracture, RENGINE_ABI_TYPES_FRACTURE)
