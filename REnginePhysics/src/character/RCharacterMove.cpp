// The moves of a character (RCharacterMove.h): casts, collide-and-slide, steps, contacts,
// pushes.
#include "character/RCharacterMove.h"

#include <REnginePhysics/RLimits.h>
#include <REnginePhysics/RRigidBody.h>

#include "queries/RQueryState.h"

#include <algorithm>
#include <cmath>

namespace REngine {

namespace {

constexpr int kSlideCasts = 8;

bool Listed(const std::vector<RBodyHandle>& list, RBodyHandle h) {
  return std::find(list.begin(), list.end(), h) != list.end();
}

bool Contains(const std::vector<std::uint32_t>& sorted, std::uint32_t id) {
  return std::binary_search(sorted.begin(), sorted.end(), id);
}

bool AcceptBody(RBodyHandle h, const RRigidBody& b, void* user) {
  return static_cast<const RCharacterMover*>(user)->Solid(h, b);
}


}  // namespace

RVec3 SurfaceVelocity(const RRigidBody& b, const RVec3& p_W) {
  if (b.IsStatic()) return RVec3::Zero();
  return b.Velocity_W() + b.AngularVelocity_W().cross(p_W - b.Position_W());
}

RConvexShape RCharacterMover::Shape() const { return ConvexShapeOf(*c.m_shape); }

RMat3 RCharacterMover::R_WB() const {
  RQuat q = c.m_q * c.m_shape->q_BS.conjugate();
  q.normalize();
  return q.toRotationMatrix();
}

RVec3 RCharacterMover::x_B() const { return c.m_position - R_WB() * c.m_shape->p_BS; }

bool RCharacterMover::Solid(RBodyHandle h, const RRigidBody& b) const {
  const RCharacterDef& d = c.m_def;
  if (h == skip || (b.Category() & d.mask) == 0 || (d.category & b.Mask()) == 0) return false;
  if (carrier && !b.IsStatic() && b.Velocity_W() == carrier->Velocity_W() &&
      b.AngularVelocity_W() == carrier->AngularVelocity_W()) {
    return false;
  }
  if (d.id && Contains(b.IgnoredIds(), *d.id)) return false;
  const std::optional<std::uint32_t> id = b.Id();
  if (id && Contains(d.ignore, *id)) return false;
  return !(b.OneWay() && Listed(c.m_passed, h)) && !Listed(c.m_leaving, h);
}

std::optional<RShapeCastHit> RCharacterMover::Cast(const RVec3& d) {
  RQueryFilter filter;
  filter.mask = c.m_def.mask;
  filter.callback = &AcceptBody;
  filter.user = this;
  // Each pass either returns or adds a body to the passed list: the loop ends.
  for (;;) {
    std::optional<RShapeCastHit> hit = queries.CastShape(bodies, *c.m_shape, c.m_position, c.m_q, d, filter);
    if (!hit || !bodies[hit->body].OneWay()) return hit;
    // A one-way body holds only a landing from above: the normal within maxSlope of up,
    // and the character outside it (a cast that starts overlapping reports fraction 0).
    bool lands = hit->normal_W.dot(c.m_up) >= c.m_cosSlope;
    if (lands && hit->fraction == 0) {
      m_probe.clear();
      Collect(c.m_def.contactOffset, m_probe);
      lands = false;
      for (const RCharacterContact& k : m_probe) {
        if (k.body == hit->body) lands = k.distance > -RScalar(0.5) * c.m_def.contactOffset;
      }
    }
    if (lands) return hit;
    c.m_passed.push_back(hit->body);
  }
}

void RCharacterMover::Push(RBodyHandle h, const RVec3& p, const RVec3& n, const RVec3& vChar) {
  RRigidBody& b = bodies[h];
  if (b.Kind() != RBodyKind::kDynamic || c.m_def.maxPushForce == 0 || Listed(c.m_pushed, h)) return;
  // Pushes act across the plane of up: what the character lands or stands on gets its
  // weight (RCharacter::Update), not the speed of its fall, which on a light crate would be a
  // blow far beyond any force the game set.
  if (Walkable(n)) return;
  const RVec3 level = AcrossUp(-n, c.m_up);
  if (!(level.norm() > RScalar(1e-9))) return;
  const RVec3 u = level.normalized();  // the way the character pushes it
  const RScalar target = AcrossUp(vChar, c.m_up).dot(u);
  const RScalar now = SurfaceVelocity(b, p).dot(u);
  if (!(target > now)) return;
  // The body's effective mass at p along u: 1/m + (r x u) . I_W^-1 (r x u).
  const RVec3 r = p - b.Position_W();
  const RVec3 ru_B = b.Orientation_WB().conjugate() * r.cross(u);
  const RScalar k = b.InvMass() + ru_B.dot(b.InvInertia_B().cwiseProduct(ru_B));
  if (!(k > 0)) return;
  const RScalar j = std::min((target - now) / k, c.m_def.maxPushForce * dt);
  b.AddImpulseAtPoint_W(j * u, p);
  c.m_pushed.push_back(h);
}

void RCharacterMover::Slide(RVec3 d, bool walking, const RVec3& vChar, bool push, bool* steep) {
  const RScalar offset = c.m_def.contactOffset;
  RVec3 planes[2];
  int planeCount = 0;
  // Bodies it starts this move overlapping (or within the casts' touching band of: a floor
  // a million metres wide) and moves away from or along: not in its way (a wall carried with
  // the deck it stands on, which the deck's motion has already brought into it).
  c.m_leaving.clear();
  struct RClear {
    std::vector<RBodyHandle>& list;
    ~RClear() { list.clear(); }
  } clear{c.m_leaving};
  for (int k = 0; k < kSlideCasts; ++k) {
    // Below a billionth of the character's size the motion is rounding: done.
    if (!(d.norm() > RScalar(1e-9) * c.m_shape->boundingRadius)) return;
    const std::optional<RShapeCastHit> hit = Cast(d);
    if (!hit) {
      c.m_position += d;
      return;
    }
    RVec3 n = hit->normal_W;
    const RScalar approach = -d.dot(n);
    if (hit->fraction == 0 && !(approach > 0)) {
      c.m_leaving.push_back(hit->body);
      continue;
    }
    // Stop where the gap along the normal is the offset: back along d from the touch.
    RScalar f = hit->fraction;
    if (approach > 0) f = std::max(RScalar(0), f - offset / approach);
    else f = 0;
    c.m_position += f * d;
    d *= (1 - f);
    if (push) Push(hit->body, hit->point_W, n, vChar);
    const RScalar rise = n.dot(c.m_up);
    if (rise >= c.m_cosSlope) {
      // Walkable: a fall ends here (no sliding downhill on landing), and the motion across
      // the plane of up goes on along the ground, its horizontal part kept.
      const RVec3 level = AcrossUp(d, c.m_up);
      d = level - c.m_up * (level.dot(n) / rise);
    } else if (rise > -RScalar(1e-6)) {
      if (steep) *steep = true;
      // Steep ground or a wall: what walks into it is blocked across the plane of up,
      // and only that; motion down it still slides along its true normal below.
      if (walking) {
        const RVec3 h = AcrossUp(n, c.m_up);
        if (h.norm() > RScalar(1e-9)) n = h.normalized();
      } else if (rise > 0) {
        const RVec3 h = AcrossUp(n, c.m_up);
        if (h.norm() > RScalar(1e-9)) {
          const RVec3 hn = h.normalized();
          const RVec3 across = AcrossUp(d, c.m_up);
          const RScalar into = across.dot(hn);
          if (into < 0) d -= hn * into;
        }
      }
    }
    const RScalar into = d.dot(n);
    if (into < 0) d -= n * into;
    // Two planes met: a crease. Sliding along the second must not go back into the first.
    for (int i = 0; i < planeCount; ++i) {
      if (d.dot(planes[i]) < 0) {
        const RVec3 crease = planes[i].cross(n);
        const RScalar len2 = crease.squaredNorm();
        d = len2 > RScalar(1e-18) ? RVec3(crease * (d.dot(crease) / len2)) : RVec3::Zero();
      }
    }
    if (planeCount < 2) planes[planeCount++] = n;
    else planes[0] = planes[1], planes[1] = n;
  }
}

void RCharacterMover::TryStep(RVec3 start, RVec3 d, RVec3 slid) {
  const RVec3 across = AcrossUp(d, c.m_up);
  const RScalar length = across.norm();
  if (!(c.m_def.stepHeight > 0) || !(length > 0)) return;
  const RVec3 dir = across / length;
  const RVec3 passedBefore = c.m_position;
  const std::size_t passedCount = c.m_passed.size();
  c.m_position = start;
  Slide(c.m_up * c.m_def.stepHeight, false, RVec3::Zero(), false);
  const RScalar risen = (c.m_position - start).dot(c.m_up);
  Slide(across, true, RVec3::Zero(), false);
  const std::optional<RShapeCastHit> down = Cast(-c.m_up * (risen + 2 * c.m_def.contactOffset));
  bool keep = false;
  if (down && down->normal_W.dot(c.m_up) > 0 &&
      Walkable(SurfaceNormal(down->body, down->point_W, down->normal_W))) {
    const RScalar fall = down->fraction * (risen + 2 * c.m_def.contactOffset) -
                         c.m_def.contactOffset / down->normal_W.dot(c.m_up);
    const RVec3 landed = c.m_position - c.m_up * std::max(RScalar(0), fall);
    // Further along than sliding got, no lower than it started (going down is the ground
    // keeping's), and on a point no more than stepHeight above the ground it stood on (a
    // round bottom could otherwise lever itself up any edge a little at a time). Over a
    // sill narrower than the step it lands on the floor beyond: kept too.
    keep = (landed - start).dot(dir) > (slid - start).dot(dir) + RScalar(1e-9) * length &&
           (landed - start).dot(c.m_up) > -RScalar(0.5) * c.m_def.contactOffset &&
           (down->point_W - c.m_ground.contact.point_W).dot(c.m_up) <=
               c.m_def.stepHeight + RScalar(1e-9) * c.m_shape->boundingRadius;
    if (keep) c.m_position = landed;
  }
  if (!keep) {
    c.m_position = passedBefore;
    c.m_passed.resize(passedCount);
  }
}

void RCharacterMover::Collect(RScalar probe, std::vector<RCharacterContact>& out) {
  out.clear();
  const RConvexShape shape = Shape();
  const RMat3 R = R_WB();
  const RVec3 x = x_B();
  // The candidates: the bodies that meet the sphere about its centre of mass that holds its
  // shape grown by the probe (a sphere query builds nothing: no allocation per Update).
  c.m_near.clear();
  if (x.cwiseAbs().maxCoeff() <= kMaxPosition) {
    queries.OverlapSphere(bodies, x, c.m_shape->boundingRadius + probe, c.m_near);
  }
  for (RBodyHandle h : c.m_near) {
    const RRigidBody& b = bodies[h];
    if (!Solid(h, b)) continue;
    const RMat3 R_WA = b.Orientation_WB().toRotationMatrix();
    RRelativePose X;
    X.R_AB = R_WA.transpose() * R;
    X.t_AB = R_WA.transpose() * (x - b.Position_W());
    const RDistanceResult r = RCollisionSolver::Distance(ShapeOf(b), shape, X);
    if (!(r.separation <= probe)) continue;
    RCharacterContact k;
    k.body = h;
    k.distance = r.separation;
    k.normal_W = (R_WA * r.normal).normalized();
    k.point_W = b.Position_W() + R_WA * r.witnessA;
    k.surfaceVelocity_W = SurfaceVelocity(b, k.point_W);
    // A one-way body is a contact only as a floor the character is above.
    if (b.OneWay() && !(k.normal_W.dot(c.m_up) >= c.m_cosSlope &&
                        k.distance > -RScalar(0.5) * c.m_def.contactOffset)) {
      continue;
    }
    out.push_back(k);
  }
}

RVec3 RCharacterMover::SurfaceNormal(RBodyHandle body, const RVec3& point, const RVec3& normal) {
  if (Walkable(normal)) return normal;
  const RVec3 level = AcrossUp(normal, c.m_up);
  if (!(normal.dot(c.m_up) > 0) || !(level.norm() > RScalar(1e-9))) return normal;
  const RScalar e = c.m_def.contactOffset;
  RRay ray;
  ray.origin_W = point - level.normalized() * e + c.m_up * e;
  ray.direction_W = -c.m_up;
  ray.maxDistance = 2 * e;
  struct Only {
    RBodyHandle h;
    static bool Accept(RBodyHandle h, const RRigidBody&, void* user) { return static_cast<Only*>(user)->h == h; }
  } only{body};
  RQueryFilter filter;
  filter.callback = &Only::Accept;
  filter.user = &only;
  const std::optional<RRayHit> hit = queries.CastRay(bodies, ray, filter);
  // distance 0: the ray started inside the body (a wall's contact, not a nosing).
  return hit && hit->distance > 0 ? hit->normal_W : normal;
}

void RCharacterMover::Depenetrate() {
  const RScalar offset = c.m_def.contactOffset;
  for (int k = 0; k < 4; ++k) {
    Collect(offset, m_probe);
    const RCharacterContact* deepest = nullptr;
    for (const RCharacterContact& q : m_probe) {
      if (bodies[q.body].OneWay()) continue;
      if (q.distance < RScalar(0.5) * offset && (!deepest || q.distance < deepest->distance)) deepest = &q;
    }
    if (!deepest) return;
    // Out along the normal by a cast, the overlapped body skipped: pressed against another
    // (a kinematic wall pushing it into a static one) it stays where it is rather than pass
    // through that one.
    const RVec3 out = deepest->normal_W * (offset - deepest->distance);
    const RBodyHandle was = skip;
    skip = deepest->body;
    const RVec3 before = c.m_position;
    Slide(out, false, RVec3::Zero(), false);
    skip = was;
    if (c.m_position == before) return;
  }
}

}  // namespace REngine
