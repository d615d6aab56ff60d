// Queries between steps: ray casts, shape casts and overlap tests against the bodies of an
// RBodies, answered in handles.
//
//   RQueries queries;                                   // one per thread that asks
//   integrator.Update(bodies, dt);
//   if (auto hit = queries.CastRay(bodies, {gun_W, aim_W, 2000.0})) Damage(hit->body);
//
// Where it lives. An object of its own beside RBodies and RIntegrator, not a method of
// either: a query needs state that neither should carry, a bounding-volume tree over the
// bodies' present bounds and scratch buffers. RBodies is a plain container that games copy
// and move; RIntegrator steps whatever container it is given (one integrator may step
// several). Like Update, every query takes the bodies it asks about.
//
// The tree. A bounding-volume tree over the enabled bodies' world boxes (RBoundsTree, the
// broad phase's structure), built the first time a query is asked and kept current lazily:
// before answering, a query compares the container's stamps (RBodies::LayoutStamp,
// PoseStamp) and BodyEditCount() with those the tree was made at. Bodies moved (a step, a
// SetShapePose): the boxes are recomputed from each body's pose, O(1) per body, and the tree
// refitted, O(n), once, by the first query after the move. Bodies added, removed, enabled or
// disabled, or a refitted tree whose nodes have grown to twice their area at its last build:
// built again, O(n log n). Every query after that costs O(log n + what it touches). The
// step's own trees (over boxes grown by the step's motion) are not used: they are stale once
// the step has moved the bodies.
//
// What is tested. Enabled bodies only (a disabled body touches nothing), asleep or awake,
// static, kinematic or dynamic. Each body is tested in its own body frame, about its centre
// of mass, so a query 1e7 m from the origin computes what it computes at the origin (only the
// world points carry the rounding of their large coordinates). The tree only skips bodies it
// can prove missed (its boxes are padded beyond rounding): the answers are exactly, bit for
// bit, those of a loop over every body (RSettings::useTree = false, the reference the tests
// compare against).
//
// Filtering (RQueryFilter). A body is a candidate when its category shares a bit with the
// filter's mask (RBodyDef::category: the rule the pair loop applies in both directions, here
// from the query's side), and then only if the game's callback, when set, accepts it. The
// callback is asked only for bodies the query actually hits (a nearest-hit search may skip
// bodies behind a nearer accepted hit); to ignore the caster (a missile's own launcher),
// reject its handle there.
//
// Determinism. Ties are broken by handle, never by memory address or visiting order: the
// same bodies and query give the same answer, in the same order.
//
// Threads and allocation. An RQueries is used by one thread at a time; it only reads the
// bodies (it never touches their cached world forms), so several RQueries, one per thread,
// may query the same bodies at once while nothing changes them. A query allocates nothing
// once its scratch buffers (kept by the object) and the caller's output vectors have grown
// to size; the tree's rebuilds reuse their arrays as well.
//
// Bad input (a non-finite origin, a zero direction, a negative distance, a non-finite pose
// or a zero quaternion) throws RQueryError naming the argument, before anything is done.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RRigidBody.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace REngine {

// A query that cannot be answered: which argument ("ray.direction") and what is wrong.
class RQueryError : public RError {
 public:
  using RError::RError;
};

// The game's veto on a body a query hits: return false to skip it. A plain function pointer
// with a user pointer, as RPairFilter. It must not change the bodies.
using RQueryCallback = bool (*)(RBodyHandle handle, const RRigidBody& body, void* user);

struct RQueryFilter {
  // Bodies whose RRigidBody::Category() shares no bit with this are skipped.
  std::uint32_t mask = 0xFFFFFFFFu;
  RQueryCallback callback = nullptr;  // null: every body the mask lets through
  void* user = nullptr;               // handed to the callback
};

// A ray: the points origin_W + t * direction_W / |direction_W| for t in [0, maxDistance].
struct RRay {
  RVec3 origin_W = RVec3::Zero();      // m, finite, within 1e15 m of the origin (as bodies)
  RVec3 direction_W = RVec3::UnitX();  // any finite length but 0; only its direction counts
  RScalar maxDistance = std::numeric_limits<RScalar>::infinity();  // m, >= 0 (may be infinite)
};

struct RRayHit {
  RBodyHandle body;
  // Along the ray from its origin, m: exact to rounding in the body's frame (~1e-16 of the
  // body's size plus of the distance). 0 when the ray starts inside the body or on its
  // surface.
  RScalar distance = 0;
  RVec3 point_W = RVec3::Zero();  // origin_W + distance * unit direction, world, m
  // Unit, world: the body's outward surface normal at the point (a sphere's radial
  // direction; the face's normal on a box or hull, the entered face at an edge or corner).
  // A ray that starts inside the body reports the negated ray direction: the normal of a
  // surface that faces the ray, whatever the point (there is no entered face).
  RVec3 normal_W = -RVec3::UnitX();
};

// A convex shape swept along a straight path: where it first touches a body.
struct RShapeCastHit {
  RBodyHandle body;
  // The first touch, as a fraction of the translation, in [0, 1]: the shape at
  // position + fraction * translation is apart from the body by at most the touching band
  // (RCollisionSolver::kTouchingTolerance times the two bounding radii summed; 1e-9 m for two
  // 0.5 m shapes) and never overlaps it before. 0 when they overlap at the start.
  RScalar fraction = 0;
  RVec3 point_W = RVec3::Zero();  // on the body's surface at that moment, world, m
  // Unit, world: from the body towards the cast shape (the body's outward normal at the
  // contact). Overlapping at the start: the direction that separates them fastest (moving
  // the cast shape along it by the depth separates them).
  RVec3 normal_W = RVec3::UnitX();
};

// ---- the narrow phase of one query against one shape, in the shape's own frame ----------
// Pure functions (no bodies, no tree): what RQueries runs for each candidate body, exposed so
// that they can be tested and used alone.

struct RShapeRayHit {
  RScalar distance = 0;            // m along the unit direction
  RVec3 normal = -RVec3::UnitX();  // unit, outward, shape frame (inside: -direction)
};
// The ray origin + t * direction, t in [0, maxDistance], against a shape in its frame
// (origin in m, direction unit, both in that frame): the first point of the solid it meets.
// A sphere by the quadratic in the form that loses no digits (the product of the roots, not
// their difference); a box or hull by clipping the ray against its face planes (exact: no
// iteration). A polyhedron's rounding radius is ignored (bodies have none).
bool RayCastShape(const RConvexShape& shape, const RVec3& origin, const RVec3& direction,
                  RScalar maxDistance, RShapeRayHit& hit);

struct RShapeCastResult {
  RScalar fraction = 0;           // of the translation, see RShapeCastHit
  RVec3 point = RVec3::Zero();    // on A's surface, A's frame, m
  RVec3 normal = RVec3::UnitX();  // unit, from A to B, A's frame
  int iterations = 0;             // distance queries made
  bool converged = true;          // false: stopped at the iteration cap, short of touching
};
// Shape B, at X_AB in A's frame, moved by fraction * translation_A (A's frame, m) for fraction
// in [0, maxFraction]: the first fraction at which it touches A. Conservative advancement on
// the pair's distance (RCollisionSolver::Distance): each step moves B up to the plane that
// supports A's side of the gap, which B cannot cross sooner, so the answer is never past the
// first touch; for a pure translation the distance is convex along the path, so a path that
// does not approach along the closest direction never will, and the search stops. It stops
// touching (the band of RShapeCastHit::fraction); a face meets a face in one step, an edge or
// corner in a few. At kMaxCastIterations it reports where it got to (converged false): short
// of the touch, never past it.
constexpr int kMaxCastIterations = 64;
bool ShapeCastShape(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                    const RVec3& translation_A, RScalar maxFraction, RShapeCastResult& out);

// ---- queries against the bodies -----------------------------------------------------------

struct RQueryState;  // private to REnginePhysics: the tree, the bodies' query forms, scratch

class RQueries {
 public:
  struct RSettings {
    // false: every body is tested, no tree (the reference the tree's answers equal).
    bool useTree = true;
  };

  RQueries();
  explicit RQueries(const RSettings& settings);
  ~RQueries();
  // A copy is another query object with the same settings; it builds its own tree.
  RQueries(const RQueries& other);
  RQueries& operator=(const RQueries& other);
  RQueries(RQueries&&) noexcept;
  RQueries& operator=(RQueries&&) noexcept;

  const RSettings& Settings() const { return m_settings; }
  void SetSettings(const RSettings& settings) { m_settings = settings; }

  // The nearest body the ray hits (distance, then handle, the least), or nothing.
  std::optional<RRayHit> CastRay(const RBodies& bodies, const RRay& ray,
                                 const RQueryFilter& filter = {});
  // Every body the ray hits, nearest first (ties by handle), one hit per body, into `hits`
  // (cleared first).
  void CastRayAll(const RBodies& bodies, const RRay& ray, std::vector<RRayHit>& hits,
                  const RQueryFilter& filter = {});

  // A convex shape (PrepareShape; share it between casts: nothing is built per cast) with its
  // shape frame S at position_W (m) turned by q_WS (normalised here), moved by translation_W
  // (m, world; zero: whether it overlaps at the start), without turning: the first body it
  // touches (fraction, then handle, the least), or nothing.
  std::optional<RShapeCastHit> CastShape(const RBodies& bodies, const RPreparedShape& shape,
                                         const RVec3& position_W, const RQuat& q_WS,
                                         const RVec3& translation_W,
                                         const RQueryFilter& filter = {});
  // The body `caster` swept from where it is by translation_W: as CastShape with its shape and
  // pose, skipping itself and every body the pair loop would never test it against (its
  // ShouldCheckCollision: category and mask both ways, ignore lists; a missile that ignores
  // its launcher ignores it here too). `filter` applies as well. Throws RHandleError for a
  // stale handle.
  std::optional<RShapeCastHit> CastBody(const RBodies& bodies, RBodyHandle caster,
                                        const RVec3& translation_W,
                                        const RQueryFilter& filter = {});

  // Every body that overlaps or touches (within the touching band, RCollision.h) the shape
  // at that pose, into `out` (cleared first), in handle order. The verdict is the narrow
  // phase's (RCollisionSolver::Intersect), exact to that band.
  void Overlap(const RBodies& bodies, const RPreparedShape& shape, const RVec3& position_W,
               const RQuat& q_WS, std::vector<RBodyHandle>& out, const RQueryFilter& filter = {});
  // The same for a sphere (centre, m; radius, m, finite and > 0) ...
  void OverlapSphere(const RBodies& bodies, const RVec3& center_W, RScalar radius,
                     std::vector<RBodyHandle>& out, const RQueryFilter& filter = {});
  // ... and for a solid axis-aligned box, world, m (min_W <= max_W, each side at least 1e-4
  // of the largest: the narrow phase's thinnest box). The bodies inside it, not only those
  // whose bounding boxes meet it.
  void OverlapBox(const RBodies& bodies, const RVec3& min_W, const RVec3& max_W,
                  std::vector<RBodyHandle>& out, const RQueryFilter& filter = {});

  // How the tree was kept current, for tests and profiling: builds and refits so far.
  std::uint64_t TreeBuilds() const;
  std::uint64_t TreeRefits() const;

 private:
  RSettings m_settings;
  std::unique_ptr<RQueryState> m_s;
};

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_QUERIES(X) \
  X(RQueryFilter) \
  X(RRay) \
  X(RRayHit) \
  X(RShapeCastHit) \
  X(RShapeRayHit) \
  X(RShapeCastResult) \
  X(RQueries)
RENGINE_ABI_CHECK(kQueries, RENGINE_ABI_TYPES_QUERIES)
