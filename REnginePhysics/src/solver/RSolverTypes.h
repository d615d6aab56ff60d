// Private to REnginePhysics: the contact solver's types, what its contact phase
// (RContactSolver::FindImpulses and the files of solver/) works on: a direction's
// precomputed arms and effective mass, a contact point's normal row, a manifold's block with
// its friction patch and its impact row, a body's working state through the solve, the
// warm-start memory kept from step to step, and the layout's per-contact slots and per-task
// tallies. The contact solver holds them (solver/RContactSolver.h); the joints, the motion,
// the welds and the contact events read them. Plain data: the arithmetic on them is the
// solver's (solver/RSolverRows.h and RContactSolver's functions).
#pragma once

#include <REngineMath/RMath.h>

#include <Eigen/Core>

#include <cstdint>

namespace REngine {

// One direction of a contact point's constraint, with everything the solver's inner
// loop needs precomputed (Catto's formulation): relative velocity along d is
// d.(vB - vA) + rBxd.wB - rAxd.wA, and an impulse lambda d changes wA by -lambda iA and
// wB by lambda iB.
struct RDirection {
  RVec3 d;                   // unit direction, world
  RVec3 rAxd, rBxd;          // lever arms crossed with d, m
  RVec3 iA, iB;              // inverse inertia times the lever arms, 1/(kg m)
  RScalar k;                 // inverse effective mass along d, 1/kg
};
// One contact point's normal constraint, built once per step (solver scratch). Friction
// acts per manifold (RBlock).
struct RContactRow {
  std::uint32_t a, b;        // body indices
  std::uint32_t contact;     // index into the step's contacts (RPairSweep::Contacts)
  std::uint32_t block;       // index into m_blocks
  int point;                 // index into its manifold
  RDirection n;              // the normal, A to B (arms shifted after impacts: FindImpulses)
  RVec3 rA, rB;              // contact point from each centre of mass, world, m
  RScalar lever;             // distance from the manifold's centroid, m
  RScalar gap;               // separation at the start of the step, m
  RScalar deferN;            // normal velocity the impacts deferred to the step's end, m/s
  RScalar target;            // normal relative velocity to reach, m/s
  RScalar pseudoTarget;      // normal pseudo-velocity for position correction, m/s
  RScalar endTarget;         // at the end of the step: 0, or -inf when not in contact
  // Accumulated normal impulses, N s: at the start of the step, of position correction,
  // at the end of the step.
  RScalar lambdaN, lambdaP, lambdaE;
};
// What a solve works on: the velocities with the impulses at the start of the step, the
// pseudo-velocities of position correction, or the velocities at the end of the step.
enum class RPhase : std::uint8_t { kVelocity, kPosition, kEnd };
// A row's accumulated normal impulse (N s) and its target (m/s) in a phase.
inline RScalar& Lambda(RContactRow& r, RPhase phase) {
  return phase == RPhase::kVelocity ? r.lambdaN : phase == RPhase::kPosition ? r.lambdaP : r.lambdaE;
}
inline RScalar Target(const RContactRow& r, RPhase phase) {
  return phase == RPhase::kVelocity ? r.target : phase == RPhase::kPosition ? r.pseudoTarget : r.endTarget;
}
// A manifold's impact constraint: one point at the centre of its leading points, where
// restitution acts (solver scratch, built once per step for every resolved contact).
struct RImpactRow {
  std::uint32_t a, b;        // body indices
  std::uint32_t contact;     // index into the step's contacts (RPairSweep::Contacts)
  int point;                 // the manifold's deepest point, where the impulse is reported
  RDirection normal;         // A to B, with the arms of the leading points' centre
  RVec3 tangent[2];          // the tangents' directions (arms worked out at the impact)
  RVec3 rA, rB;              // the point from each centre of mass, world, m
  RScalar gap;               // the leading points' separation, m (negative: overlap)
  RScalar restitution;       // combined coefficient
  RScalar friction;          // combined Coulomb coefficient
  RScalar lambdaN, lambdaT1, lambdaT2;  // accumulated impulses, N s
  // The impulse on B (world, N s) and its moments about each centre of mass, N m s: the
  // lever arms depend on when within the step each application happened.
  RVec3 impulse, angularA, angularB;
  RVec3 frictionImpulse;     // the tangential part of impulse (contact events), N s
  // Where and along which normal (A to B) the last application acted, world (contact
  // events: where a pair that met within the step touched).
  RVec3 point_W, normal_W;
  bool miss;                 // found, along the motion, not to meet within the step
  bool joined;               // a weld's contacts joined in it: its point whenever it meets
  // The bodies' impact counts (RSolverBody::impacts) when the row was last swept for a
  // contact along their turning paths (SweepImpact): swept again only once either has
  // taken another impulse.
  std::uint32_t sweptA, sweptB;
};
// Working state of a body during the solve: velocities that include every pending change.
struct RSolverBody {
  RVec3 v, w;                // linear and angular velocity, world
  RVec3 vp, wp;              // pseudo-velocities (position correction), world
  RVec3 vMid;                // the velocity it moves with, kept for the end of the step
  // Impacts within the step (SolveIslandImpacts): displacement travelled up to time tau of the
  // step, and the velocity change deferred to the step's end.
  RVec3 moved;
  RScalar tau;
  RVec3 deferV;
  RVec3 vImpacts;            // its velocity after the impact phase
  RVec3 contactDeltaV;      // the contact phase's velocity change after that, m/s
  RMat3 invI;                // inverse inertia, world, 1/(kg m^2) (locks: RMotion::InvInertia_W)
  RScalar invM;              // 1/kg (0: static or kinematic)
  // Linear locks: the inverse mass along world axis k is invM * linMask[k] (1 free, 0
  // locked); only read when linLocked.
  RVec3 linMask;
  bool linLocked;
  // The solver's outputs for the motion (Integrate), besides the impulses it accumulates
  // on the body: contact impulses at the end of the step (world, N s and N m s about the
  // centre of mass at the start of the step), and the impacts' velocity change deferred
  // to the step's end (N s). Valid when the step solved (RContactSolver::Solved).
  RVec3 endLinear, endAngular;
  RVec3 deferredImpulse;
  // What CloseAtEnd asks of the body, read here instead of from the body: its acceleration
  // (0 when static), bounding radius, and whether its spin turns a contact's arm (a
  // dynamic polyhedron's does; a sphere's contact point does not turn with it).
  RVec3 accel;
  RScalar radius;
  bool armTurns;
  // The body's impulses (world, N s and N m s about its centre): its own, then the
  // contacts' added (FindImpulses), written back to the body at the end of the solve.
  RVec3 impulse, angularImpulse;
  // The impact phase's rotation (SolveIslandImpacts, solver/RImpactPath.h). A body that
  // turns on its path (turns: a dynamic body whose contacts move as it turns, without
  // angular locks, drag, welds or joints) is at orientation turnQ at time turnTau of the
  // step, with body spin turnW_B, and turns on the torque-free flow from there; its w and
  // invI are those of turnTau, or of the time atTau its geometry is being worked out at
  // (qAt its orientation then); turning: its spin turns it far enough within the step for
  // that geometry to follow it (TurnsFar; else it keeps turnQ). impacts: the impulses it took
  // in the phase. turned: one of them, after the start, found it turning or set it turning:
  // the motion turns it from turnQ at turnTau with turnW_W, its spin after the contact
  // phase (world), and not from its start (RMotion::Integrate).
  RQuat turnQ, qAt;
  RVec3 turnW_B, turnW_W;
  RScalar turnTau, atTau;
  std::uint32_t impacts;
  bool turns, turning, turned;
};
// Warm-start memory: last step's impulses by (slot a, slot b, feature id), a the lower
// slot; the generations tell a body that took over a freed slot from its former holder.
struct RWarmStart {
  // Left unset: next step's memory is resized to its slots each step (FindImpulses),
  // every one of which is then written whole, and 5 MB of zeros a step would be wasted.
  RWarmStart() {}
  std::uint64_t pair;        // (slot a, slot b)
  std::uint32_t genA, genB;  // the bodies' handle generations
  std::uint32_t feature;
  RVec3 point_A;             // contact point in body a's frame, m
  RScalar lambdaN, lambdaE;  // at the start and at the end of the step, N s
  // Its manifold's friction impulse (world, N s) and twist (N m s), start and end.
  RVec3 tangentImpulse[2];
  RScalar twistImpulse[2];
};
// A manifold: its rows, the minimum-norm inverse of their normal block (up to 4 x 4), and
// its friction patch at the centroid of its points.
struct RBlock {
  std::uint32_t first;
  int count;
  bool useBlock;
  // Its inverse this step: 0 not needed yet (SolveNormalBlock asks for it when the block has
  // something to solve), 1 computed, 2 kept from the manifold's memory.
  std::uint8_t inverse;
  Eigen::Matrix<RScalar, 4, 4> pinv;
  RDirection t[2];           // tangents at the centroid (arms shifted as the rows')
  RVec3 rA, rB;              // the centroid from each centre of mass, world, m
  RVec3 normal;              // world, A to B
  RVec3 twistIA, twistIB;    // inverse inertias times the normal, 1/(kg m^2)
  RScalar kTwist;            // inverse effective inertia about the normal, 1/(kg m^2)
  RScalar friction;          // combined Coulomb coefficient
  // Tangential impulses (N s) and twist about the normal (N m s), at the start [0] and
  // at the end [1] of the step.
  RScalar lambdaT1[2], lambdaT2[2];
  RScalar lambdaTwist[2];
  // Tangential relative velocity (B less A, along t[0], t[1], m/s) that sticking means, at
  // the start [0] and at the end [1] of the step: 0 but against a spinning kinematic body
  // (RMotion::KinematicDrift_W).
  RScalar targetT[2][2];
  // Its friction patch's group (RPatchGroups.cpp): manifolds of one body on flush immovable
  // bodies moving as one, sharing a normal, have one patch, this block's unless patch names
  // another (the group's first block, which holds the group's patch). nextInPatch: the
  // group's next block (kNoBlock at its end); flipped: its pair's bodies the other way
  // round from the patch block's; otherPatch: the body's next patch (grouping only).
  std::uint32_t patch, nextInPatch, otherPatch;
  bool flipped;
  // On a group's patch block: the group's normal rows are few enough (kGroupRows) to be
  // solved as one block, as one manifold's, its inverse at groupSlot of the island's scratch
  // (RPatchGroups.cpp, SolveGroupNormals).
  bool groupRows, groupInverse;  // groupInverse: worked out this step
  std::uint32_t groupSlot;
};
inline constexpr std::uint32_t kNoBlock = ~std::uint32_t{0};
inline constexpr int kGroupRows = 16;
// Row building (FindImpulses): where each resolved contact's rows and block go (its impact
// row has its block's index), and where its rows' warm starts go in next step's memory.
// Blocks and rows are laid out island by island (LayOutIslands): the whole contact phase
// works island by island and reads them in order; the warm starts are in the contacts'
// order.
struct RContactSlots {
  std::uint32_t row, block, warm;
  std::uint32_t warmFound;  // where its pair's entries begin in last step's memory (m_warm)
};
// Each task's counts: rows warm-started, block inverses kept; and whether one of its warm
// starts was not finite (dropped from the memory).
struct RIslandTally {
  std::uint64_t warmStarted = 0, reusedInverses = 0, computedInverses = 0;  // (see RPairStats)
  bool dropped = false;
  bool warmUnordered = false;  // some contact's points' features decrease (ReportIsland)
};
// A manifold's leading points (RContactSolver::LeadingPoints): its deepest point, how many lie
// within the slop of it, and their centre, where an impact acts.
struct RLeadingPoints {
  int deepest = 0;
  int count = 0;
  RVec3 centre;  // contact frame as the manifold's points
};

}  // namespace REngine
