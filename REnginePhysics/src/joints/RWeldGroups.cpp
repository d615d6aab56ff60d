// Welds: bodies joined by fixed joints move as the one rigid body they form.
//
// Why. The fixed joint's rows, solved with RATTLE like every other joint, hold a welded
// pair together to the Newton tolerance, but move each body by its own free flow between
// the impulses: the pair's energy then wanders by RATTLE's (w dt)^2 error (1.4e-6 for two
// boxes tumbling at 1 rad/s), and its motion drifts from the compound's. A weld has no
// relative motion to integrate: its bodies are one rigid body, whose motion (the exact
// free flow of its composite inertia, REngine's own) conserves energy to rounding.
//
// How. At the step's start (GatherWelds, after GatherJoints) the awake dynamic bodies
// joined by the step's fixed joints are grouped; each group's members are placed where
// the joints' frames put them relative to the group's first body (a spanning tree of its
// fixed joints), and the group's mass, centre, principal moments and axes computed from
// that ideal shape. The solver solves the group's joints as it does any joint (the rows
// make the group answer contacts and other joints as the one body it is); the motion
// (MoveWeld, from Integrate) then sums what acted on the members (impulses, forces,
// torques, position correction, the end of the step's impulses) about the group's centre,
// moves the composite body as Integrate moves any body, and places each member on it. The
// fixed joints' own impulses act in pairs at one point, so they cancel in the sums: what
// the composite gets is what the rest of the world did to it.
//
// A group is a weld only when its members move alike: no axis locks (a locked member makes
// the composite's motion not a free one) and one drag rate for all; otherwise its joints
// stay RATTLE's.
#include "joints/RWeldGroups.h"

#include "motion/RMotion.h"
#include <REnginePhysics/RLimits.h>
#include "world/RStepBodies.h"

#include <REngineMath/RQuaternion.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace REngine {

namespace {

// The world inertia R diag(I) R^T of a body with principal moments I at orientation q.
RMat3 InertiaAt(const RQuat& q, const RVec3& I) {
  const RMat3 R = q.toRotationMatrix();
  return R * I.asDiagonal() * R.transpose();
}

}  // namespace

void RWeldGroups::GatherWelds(const RStepBodies& bodies, const std::vector<RStepJoint>& stepJoints) {
  m_weldGroups.clear(), m_weldMembers.clear(), m_weldJoints.clear();
  const std::uint32_t world = static_cast<std::uint32_t>(bodies.size());
  auto Weldable = [](const RBodyCore& b) {
    return !b.Immovable() && !b.m_sleeping && !b.m_linearLocked && !b.m_angularLocked;
  };
  for (std::uint32_t k = 0; k < stepJoints.size(); ++k) {
    const RStepJoint& sj = stepJoints[k];
    if (bodies.joints[sj.joint].def.type != RJointType::kFixed || sj.b == world) continue;
    if (Weldable(bodies[sj.a]) && Weldable(bodies[sj.b])) m_weldJoints.push_back(k);
  }
  if (m_weldJoints.empty()) {
    m_weldOf.clear();
    return;
  }
  const std::size_t n = bodies.size();
  m_weldSets.Reset(n);
  m_weldOf.assign(n, 0);
  for (std::uint32_t k : m_weldJoints) {
    const RStepJoint& sj = stepJoints[k];
    m_weldSets.Union(sj.a, sj.b);
  }
  // The groups in the order of their smallest body (the union-find's root), each joint
  // listed under its group: the same grouping and order on any run.
  std::sort(m_weldJoints.begin(), m_weldJoints.end(), [&](std::uint32_t x, std::uint32_t y) {
    const std::uint32_t rx = m_weldSets.Find(stepJoints[x].a), ry = m_weldSets.Find(stepJoints[y].a);
    return rx != ry ? rx < ry : x < y;
  });
  for (std::size_t j0 = 0; j0 < m_weldJoints.size();) {
    const std::uint32_t root = m_weldSets.Find(stepJoints[m_weldJoints[j0]].a);
    std::size_t j1 = j0;
    while (j1 < m_weldJoints.size() && m_weldSets.Find(stepJoints[m_weldJoints[j1]].a) == root) ++j1;
    RWeldGroup g;
    g.first = static_cast<std::uint32_t>(m_weldMembers.size());
    const RBodyCore& R = bodies[root];
    bool alike = true;
    // The members' ideal poses in the root's frame (q_RB, p_R), placed joint by joint: each
    // pass places the far end of every joint with one end placed (a spanning tree; a
    // joint closing a cycle is left to the solver's rows, which hold it as they hold any).
    m_weldMembers.push_back(RWeldMember{root, RQuat::Identity(), RVec3::Zero()});
    m_weldOf[root] = 1;
    for (bool placed = true; placed;) {
      placed = false;
      for (std::size_t t = j0; t < j1; ++t) {
        const RStepJoint& sj = stepJoints[m_weldJoints[t]];
        if (m_weldOf[sj.a] == m_weldOf[sj.b]) continue;
        const RJoint& J = bodies.joints[sj.joint];
        const bool fromA = m_weldOf[sj.a] != 0;
        const std::uint32_t known = fromA ? sj.a : sj.b, other = fromA ? sj.b : sj.a;
        const RWeldMember* m = nullptr;
        for (std::size_t k = g.first; k < m_weldMembers.size(); ++k) {
          if (m_weldMembers[k].body == known) m = &m_weldMembers[k];
        }
        // Fixed: q_B = q_A relative0, and the anchors at one point.
        RWeldMember add{other, RQuat::Identity(), RVec3::Zero()};
        if (fromA) {
          add.q = m->q * J.relative0;
          add.p = m->p + m->q * J.anchorA_B - add.q * J.anchorB_B;
        } else {
          add.q = m->q * J.relative0.conjugate();
          add.p = m->p + m->q * J.anchorB_B - add.q * J.anchorA_B;
        }
        add.q.normalize();
        const RBodyCore& B = bodies[other];
        alike = alike && B.m_linearDamping == R.m_linearDamping && B.m_angularDamping == R.m_angularDamping;
        m_weldMembers.push_back(add);
        m_weldOf[other] = 1;
        placed = true;
      }
    }
    j0 = j1;
    g.count = static_cast<std::uint32_t>(m_weldMembers.size()) - g.first;
    if (!alike) {
      for (std::uint32_t k = g.first; k < g.first + g.count; ++k) m_weldOf[m_weldMembers[k].body] = 0;
      m_weldMembers.resize(g.first);
      continue;
    }
    // The composite: mass, centre and inertia in the root's frame, then its principal axes
    // (ascending moments, a rotation), as RCompound computes a compound body's.
    RWeldMember* members = m_weldMembers.data() + g.first;
    g.mass = 0;
    RVec3 moment = RVec3::Zero();
    for (std::uint32_t k = 0; k < g.count; ++k) {
      const RBodyCore& b = bodies[members[k].body];
      g.mass += b.m_mass, moment += b.m_mass * members[k].p;
    }
    const RVec3 c = moment / g.mass;
    RMat3 I = RMat3::Zero();
    for (std::uint32_t k = 0; k < g.count; ++k) {
      const RBodyCore& b = bodies[members[k].body];
      const RVec3 d = members[k].p - c;
      I += InertiaAt(members[k].q, b.m_I_B) + b.m_mass * (d.squaredNorm() * RMat3::Identity() - d * d.transpose());
    }
    const Eigen::SelfAdjointEigenSolver<RMat3> eig(RScalar(0.5) * (I + I.transpose()));
    g.I = eig.eigenvalues();
    RMat3 axes = eig.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
    RQuat q_RC(axes);
    q_RC.normalize();
    g.q_RC = q_RC;
    // Each member in the composite's frame.
    const std::uint32_t index = static_cast<std::uint32_t>(m_weldGroups.size()) + 1;
    for (std::uint32_t k = 0; k < g.count; ++k) {
      RWeldMember& m = members[k];
      m_weldOf[m.body] = index;
      m.p = q_RC.conjugate() * RVec3(m.p - c);
      m.q = (q_RC.conjugate() * m.q).normalized();
    }
    m_weldGroups.push_back(g);
  }
}

// The group's centre of mass where its members are: summed from the root, whose position is
// exact, of the members' offsets from it (exact too: differences of nearby coordinates), so
// that 1e6 m from the origin the sum adds one rounding of the coordinates, not one a member.
RVec3 RWeldGroups::Centre(const RStepBodies& bodies, const RWeldGroup& g) const {
  const RWeldMember* members = m_weldMembers.data() + g.first;
  const RVec3 x0 = bodies[members[0].body].m_x_W;
  RVec3 moment = RVec3::Zero();
  for (std::uint32_t k = 1; k < g.count; ++k) {
    const RBodyCore& b = bodies[members[k].body];
    moment += b.m_mass * RVec3(b.m_x_W - x0);
  }
  return x0 + moment / g.mass;
}

// One group's motion: Integrate's steps for one body (RIntegration.cpp), on the composite.
void RWeldGroups::MoveWeld(const RStepBodies& bodies, std::size_t group, RScalar dt,
                           const RWorldSettings& settings,
                           const std::vector<RSolverBody>& solverBodies,
                           const std::vector<char>& inRows, bool solved,
                           std::vector<char>& putBack) const {
  const RWeldGroup& g = m_weldGroups[group];
  const RScalar halfDt = RScalar(0.5) * dt;
  const RWeldMember* members = m_weldMembers.data() + g.first;
  const RBodyCore& root = bodies[members[0].body];
  const RScalar invM = 1 / g.mass;
  const RVec3 invI = g.I.cwiseInverse();

  // The composite's state: its centre where its members' masses put it, its frame the
  // root's turned to the principal axes, its velocities those of its members' momenta. The
  // members' arms from the centre are the group's own (q p), not differences of their
  // positions: 1e6 m from the origin those carry the coordinates' rounding (5e-10 m), which
  // would wander the angular momentum by 1e-9 a step.
  RQuat q = (root.m_q_WB * g.q_RC).normalized();
  RVec3 c = Centre(bodies, g), P = RVec3::Zero();
  for (std::uint32_t k = 0; k < g.count; ++k) {
    const RBodyCore& b = bodies[members[k].body];
    P += b.m_mass * b.m_v_W;
  }
  const RVec3 c0 = c;
  bool scaled = false, forced = false;
  RVec3 L = RVec3::Zero(), J = RVec3::Zero(), H = RVec3::Zero(), F = RVec3::Zero(), T = RVec3::Zero();
  RScalar weight = 0;  // sum of m s (gravity scales)
  RVec3 Pp = RVec3::Zero(), Lp = RVec3::Zero(), deferred = RVec3::Zero(), endJ = RVec3::Zero(), endH = RVec3::Zero();
  for (std::uint32_t k = 0; k < g.count; ++k) {
    const std::uint32_t i = members[k].body;
    const RBodyCore& b = bodies[i];
    const RVec3 r = q * members[k].p;
    L += r.cross(b.m_mass * b.m_v_W) + b.m_q_WB * RVec3(b.m_I_B.cwiseProduct(b.m_w_B));
    J += b.m_linearImpulse_W, H += b.m_angularImpulse_W + r.cross(b.m_linearImpulse_W);
    F += b.m_force_W, T += b.m_torque_W;
    forced = forced || !b.m_force_W.isZero(0);
    weight += b.m_mass * b.m_gravityScale;
    scaled = scaled || b.m_gravityScale != root.m_gravityScale;
    const RSolverBody* out = solved && inRows[i] ? &solverBodies[i] : nullptr;
    if (!out) continue;
    if (!out->vp.isZero(0) || !out->wp.isZero(0)) {
      Pp += b.m_mass * out->vp, Lp += InertiaAt(b.m_q_WB, b.m_I_B) * out->wp + r.cross(b.m_mass * out->vp);
    }
    deferred += out->deferredImpulse;
    endJ += out->endLinear, endH += out->endAngular + r.cross(out->endLinear);
  }
  // Gravity: the same scale on every member pulls the composite at that scale through its
  // centre (no torque, and the very arithmetic of one body's); different scales also turn it.
  // The turning moment of the members' forces and of different scales depends on the
  // composite's orientation: taken where it is at each kick (kick-drift-kick, as for any
  // force that depends on the pose; the same moment in both kicks would be first order and
  // gain energy).
  const RVec3 accel = scaled ? RVec3(F * invM + settings.gravity_W * (weight * invM))
                             : RVec3(F * invM + RMotion::Gravity(root, settings.gravity_W));
  auto moment = [&](const RQuat& turn) {
    RVec3 m = T;
    if (!forced && !scaled) return m;
    for (std::uint32_t k = 0; k < g.count; ++k) {
      const RBodyCore& b = bodies[members[k].body];
      const RVec3 f = scaled ? RVec3(b.m_force_W + b.m_mass * b.m_gravityScale * settings.gravity_W) : b.m_force_W;
      m += RVec3(turn * members[k].p).cross(f);
    }
    return m;
  };
  const RMat3 R0 = q.toRotationMatrix();
  RVec3 w_C = invI.cwiseProduct(R0.transpose() * L);

  // Linear: kick-drift-kick; with drag the exact flow's mean and end velocities, the
  // impulses' change decaying from mid-step (RMotion::DragFlow, as Integrate).
  RVec3 v = P * invM;
  RVec3 vDragEnd = RVec3::Zero();
  if (root.m_linearDamping != 0) {
    const RMotion::RDragFlow d = RMotion::DragFlow(root.m_linearDamping, dt);
    const RVec3 vHalf = v * d.M + J * invM + accel * (d.G * dt);
    c += vHalf * dt;
    vDragEnd = v * d.E + accel * (d.M * dt);
    v = J * invM;
  } else {
    const RVec3 vHalf = v + J * invM + accel * halfDt;
    c += vHalf * dt;
    v = vHalf + accel * halfDt;
  }
  // Angular: drag (the spin scaled by the flow's mean factor through the turn, by E/M after
  // it), the start kick, the exact free flow of the composite, the end kick.
  RScalar spinEnd = 1;
  if (root.m_angularDamping != 0) {
    const RMotion::RDragFlow d = RMotion::DragFlow(root.m_angularDamping, dt);
    w_C *= d.M;
    spinEnd = d.E / d.M;
  }
  const RVec3 kick0 = H + moment(q) * halfDt;
  if (!kick0.isZero(0)) w_C += invI.cwiseProduct(q.conjugate() * kick0);
  RFreeRotation flow;
  flow.SetInertia(g.I);
  flow.Advance(dt, w_C, q);
  const RVec3 T1 = moment(q);
  if (!T1.isZero(0)) w_C += invI.cwiseProduct(q.conjugate() * RVec3(T1 * halfDt));
  // Position correction: the members' pseudo-impulses on the composite.
  RVec3 vp = RVec3::Zero(), wp = RVec3::Zero();
  if (!Pp.isZero(0) || !Lp.isZero(0)) {
    vp = Pp * invM;
    wp = R0 * invI.asDiagonal() * R0.transpose() * Lp;
    c += vp * dt;
    q = QuatExp(wp * dt) * q;
    q.normalize();
  }
  // Impacts deferred to the end, and the end of the step's impulses (about the centre the
  // step started at: moved to the one it ends at, as Integrate does).
  if (!deferred.isZero(0)) v += deferred * invM;
  if (!endJ.isZero(0) || !endH.isZero(0)) {
    v += endJ * invM;
    w_C += invI.cwiseProduct(q.conjugate() * RVec3(endH - (c - c0).cross(endJ)));
  }
  if (root.m_linearDamping != 0) v = v * RMotion::Decay(root.m_linearDamping, halfDt) + vDragEnd;
  if (root.m_angularDamping != 0) w_C *= spinEnd;

  // The members on the composite; a composite whose new state is not finite, or whose centre
  // left kMaxPosition, stays where it was, at rest, its members reported as Integrate reports
  // a body (putBack, RMotion::Kept).
  const bool finite = AllFinite(v) && AllFinite(w_C) && AllFinite(q) && c.cwiseAbs().maxCoeff() <= kMaxPosition;
  const RVec3 w_W = q * w_C;
  const RScalar pseudoSpin = wp.norm(), spin = w_C.norm();
  for (std::uint32_t k = 0; k < g.count; ++k) {
    const RWeldMember& m = members[k];
    RBodyCore& b = bodies[m.body];
    b.m_force_W.setZero(), b.m_torque_W.setZero();
    b.m_linearImpulse_W.setZero(), b.m_angularImpulse_W.setZero();
    if (!finite) {
      b.m_v_W.setZero(), b.m_w_B.setZero(), b.m_w_W.setZero();
      b.m_restTime = 0;
      putBack[m.body] = 1;
      continue;
    }
    const RVec3 r = q * m.p;
    b.m_x_W = c + r;
    b.m_q_WB = (q * m.q).normalized();
    b.m_v_W = v + w_W.cross(r);
    b.m_w_B = m.q.conjugate() * w_C;
    // How long it has been at rest, as Integrate counts it for a body.
    const RScalar pseudoSpeed =
        pseudoSpin == 0 && vp.isZero(0) ? 0 : RVec3(vp + wp.cross(r)).norm() + pseudoSpin * b.m_boundingRadius;
    const RScalar speed = std::max(b.m_v_W.norm() + spin * b.m_boundingRadius, pseudoSpeed);
    b.m_restTime = speed < settings.sleepSpeed ? b.m_restTime + dt : 0;
  }
}

// The members' end poses from the solver's velocities: MoveWeld's motion without the end of
// the step (the second kick, the end impulses), as PredictPose predicts a body's. The
// group's own fixed joints then hold exactly at the prediction; the Newton rounds of the
// other joints see where the group really goes.
void RWeldGroups::PredictWeld(const RStepBodies& bodies, std::size_t group, RScalar dt,
                              const std::vector<RSolverBody>& solverBodies,
                              std::vector<RJointPose>& jointPoses) const {
  const RWeldGroup& g = m_weldGroups[group];
  const RWeldMember* members = m_weldMembers.data() + g.first;
  const RScalar invM = 1 / g.mass;
  const RVec3 invI = g.I.cwiseInverse();
  RQuat q = (bodies[members[0].body].m_q_WB * g.q_RC).normalized();
  RVec3 c = Centre(bodies, g);
  RVec3 P = RVec3::Zero(), L = RVec3::Zero(), Pp = RVec3::Zero(), Lp = RVec3::Zero();
  for (std::uint32_t k = 0; k < g.count; ++k) {
    const std::uint32_t i = members[k].body;
    const RBodyCore& b = bodies[i];
    const RSolverBody& s = solverBodies[i];
    const RVec3 r = q * members[k].p, move = s.deferV.isZero(0) ? s.v : RVec3(s.v - s.deferV);
    const RMat3 I_W = InertiaAt(b.m_q_WB, b.m_I_B);
    P += b.m_mass * move, L += r.cross(b.m_mass * move) + I_W * s.w;
    if (!s.vp.isZero(0) || !s.wp.isZero(0)) Pp += b.m_mass * s.vp, Lp += I_W * s.wp + r.cross(b.m_mass * s.vp);
  }
  const RMat3 R0 = q.toRotationMatrix();
  const RVec3 v = P * invM;
  RVec3 w_C = invI.cwiseProduct(R0.transpose() * L);
  c += v * dt;
  RFreeRotation flow;
  flow.SetInertia(g.I);
  flow.Advance(dt, w_C, q);
  const RQuat qFlow = q;
  if (!Pp.isZero(0) || !Lp.isZero(0)) {
    c += Pp * invM * dt;
    q = QuatExp(RVec3(R0 * invI.asDiagonal() * R0.transpose() * Lp) * dt) * q;
    q.normalize();
  }
  const RVec3 wEnd_W = q * w_C;
  for (std::uint32_t k = 0; k < g.count; ++k) {
    const RWeldMember& m = members[k];
    RJointPose& p = jointPoses[m.body];
    const RVec3 r = q * m.p;
    p.x = p.xPredicted = c + r;
    p.q = p.qPredicted = (q * m.q).normalized();
    p.qFlow = (qFlow * m.q).normalized();
    p.vMid = v + wEnd_W.cross(r);
    p.wEnd_W = wEnd_W;
  }
}

}  // namespace REngine
