// The contact solver (RContactSolver::FindImpulses): rows, warm starts, manifold blocks,
// friction patches and the end of the step; see RIntegrator.h.
#include "solver/RContactSolver.h"

#include <REnginePhysics/RJobSystem.h>

#include "collision/RGjkEpa.h"
#include "joints/RWeldGroups.h"
#include "motion/RMotion.h"
#include "pairs/RPairSweep.h"
#include "world/RStepBodies.h"

#include "solver/RSolverRows.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

// Sequential impulses (Catto 2005) over every contact point, with the velocities each body
// will move with during the step (its pending impulses and half the step's acceleration
// included: kick-drift-kick moves bodies with the mid-step velocity, so a resting contact
// that holds that velocity at zero does not sink at all). In phases: impacts (SolveIslandImpacts),
// then the contacts: accumulated normal impulses clamped at zero (a contact pushes, never
// pulls: the separating-velocity guard), friction per manifold within the Coulomb disc of
// mu times the manifold's normal impulse (SolvePatch), every row starting from last step's
// impulses for the same features; small islands solved exactly; then the end of the step
// (SolveIslandContacts, RContactPasses.cpp). Penetration beyond a slop is removed by
// pseudo-velocities (split impulses), solved apart so that position correction never adds
// kinetic energy.
//
// Every phase works island by island (bodies linked through contacts between movable
// bodies: LayOutIslands), and one island goes through all of them before the next
// (SolveIsland): an island's rows, blocks and bodies are built, solved and reported while
// they are in the cache. Islands share no body an impulse moves, so they are tasks, and the
// answer is the same on any number of threads.
void RContactSolver::FindImpulses(const RStepBodies& bodies, RScalar dt, const RSolverInputs& in) {
  // The inputs, for the island functions, while the call runs (reset on every way out).
  m_in = &in;
  struct RReset {
    const RSolverInputs*& inputs;
    ~RReset() { inputs = nullptr; }
  } reset{m_in};
  const std::size_t n = bodies.size();
  // Warm-start memory is keyed by slot (and generation). A plain vector's slots are its
  // indices: when the game adds or removes bodies they shift, and another pair would
  // inherit a stranger's impulses.
  if (bodies.byIndex && n != m_warmBodyCount) m_warm.clear();
  m_warmBodyCount = bodies.byIndex ? n : 0;
  m_warmNext.clear();
  KeepSleepingWarmStarts(bodies);
  // One more solver body: the world's, what a joint to the world holds on to (never moved).
  m_solverBodies.resize(n + 1);
  m_patchHead.resize(n);  // (each island sets its bodies' entries: GroupPatches)
  const RScalar halfDt = RScalar(0.5) * dt;
  m_joints.GatherJoints(bodies);
  m_in->welds.GatherWelds(bodies, m_joints.StepJoints());
  bool anyRow = !m_joints.StepJoints().empty();
  for (const RContact& c : m_in->sweep.Contacts()) {
    anyRow = anyRow || (m_in->sweep.RespondsAt(c.a) && m_in->sweep.RespondsAt(c.b) && !(m_in->sweep.ImmovableAt(c.a) && m_in->sweep.ImmovableAt(c.b)) &&
                        c.manifold.pointCount > 0);
  }
  m_solved = anyRow;
  if (!anyRow) {
    m_rows.clear(), m_impacts.clear(), m_blocks.clear();
    m_blockIslands.clear(), m_islandImpacts.clear();
    std::swap(m_warm, m_warmNext);
    return;
  }
  // The rows, impact rows and friction patches of every contact, at places counted
  // beforehand island by island, and the islands' bodies (LayOutIslands).
  LayOutIslands(bodies);
  if (!m_joints.StepJoints().empty()) {
    RSolverBody& world = m_solverBodies[n];
    world.v.setZero(), world.w.setZero(), world.vp.setZero(), world.wp.setZero();
    world.invI.setZero(), world.invM = 0, world.linMask = RVec3::Ones(), world.linLocked = false;
    m_joints.SizeForStep(n);
  }
  // The static and kinematic bodies' solver state, which every island that touches them
  // reads (their velocities are their own: impulses do not move them, and the impact phase
  // moves them on copies).
  for (std::uint32_t i : m_immovableRowBodies) {
    RSolverBody& s = m_solverBodies[i];
    RMotion::InitSolverBody(s, bodies[i], m_in->sweep.MoveV(i), halfDt, m_in->settings.gravity_W);
    s.moved.setZero(), s.tau = 0, s.deferV.setZero();
    s.vImpacts = s.v, s.contactDeltaV.setZero(), s.vMid = s.v;
    s.turns = s.turned = false, s.impacts = 0;
  }
  // Next step's warm starts: those kept for sleeping pairs, then each contact's rows in the
  // contacts' order (RContactSlots::warm), written by the islands.
  const std::size_t warmBase = m_warmNext.size();
  m_warmNext.resize(warmBase + m_rows.size());
  m_in->sweep.MutableStats().contactPoints = m_rows.size();
  m_islandImpacts.assign(m_blockIslands.size(), 0);
  if (m_islandTallies.size() < m_in->tasks) m_islandTallies.resize(m_in->tasks);
  if (m_islandScratch.size() < m_in->tasks) m_islandScratch.resize(m_in->tasks);
  // An island too large to share the work with others (one pile of everything) has its
  // bodies' solver state and its rows built first, as tasks over its bodies and contacts
  // (each alone: the same rows), so that a world of one island still builds them on every
  // thread; its passes stay in order.
  m_islandRowsBuilt.assign(m_blockIslands.size(), 0);
  std::uint64_t prebuiltWarm = 0;
  if (m_in->jobs && m_in->tasks > 1) {
    for (std::size_t isl = 0; isl < m_blockIslands.size(); ++isl) {
      // (Not a structured binding: the lambdas below capture them, which C++17 forbids.)
      const std::uint32_t first = m_blockIslands[isl].first, last = m_blockIslands[isl].second;
      if (last - first < 256 || 2 * m_in->tasks * (last - first) < m_blocks.size()) continue;
      m_islandRowsBuilt[isl] = 1;
      const std::uint32_t b0 = m_islandBodyStart[isl], b1 = m_islandBodyStart[isl + 1];
      ParallelRanges(m_in->jobs, b1 - b0, m_in->tasks, 64, [&](std::size_t k0, std::size_t k1, std::size_t) {
        for (std::size_t k = b0 + k0; k < b0 + k1; ++k) {
          const std::uint32_t i = m_islandBodies[k];
          RMotion::InitSolverBody(m_solverBodies[i], bodies[i], m_in->sweep.MoveV(i), halfDt, m_in->settings.gravity_W);
        }
      });
      const std::size_t used = ParallelRanges(m_in->jobs, last - first, m_in->tasks, 32, [&](std::size_t k0, std::size_t k1, std::size_t task) {
        RIslandTally& tally = m_islandTallies[task];
        tally = RIslandTally{};
        for (std::size_t k = first + k0; k < first + k1; ++k) {
          tally.warmStarted += BuildContactRows(bodies, m_blockContact[k], dt);
        }
      });
      for (std::size_t t = 0; t < used; ++t) prebuiltWarm += m_islandTallies[t].warmStarted;
    }
  }
  m_in->sweep.MutableStats().warmStarted += prebuiltWarm;
  const std::size_t tasks = ParallelRanges(m_in->jobs, m_blockIslands.size(), m_in->tasks, 4, [&](std::size_t i0, std::size_t i1, std::size_t task) {
    RIslandTally& tally = m_islandTallies[task];
    tally = RIslandTally{};
    for (std::size_t isl = i0; isl < i1; ++isl) SolveIsland(bodies, dt, isl, warmBase, m_islandScratch[task], tally);
  });
  bool dropped = false, warmUnordered = false;
  for (std::size_t t = 0; t < tasks; ++t) {
    m_in->sweep.MutableStats().warmStarted += m_islandTallies[t].warmStarted;
    m_in->sweep.MutableStats().reusedInverses += m_islandTallies[t].reusedInverses;
    m_in->sweep.MutableStats().computedInverses += m_islandTallies[t].computedInverses;
    dropped = dropped || m_islandTallies[t].dropped;
    warmUnordered = warmUnordered || m_islandTallies[t].warmUnordered;
  }
  // A step that overflowed must not seed the next one (ReportIsland marks its rows).
  if (dropped) {
    m_warmNext.erase(std::remove_if(m_warmNext.begin(), m_warmNext.end(),
                                    [](const RWarmStart& w) { return w.pair == kDroppedWarm; }),
                     m_warmNext.end());
  }
  // Rows come in the pair sweep's order, which is slot order unless bodies were added or
  // removed (or it is a plain vector reordered): sorted already, most steps. Known to be
  // sorted, without reading the list again (5 MB in a 10000-box pile), when nothing was
  // kept for sleeping pairs before the rows, the contacts' pairs increase and each
  // contact's features do not decrease (what std::is_sorted would find).
  auto before = [](const RWarmStart& x, const RWarmStart& y) {
    return x.pair < y.pair || (x.pair == y.pair && x.feature < y.feature);
  };
  const bool inOrder = warmBase == 0 && !dropped && m_warmPairsIncrease && !warmUnordered;
  if (!inOrder && !std::is_sorted(m_warmNext.begin(), m_warmNext.end(), before)) {
    std::sort(m_warmNext.begin(), m_warmNext.end(), before);
  }
  std::swap(m_warm, m_warmNext);
}

// One island, start to end: its bodies' solver state (the velocities they move with this
// step, from CollisionDetection's pre-pass, their world inverse inertias and masks:
// RBodyMotion.cpp), its contacts' rows, last step's impulses applied (warm start), its
// impacts, its contact phase and end of the step, and the report.
void RContactSolver::SolveIsland(const RStepBodies& bodies, RScalar dt, std::size_t island, std::size_t warmBase,
                                 RIslandScratch& sc, RIslandTally& tally) {
  const RScalar halfDt = RScalar(0.5) * dt;
  const auto [first, last] = m_blockIslands[island];
  if (!m_islandRowsBuilt[island]) {  // (else built as tasks: FindImpulses)
    // An island's bodies and contacts lie far apart in storage (a pile's column: a layer of
    // bodies between two), each a wait for memory: the next ones are asked for while one
    // is worked on, across the island's end (the islands are laid out in the order they
    // are solved: a debris cloud's islands of two or three bodies wait on every one).
    const std::uint32_t b0 = m_islandBodyStart[island], b1 = m_islandBodyStart[island + 1];
    for (std::uint32_t k = b0; k < b1; ++k) {
      if (k + 2 < m_islandBodies.size()) PrefetchBody(bodies[m_islandBodies[k + 2]], 8 * 64);  // to the shape's core
      const std::uint32_t i = m_islandBodies[k];
      RMotion::InitSolverBody(m_solverBodies[i], bodies[i], m_in->sweep.MoveV(i), halfDt, m_in->settings.gravity_W);
    }
    for (std::uint32_t k = first; k < last; ++k) {
      if (k + 1 < m_blockContact.size()) PrefetchContact(m_blockContact[k + 1]);
      tally.warmStarted += BuildContactRows(bodies, m_blockContact[k], dt);
    }
  }
  const bool joints = m_joints.IslandHasJoints(island);
  // (An island with joints keeps a patch per manifold: the joints' end reads them one by one.)
  if (!joints) GroupPatches(bodies, first, last, sc);
  WarmStartIslandVelocities(bodies, dt, island, sc);
  const RJointIslandView jointView = JointView(bodies, dt, island);
  if (joints) m_joints.BuildIslandJoints(jointView, sc);
  // Most islands (a resting pile: every one) have no impact: their impact rows are not built.
  m_islandImpacts[island] = MayImpact(island);
  if (m_islandImpacts[island]) {
    for (std::uint32_t k = first; k < last; ++k) BuildImpactRow(bodies, m_blockContact[k], k);
    JoinPairImpacts(bodies, first, last);
  }
  SolveIslandImpacts(bodies, dt, island, jointView, sc);
  if (m_islandImpacts[island]) ShiftArmsAfterImpacts(dt, island);
  // Rows come grouped by contact. A manifold's normal rows are solved together: its points
  // share two bodies, and solving them one after another favours the first, leaving a
  // small torque that tilts stacked bodies step after step. The block's matrix is rank
  // deficient (four points of one face constrain three degrees of freedom), so the
  // minimum-norm least-squares inverse is worked out (or kept from the manifold's memory)
  // once a step, the first time the block has something to solve; when its answer would
  // pull at a point, that manifold falls back to one point at a time.
  SolveIslandContacts(bodies, dt, island, jointView, sc);
  if (joints) m_joints.ReportJoints(jointView);
  ReportIsland(bodies, dt, island, warmBase, tally);
  if (joints) m_joints.SolveJointsAtEnd(jointView, sc);
}

RJointIslandView RContactSolver::JointView(const RStepBodies& bodies, RScalar dt, std::size_t island) {
  const auto [rowsFirst, rowsLast] = IslandRows(island);
  return RJointIslandView{bodies,    dt,       island,         m_solverBodies, m_rows.data(), m_blocks.data(),
                          rowsFirst, rowsLast, m_in->settings, m_in->welds,    m_in->sweep};
}

// Several contacts of one pair of bodies (a compound's child pairs, one after another in
// the contacts) bounce as one impact: restitution targets solved one after another, each
// at its own contact, could return more energy than came in (a box split in two children
// hitting a wall at e = 1 left at 0.84 of its speed, spinning) or let a fast body through.
// The deepest contact's row takes the centre of the leading points of every contact of the
// pair facing its way, whose rows then never impact (their gap is infinite); a contact
// facing another way (a compound meeting two faces of a static U at once) keeps its own.
void RContactSolver::JoinPairImpacts(const RStepBodies& bodies, std::uint32_t first, std::uint32_t last) {
  for (std::uint32_t k0 = first; k0 < last;) {
    const RContact& c0 = m_in->sweep.Contacts()[m_blockContact[k0]];
    std::uint32_t k1 = k0 + 1;
    while (k1 < last && m_in->sweep.Contacts()[m_blockContact[k1]].a == c0.a && m_in->sweep.Contacts()[m_blockContact[k1]].b == c0.b) ++k1;
    if (k1 - k0 > 1) {
      std::uint32_t lead = k0;
      for (std::uint32_t k = k0 + 1; k < k1; ++k) {
        if (m_impacts[k].gap < m_impacts[lead].gap) lead = k;
      }
      RImpactRow& r = m_impacts[lead];
      const RVec3& n = m_in->sweep.Contacts()[m_blockContact[lead]].manifold.normal;
      RVec3 sum = RVec3::Zero();
      int count = 0;
      for (std::uint32_t k = k0; k < k1; ++k) {
        const RContactManifold& m = m_in->sweep.Contacts()[m_blockContact[k]].manifold;
        if (m.normal.dot(n) < kFaceContactCos) continue;
        if (k != lead) m_impacts[k].gap = std::numeric_limits<RScalar>::infinity();
        for (int q = 0; q < m.pointCount; ++q) {
          if (m.points[q].separation <= r.gap + m_in->settings.penetrationSlop) sum += m.points[q].position, ++count;
        }
      }
      if (count > 0) {
        const RContact& c = m_in->sweep.Contacts()[m_blockContact[lead]];
        const RVec3 centre = sum / count;
        r.rA = centre - bodies[c.a].m_x_W, r.rB = centre - bodies[c.b].m_x_W;
        SetDirection(r.normal, n, r.rA, r.rB, m_solverBodies[c.a], m_solverBodies[c.b]);
      }
    }
    k0 = k1;
  }
  if (m_in->welds.GroupCount() != 0) JoinWeldImpacts(bodies, first, last);
}

// The same for a weld (RWeldGroups.cpp), one rigid body made of several: its members'
// contacts with one body facing one way bounce as one impact, through the centre of their
// leading points, as a compound's children's do; the weld's rows carry the impulse to the
// members (RJointImpacts.cpp). Bounced one contact after another, a welded pair landing
// flat left turning at 2.3 rad/s. The joined row keeps that point and normal whenever
// within the step it meets (ImpactGeometry, which looks at one manifold, would find its own
// contact's alone).
void RContactSolver::JoinWeldImpacts(const RStepBodies& bodies, std::uint32_t first, std::uint32_t last) {
  auto group = [this](std::uint32_t i) -> std::uint64_t {
    const std::uint32_t g = m_in->welds.WeldOf(i);
    if (g == RWeldGroups::kNoWeld) return i;
    return std::uint64_t(m_in->welds.Root(g)) | (std::uint64_t(1) << 32);
  };
  for (std::uint32_t k0 = first; k0 < last; ++k0) {
    const RContact& c0 = m_in->sweep.Contacts()[m_blockContact[k0]];
    if (!m_in->welds.Welded(c0.a) && !m_in->welds.Welded(c0.b)) continue;
    if (!std::isfinite(m_impacts[k0].gap) || m_impacts[k0].joined) continue;  // (joined already)
    const std::uint64_t ga = group(c0.a), gb = group(c0.b);
    if (ga == gb) continue;
    const RVec3& n = c0.manifold.normal;
    // The contacts of the same two (the weld on the same side), facing the same way; the
    // deepest leads.
    std::uint32_t lead = k0;
    int others = 0;
    for (std::uint32_t k = k0 + 1; k < last; ++k) {
      const RContact& c = m_in->sweep.Contacts()[m_blockContact[k]];
      if (group(c.a) != ga || group(c.b) != gb || c.manifold.normal.dot(n) < kFaceContactCos) continue;
      if (!std::isfinite(m_impacts[k].gap)) continue;
      ++others;
      if (m_impacts[k].gap < m_impacts[lead].gap) lead = k;
    }
    if (others == 0) continue;
    RImpactRow& r = m_impacts[lead];
    RVec3 sum = RVec3::Zero();
    int count = 0;
    for (std::uint32_t k = k0; k < last; ++k) {
      const RContact& c = m_in->sweep.Contacts()[m_blockContact[k]];
      if (group(c.a) != ga || group(c.b) != gb || c.manifold.normal.dot(n) < kFaceContactCos) continue;
      if (!std::isfinite(m_impacts[k].gap)) continue;
      const RContactManifold& m = c.manifold;
      for (int q = 0; q < m.pointCount; ++q) {
        if (m.points[q].separation <= r.gap + m_in->settings.penetrationSlop) sum += m.points[q].position, ++count;
      }
      if (k != lead) m_impacts[k].gap = std::numeric_limits<RScalar>::infinity();
    }
    if (count == 0) continue;
    const RContact& c = m_in->sweep.Contacts()[m_blockContact[lead]];
    const RVec3 centre = sum / count;
    r.rA = centre - bodies[c.a].m_x_W, r.rB = centre - bodies[c.b].m_x_W;
    SetDirection(r.normal, c.manifold.normal, r.rA, r.rB, m_solverBodies[c.a], m_solverBodies[c.b]);
    r.joined = true;
  }
}

// An impact row's approach speed at the centre of its manifold's leading points is the mean
// of their rows' speeds (a speed is linear in the point), so it is no faster than the
// fastest row's; half the threshold leaves room for rounding (with no threshold there is
// no room: every island has its impact rows). Not a number: the impact phase decides.
bool RContactSolver::MayImpact(std::size_t island) const {
  if (!(m_in->settings.restitutionThreshold > 0)) return true;
  const RScalar floor = RScalar(-0.5) * m_in->settings.restitutionThreshold;
  const auto [rowsFirst, rowsLast] = IslandRows(island);
  for (std::uint32_t i = rowsFirst; i < rowsLast; ++i) {
    const RContactRow& r = m_rows[i];
    const RSolverBody& sa = m_solverBodies[r.a];
    const RSolverBody& sb = m_solverBodies[r.b];
    if (!(Speed(r.n, sa.v, sa.w, sb.v, sb.w) >= floor)) return true;
  }
  return false;
}

// After the island's impacts: which speculative rows keep their targets, and the arms of
// the rows of bodies that impacted (with no impact row, deferN stays 0 and the arms as built).
void RContactSolver::ShiftArmsAfterImpacts(RScalar dt, std::size_t island) {
  const auto [first, last] = m_blockIslands[island];
  // A manifold whose impact the narrow phase, run again along the motion, found not to
  // happen within this step keeps no speculative rows: their linear prediction from the
  // start of the step (which said it would) would stop the bodies short, an inelastic
  // collision that never happened. Points already touching keep their rows.
  for (std::uint32_t k = first; k < last; ++k) {
    const RImpactRow& impact = m_impacts[k];
    if (!impact.miss || impact.lambdaN != 0) continue;
    const RBlock& blk = m_blocks[k];
    for (int i = 0; i < blk.count; ++i) {
      RContactRow& r = m_rows[blk.first + i];
      if (r.gap > 0 && r.lambdaN == 0) r.target = kNever;
    }
  }
  // Bodies that impacted move with their piecewise path's velocity, deferV less than the
  // velocity after the impacts that the contact phase works on; the end of the step needs
  // the difference to predict which contacts are then closed.
  const auto [rowsFirst, rowsLast] = IslandRows(island);
  for (std::uint32_t i = rowsFirst; i < rowsLast; ++i) {
    RContactRow& r = m_rows[i];
    r.deferN = r.n.d.dot(m_solverBodies[r.b].deferV - m_solverBodies[r.a].deferV);
  }
  // The contact phase's impulses change the velocities after the impacts, and a body that
  // impacted moves with them on its post-impact path, which, run back to the start of the
  // step, passes through x - dt deferV, not through its centre x: the body gets their
  // moment about that point (the spin added with the deferred impulse in ReportIsland, which
  // keeps angular momentum exact). So they are solved with the lever arms they act with,
  // r + dt deferV. Solved with r, an impulse that only slows an approach also gave the
  // body a spin of dt deferV x J that no row had weighed, whatever its energy: a 0.4 m box
  // at 1.6 km/s glancing off a static sphere was still closing on it after the bounce, the
  // speculative row stopped that with its arm 2.2 m short, and the box left the step with
  // 2.2e8 J of spin from 1.2e7 J (the seed-3 world of broadphase_test reached 1e221 J in
  // 12 steps). The shift lies along the impacts' impulses, so a frictionless impact along
  // a row's normal (a box landing flat) leaves the row's angular terms as they were.
  // Position correction shares the rows' directions and sees the same arms (it moves
  // positions only: no energy).
  // A body with linear locks gets the moment of the shift only for the impulse's free part:
  // along a locked axis the lock's reaction cancels the impulse at the body's centre, which
  // moved with it, and the spin it is handed is dt deferV x (its velocity change times its
  // mass), the free part alone. Solved with the whole impulse's moment, the rows weighed a
  // spin the body never got (a crate locked on x, squeezed by a kinematic paddle along x,
  // left a step at 515 rad/s where the solve had 20).
  auto shiftArms = [this, dt](RDirection& dir, const RVec3& rA, const RVec3& rB, std::uint32_t a, std::uint32_t b) {
    const RSolverBody& sa = m_solverBodies[a];
    const RSolverBody& sb = m_solverBodies[b];
    const RVec3& d = dir.d;
    const RVec3 shiftA = dt * sa.deferV, shiftB = dt * sb.deferV;
    dir.rAxd = sa.linLocked ? RVec3(rA.cross(d) + shiftA.cross(d.cwiseProduct(sa.linMask))) : RVec3((rA + shiftA).cross(d));
    dir.rBxd = sb.linLocked ? RVec3(rB.cross(d) + shiftB.cross(d.cwiseProduct(sb.linMask))) : RVec3((rB + shiftB).cross(d));
    SetEffectiveMass(dir, sa, sb);
  };
  // A body that turned at an impact within the step has the inverse inertia of its
  // orientation then (TurnTo), which the contact phase's impulses act with.
  auto deferred = [this](std::uint32_t i) { return !m_solverBodies[i].deferV.isZero(0) || m_solverBodies[i].turned; };
  for (std::uint32_t i = rowsFirst; i < rowsLast; ++i) {
    RContactRow& r = m_rows[i];
    if (!deferred(r.a) && !deferred(r.b)) continue;
    shiftArms(r.n, r.rA, r.rB, r.a, r.b);
    if (!(r.n.k > 0)) r.target = kNever, r.pseudoTarget = 0;  // as BuildContactRows
  }
  for (std::uint32_t k = first; k < last; ++k) {
    RBlock& blk = m_blocks[k];
    const std::uint32_t a = m_rows[blk.first].a, b = m_rows[blk.first].b;
    if (!deferred(a) && !deferred(b)) continue;
    for (RDirection& t : blk.t) shiftArms(t, blk.rA, blk.rB, a, b);
    if (m_solverBodies[a].turned || m_solverBodies[b].turned) {
      blk.twistIA = m_solverBodies[a].invI * blk.normal, blk.twistIB = m_solverBodies[b].invI * blk.normal;
      blk.kTwist = blk.normal.dot(blk.twistIA) + blk.normal.dot(blk.twistIB);
    }
  }
}

// One manifold's normal rows: the block's minimum-norm answer when it pushes at every point,
// else one point at a time. On the velocities (towards the rows' targets, impulses lambdaN)
// or on the pseudo-velocities of position correction (pseudoTarget, lambdaP).
RScalar RContactSolver::SolveNormalBlock(RBlock& blk, RContactRow* rows, RPhase phase) {
  const bool pseudo = phase == RPhase::kPosition;
  RSolverBody& sa = m_solverBodies[rows[0].a];
  RSolverBody& sb = m_solverBodies[rows[0].b];
  RVec3& va = pseudo ? sa.vp : sa.v;
  RVec3& wa = pseudo ? sa.wp : sa.w;
  RVec3& vb = pseudo ? sb.vp : sb.v;
  RVec3& wb = pseudo ? sb.wp : sb.w;
  auto lambda = [phase](RContactRow& r) -> RScalar& { return Lambda(r, phase); };
  auto target = [phase](const RContactRow& r) { return Target(r, phase); };
  if (phase != RPhase::kVelocity) {
    // Most contacts need no position correction, and many are not in contact at the end of
    // the step: nothing to do unless some row does or did.
    bool active = false;
    for (int i = 0; i < blk.count; ++i) active = active || target(rows[i]) > 0 || lambda(rows[i]) > 0 || (phase == RPhase::kEnd && target(rows[i]) == 0);
    if (!active) return 0;
  }
  constexpr RScalar kAtTarget = 1e-12;  // m/s: a row this close to its target is at it
  RScalar change = 0;
  bool allTargets = true;
  for (int i = 0; i < blk.count; ++i) allTargets = allTargets && target(rows[i]) != kNever;
  if (blk.useBlock && allTargets) {
    Eigen::Matrix<RScalar, 4, 1> rhs = Eigen::Matrix<RScalar, 4, 1>::Zero();
    for (int i = 0; i < blk.count; ++i) rhs[i] = target(rows[i]) - Speed(rows[i].n, va, wa, vb, wb);
    // Already solved, to the passes' tolerance (kConverged): every pushing row at its
    // target, every other at or above it. The block's answer would change its rows' speeds
    // by no more than that; a resting manifold (warm-started to 1e-13 m/s) needs neither
    // the answer nor the inverse it takes.
    bool solved = true;
    for (int i = 0; i < blk.count; ++i) {
      solved = solved && (lambda(rows[i]) > 0 ? std::abs(rhs[i]) <= kAtTarget : rhs[i] <= kAtTarget);
    }
    if (solved) return 0;
    if (blk.inverse == 0) blk.inverse = BlockInverse(blk) ? 2 : 1;
    const Eigen::Matrix<RScalar, 4, 1> delta = blk.pinv * rhs;
    bool valid = true;
    for (int i = 0; i < blk.count; ++i) valid = valid && lambda(rows[i]) + delta[i] >= 0;
    if (valid) {
      for (int i = 0; i < blk.count; ++i) {
        lambda(rows[i]) += delta[i];
        if (delta[i] != 0) Push(rows[i].n, delta[i], sa, sb, va, wa, vb, wb);
        change = std::max(change, std::abs(delta[i]) * rows[i].n.k);
      }
      // Not at its targets when solved: never reported as no change (SolveIslandBlocks'
      // settled), even if the answer rounded to nothing.
      return std::max(change, std::numeric_limits<RScalar>::denorm_min());
    }
  }
  bool missed = false;
  for (int i = 0; i < blk.count; ++i) {
    RContactRow& r = rows[i];
    if (!(r.n.k > 0)) continue;  // no effective mass: see BuildContactRows
    const RScalar miss = target(r) - Speed(r.n, va, wa, vb, wb);
    // A row off its target by more than kAtTarget whose impulse rounds to no change (a
    // heavy body's impulse, 1e7 N s and more, has ulps of 1e-9 m/s of the light body's
    // speed) is not at its target either: see the block above.
    missed = missed || (lambda(r) > 0 ? std::abs(miss) > kAtTarget : miss > kAtTarget);
    const RScalar l = std::max(lambda(r) + miss / r.n.k, RScalar(0));
    const RScalar d = l - lambda(r);
    lambda(r) = l;
    if (d != 0) Push(r.n, d, sa, sb, va, wa, vb, wb);
    change = std::max(change, std::abs(d) * r.n.k);
  }
  return missed ? std::max(change, std::numeric_limits<RScalar>::denorm_min()) : change;
}

}  // namespace REngine
