// The island direct solve: islands of contact rows solved exactly by an active-set method
// on their dense matrix (RContactSolver::LayOutIslands, SolveIslandDirect).
#include "solver/RContactSolver.h"

#include <REnginePhysics/RJobSystem.h>

#include "pairs/RPairSweep.h"
#include "solver/RSolverRows.h"
#include "world/RStepBodies.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

namespace {

// The change of row i's normal velocity per unit normal impulse at row j: the (i, j) entry
// of the contact system's matrix J M^-1 J^T, from the bodies the two rows share (a static
// body's inverse mass and inertia are zero, so it couples nothing).
template <class Row, class Body>
RScalar Coupling(const Row& ri, const Row& rj, const Body& ai, const Body& bi) {
  const RScalar dd = ri.n.d.dot(rj.n.d);
  const RScalar la = LinearCoupling(ai, ri.n.d, rj.n.d, dd), lb = LinearCoupling(bi, ri.n.d, rj.n.d, dd);
  RScalar k = 0;
  if (ri.a == rj.a) k += la + ri.n.rAxd.dot(rj.n.iA);
  if (ri.a == rj.b) k -= la + ri.n.rAxd.dot(rj.n.iB);
  if (ri.b == rj.a) k -= lb + ri.n.rBxd.dot(rj.n.iA);
  if (ri.b == rj.b) k += lb + ri.n.rBxd.dot(rj.n.iB);
  return k;
}

// In-place Cholesky factorisation L L^T of a symmetric positive definite m x m matrix,
// row-major with leading dimension ld, lower triangle, that skips the zeros before each
// row's first non-zero (first[i] <= i): the factor keeps that envelope, so a chain of
// manifolds (a stack: each couples only with its neighbours) costs O(m b^2) for bandwidth b
// instead of O(m^3). False if the matrix is not positive definite.
bool EnvelopeCholesky(RScalar* M, int m, int ld, const int* first, RScalar* inverseDiagonal) {
  for (int j = 0; j < m; ++j) {
    RScalar* Lj = M + j * ld;
    for (int i = first[j]; i <= j; ++i) {
      const RScalar* Li = M + i * ld;
      RScalar s = Lj[i];
      for (int k = std::max(first[i], first[j]); k < i; ++k) s -= Lj[k] * Li[k];
      if (i < j) {
        Lj[i] = s * inverseDiagonal[i];
      } else {
        if (!(s > 0)) return false;
        Lj[j] = std::sqrt(s);
        inverseDiagonal[j] = 1 / Lj[j];
      }
    }
  }
  return true;
}
// Solves L L^T x = x in place with the factor above.
void EnvelopeCholeskySolve(const RScalar* L, int m, int ld, const int* first, RScalar* x) {
  for (int i = 0; i < m; ++i) {
    RScalar s = x[i];
    for (int k = first[i]; k < i; ++k) s -= L[i * ld + k] * x[k];
    x[i] = s / L[i * ld + i];
  }
  for (int i = m - 1; i >= 0; --i) {
    x[i] /= L[i * ld + i];
    for (int k = first[i]; k < i; ++k) x[k] -= L[i * ld + k] * x[i];
  }
}

}  // namespace

// Islands (bodies connected through contacts; static bodies connect nothing) of several
// manifolds and at most kDirectRows rows get their normal impulses solved exactly after the
// iterations: the linear complementarity problem v = b + K lambda >= target, lambda >= 0,
// one of the two tight per row, by an active-set method on the island's dense matrix K.
// Sequential impulses pass momentum along a chain a fraction at a time, as small as the
// mass ratio: 1000 kg on a 1 kg box takes thousands of passes to hold and sinks through it
// meanwhile; the direct solve holds it exactly in the first step. Friction keeps its
// iterated impulses, clamped again to the new cones. Larger islands (a whole pile) keep
// the iterated answer: a dense solve grows as the cube of the rows.
void RContactSolver::LayOutIslands(const RStepBodies& bodies) {
  const std::size_t n = bodies.size();
  m_islandSets.Reset(n);
  m_rowStart.resize(m_in->sweep.Contacts().size());
  m_inRows.assign(n, 0);
  std::uint32_t blockCount = 0, warmCount = 0;
  constexpr std::size_t kWarmAhead = 16;  // entries: four contacts' manifolds
  // Each contact alone, as tasks: whether it is resolved, and where last step's warm starts
  // of its pair begin (searched in the contacts' order: the rows are built island by
  // island, where a search from the last contact's entries would cross the list each time).
  ParallelRanges(m_in->jobs, m_in->sweep.Contacts().size(), m_in->tasks, 256, [&](std::size_t c0, std::size_t c1, std::size_t) {
    std::size_t warmFrom = 0;
    for (std::size_t ci = c0; ci < c1; ++ci) {
      // The search reads on from the last contact's entries, a manifold's worth (four
      // entries, 512 bytes) a contact: the stream prefetch stops at every page, so the next
      // pages' lines are asked for a few contacts ahead.
      for (std::size_t w = warmFrom + kWarmAhead; w < std::min(warmFrom + kWarmAhead + 4, m_warm.size()); ++w) {
        __builtin_prefetch(&m_warm[w].pair);
      }
      RContact& c = m_in->sweep.SolverContact(ci);
      // A manifold without points (the narrow phase hit its iteration cap) gives no rows:
      // its impact point and centroid would be 0/0; nor do separations that are not
      // numbers (see ImpactGeometry), which leave no point within the slop of the deepest.
      c.resolved = m_in->sweep.RespondsAt(c.a) && m_in->sweep.RespondsAt(c.b) && !(m_in->sweep.ImmovableAt(c.a) && m_in->sweep.ImmovableAt(c.b)) &&
                   c.manifold.pointCount > 0 && LeadingPoints(c.manifold).count > 0 &&
                   (!m_in->materials.Active() || m_in->materials.At(static_cast<std::uint32_t>(ci)).enabled);
      if (!c.resolved) continue;
      warmFrom = FindWarmStarts(m_warm, PairKey(c.handleA.index, c.handleB.index), warmFrom);
      m_rowStart[ci].warmFound = static_cast<std::uint32_t>(warmFrom);
    }
  });
  m_warmPairsIncrease = true;
  std::uint64_t lastPair = 0;
  for (std::uint32_t ci = 0; ci < m_in->sweep.Contacts().size(); ++ci) {
    const RContact& c = m_in->sweep.Contacts()[ci];
    if (!c.resolved) continue;
    const std::uint64_t pair = PairKey(c.handleA.index, c.handleB.index);
    if (blockCount > 0 && !(pair > lastPair)) m_warmPairsIncrease = false;
    lastPair = pair;
    m_inRows[c.a] = m_inRows[c.b] = 1;
    ++blockCount;
    // Next step's warm starts come out in the contacts' order, whichever island each
    // contact's rows are solved in.
    m_rowStart[ci].warm = warmCount;
    warmCount += static_cast<std::uint32_t>(c.manifold.pointCount);
    if (!m_in->sweep.ImmovableAt(c.a) && !m_in->sweep.ImmovableAt(c.b)) m_islandSets.Union(c.a, c.b);
  }
  // Joints join islands as contacts do; the world's end (index n) joins nothing.
  for (const RStepJoint& j : m_joints.StepJoints()) {
    const bool movesA = !bodies[j.a].Immovable(), movesB = j.b < n && !bodies[j.b].Immovable();
    m_inRows[j.a] = 1;
    if (j.b < n) m_inRows[j.b] = 1;
    if (movesA && movesB) m_islandSets.Union(j.a, j.b);
  }
  // A counting sort of the resolved contacts by their island's representative (its smallest
  // body index), each island's in the contacts' order.
  m_blockStart.assign(n + 1, 0);
  for (std::uint32_t ci = 0; ci < m_in->sweep.Contacts().size(); ++ci) {
    const RContact& c = m_in->sweep.Contacts()[ci];
    if (!c.resolved) continue;
    const std::uint32_t root = m_islandSets.Find(m_in->sweep.ImmovableAt(c.a) ? c.b : c.a);
    m_rowStart[ci].block = root;  // for now
    ++m_blockStart[root + 1];
  }
  // Joints likewise, by the island of their movable body (an island may have only joints).
  m_joints.CountIslandJoints(bodies, m_islandSets);
  m_blockIslands.clear();
  m_islandOfRoot.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (m_blockStart[i + 1] > 0 || m_joints.JointsAtRoot(i)) {
      m_islandOfRoot[i] = static_cast<std::uint32_t>(m_blockIslands.size());
      m_blockIslands.emplace_back(static_cast<std::uint32_t>(m_blockStart[i]),
                                  static_cast<std::uint32_t>(m_blockStart[i] + m_blockStart[i + 1]));
    }
    m_blockStart[i + 1] += m_blockStart[i];
  }
  m_joints.LayOutIslandJoints(bodies, m_islandSets, m_islandOfRoot, m_blockIslands.size());
  m_blockContact.resize(blockCount);
  for (std::uint32_t ci = 0; ci < m_in->sweep.Contacts().size(); ++ci) {
    if (!m_in->sweep.Contacts()[ci].resolved) continue;
    const std::uint32_t block = m_blockStart[m_rowStart[ci].block]++;
    m_rowStart[ci].block = block;
    m_blockContact[block] = ci;
  }
  std::uint32_t rowCount = 0;
  for (std::uint32_t block = 0; block < blockCount; ++block) {
    const std::uint32_t ci = m_blockContact[block];
    m_rowStart[ci].row = rowCount;
    rowCount += static_cast<std::uint32_t>(m_in->sweep.Contacts()[ci].manifold.pointCount);
  }
  // Resized, not cleared first: BuildContactRows writes every element whole, and a clear
  // would have resize zero 15 MB a step in a 10000-box pile.
  m_rows.resize(rowCount), m_impacts.resize(blockCount), m_blocks.resize(blockCount);
  m_rowPoint_A.resize(rowCount);
  // The bodies in rows: each movable one with its island (a counting sort by island, in
  // index order within), the static and kinematic ones apart (shared by islands, which
  // read their solver state and never write it).
  const std::size_t islands = m_blockIslands.size();
  m_islandBodyStart.assign(islands + 1, 0);
  m_immovableRowBodies.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (!m_inRows[i]) continue;
    if (m_in->sweep.ImmovableAt(i)) {
      m_immovableRowBodies.push_back(static_cast<std::uint32_t>(i));
    } else {
      ++m_islandBodyStart[m_islandOfRoot[m_islandSets.Find(static_cast<std::uint32_t>(i))] + 1];
    }
  }
  for (std::size_t k = 0; k < islands; ++k) m_islandBodyStart[k + 1] += m_islandBodyStart[k];
  m_islandBodies.resize(m_islandBodyStart[islands]);
  m_islandBodyFill.assign(m_islandBodyStart.begin(), m_islandBodyStart.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (!m_inRows[i] || m_in->sweep.ImmovableAt(i)) continue;
    m_islandBodies[m_islandBodyFill[m_islandOfRoot[m_islandSets.Find(static_cast<std::uint32_t>(i))]]++] =
        static_cast<std::uint32_t>(i);
  }
  // The islands solved directly: several manifolds (one alone is already solved exactly by
  // its block), at most kDirectRows rows; each island's blocks and their rows are one run.
  m_islandDirect.clear();
  for (const auto& [first, last] : m_blockIslands) {
    if (first == last) {  // joints only
      m_islandDirect.push_back(0);
      continue;
    }
    const std::size_t rowsFirst = m_rowStart[m_blockContact[first]].row;
    const std::size_t rowsLast = m_rowStart[m_blockContact[last - 1]].row +
                                 static_cast<std::size_t>(m_in->sweep.Contacts()[m_blockContact[last - 1]].manifold.pointCount);
    m_islandDirect.push_back(last - first > 1 && rowsLast - rowsFirst <= std::size_t(kDirectRows));
  }
}

void RContactSolver::PrepareIslandDirect(std::size_t island, RIslandScratch& sc) {
  const auto [first, last] = IslandRows(island);
  sc.index.resize(last - first);
  for (std::size_t i = 0; i < sc.index.size(); ++i) sc.index[i] = static_cast<std::uint32_t>(first + i);
  sc.kReady = false;
}

// The island's matrix K (m x m, row-major, in sc.K), assembled from the pairs of
// manifolds that share a dynamic body: the others couple nothing, and in a stack or a pile
// a manifold touches only a few of the island's others.
void RContactSolver::AssembleIslandMatrix(RIslandScratch& sc) {
  const int m = static_cast<int>(sc.index.size());
  RScalar* K = sc.K.data();
  std::fill(K, K + std::size_t(m) * m, RScalar(0));
  // Manifolds as runs of consecutive rows (rows come grouped by contact).
  sc.runs.clear();
  for (int i = 0; i < m;) {
    int j = i + 1;
    while (j < m && m_rows[sc.index[j]].contact == m_rows[sc.index[i]].contact) ++j;
    sc.runs.emplace_back(i, j);
    i = j;
  }
  // Each row's non-zero columns lie within [lo, hi]: the loops below visit only those.
  for (int i = 0; i < m; ++i) sc.lo[i] = i, sc.hi[i] = i;
  auto dynamic = [this](std::uint32_t body) { return m_solverBodies[body].invM > 0; };
  for (std::size_t s = 0; s < sc.runs.size(); ++s) {
    const RContactRow& rs = m_rows[sc.index[sc.runs[s].first]];
    for (std::size_t t = s; t < sc.runs.size(); ++t) {
      const RContactRow& rt = m_rows[sc.index[sc.runs[t].first]];
      const bool shared = ((rs.a == rt.a || rs.a == rt.b) && dynamic(rs.a)) ||
                          ((rs.b == rt.a || rs.b == rt.b) && dynamic(rs.b));
      if (!shared) continue;
      for (int i = sc.runs[s].first; i < sc.runs[s].second; ++i) {
        const RContactRow& ri = m_rows[sc.index[i]];
        const RSolverBody& sa = m_solverBodies[ri.a];
        const RSolverBody& sb = m_solverBodies[ri.b];
        for (int j = sc.runs[t].first; j < sc.runs[t].second; ++j) {
          const RScalar k = Coupling(ri, m_rows[sc.index[j]], sa, sb);
          K[i * m + j] = k;
          K[j * m + i] = k;
        }
        const int first = sc.runs[t].first, last = sc.runs[t].second - 1;
        sc.lo[i] = std::min(sc.lo[i], first), sc.hi[i] = std::max(sc.hi[i], last);
        for (int j = first; j <= last; ++j) {
          sc.lo[j] = std::min(sc.lo[j], sc.runs[s].first);
          sc.hi[j] = std::max(sc.hi[j], sc.runs[s].second - 1);
        }
      }
    }
  }
  sc.kReady = true;
}

// The active-set solve of one island's normal rows (sc.index), on the velocities or on
// the pseudo-velocities. Applies the answer and returns true if it converged; otherwise
// leaves the iterated impulses as they are.
bool RContactSolver::SolveIslandDirect(RPhase phase, RIslandScratch& sc) {
  const bool pseudo = phase == RPhase::kPosition;
  const int m = static_cast<int>(sc.index.size());
  const int ld = m;
  sc.K.resize(std::size_t(kDirectRows) * kDirectRows);
  sc.L.resize(std::size_t(kDirectRows) * kDirectRows);
  sc.b.resize(kDirectRows), sc.x.resize(kDirectRows), sc.active.resize(kDirectRows), sc.dropped.resize(kDirectRows);
  sc.map.resize(kDirectRows), sc.envelope.resize(kDirectRows);
  sc.lo.resize(kDirectRows), sc.hi.resize(kDirectRows);
  sc.columnsFrom.resize(kDirectRows), sc.columnsTo.resize(kDirectRows);
  sc.invDiag.resize(kDirectRows), sc.residual.resize(kDirectRows);
  RScalar* K = sc.K.data();
  RScalar* b = sc.b.data();
  RScalar* x = sc.x.data();
  auto target = [phase](const RContactRow& r) { return Target(r, phase); };
  auto lambda = [phase](RContactRow& r) -> RScalar& { return Lambda(r, phase); };
  // An island the iterations left solved (a row that pushes is at its target, one that
  // does not is at or above it) is left alone. Only to rounding: with a looser test
  // (1e-6 m/s) a 1000 kg box on a 1 kg one, skipped step after step, lost its hold after
  // 170 steps and sank through.
  constexpr RScalar kSolved = kDirectSolved;  // m/s
  RScalar worst = 0;
  bool anyActive = false;
  for (int i = 0; i < m; ++i) {
    RContactRow& r = m_rows[sc.index[i]];
    const RSolverBody& sa = m_solverBodies[r.a];
    const RSolverBody& sb = m_solverBodies[r.b];
    const RScalar v = pseudo ? Speed(r.n, sa.vp, sa.wp, sb.vp, sb.wp)
                             : Speed(r.n, sa.v, sa.w, sb.v, sb.w);
    b[i] = v;  // for now; b proper below
    const RScalar miss = target(r) - v;
    worst = std::max(worst, lambda(r) > 0 ? std::abs(miss) : miss);
    sc.active[i] = lambda(r) > 0 || miss > 0;
    sc.dropped[i] = 0;
    anyActive = anyActive || sc.active[i];
  }
  if (!anyActive || worst <= kSolved) return true;
  if (!sc.kReady) AssembleIslandMatrix(sc);
  // b: the velocity each row would have with none of the island's normal impulses.
  for (int i = 0; i < m; ++i) {
    RScalar s = b[i];
    for (int j = sc.lo[i]; j <= sc.hi[i]; ++j) s -= K[i * ld + j] * lambda(m_rows[sc.index[j]]);
    b[i] = s;
  }
  RScalar maxDiag = 0;
  for (int i = 0; i < m; ++i) maxDiag = std::max(maxDiag, K[i * ld + i]);
  // Four points of one face constrain three degrees of freedom: K is only semi-definite. A
  // relative 1e-9 on the diagonal makes it definite and picks (nearly) the minimum-norm
  // impulses among the equivalent ones; it costs a velocity error of 1e-9 of the impulse's.
  const RScalar ridge = 1e-9 * maxDiag;
  constexpr RScalar kTolerance = 1e-9;  // m/s: a violation smaller than this is rounding
  constexpr int kRounds = 16;
  const int* map = sc.map.data();
  for (int round = 0; round < kRounds; ++round) {
    int na = 0;
    for (int i = 0; i < m; ++i) {
      if (sc.active[i]) sc.map[na++] = i;
    }
    RScalar* L = sc.L.data();
    int* envelope = sc.envelope.data();
    for (int p = 0; p < na; ++p) {
      // Active rows before p whose columns may be non-zero: from the first at or after lo.
      const int start = static_cast<int>(std::lower_bound(map, map + p, sc.lo[map[p]]) - map);
      envelope[p] = p;
      for (int q = start; q <= p; ++q) {
        const RScalar k = K[map[p] * ld + map[q]];
        L[p * na + q] = k;
        if (k != 0 && q < envelope[p]) envelope[p] = q;
      }
      L[p * na + p] += ridge;
    }
    if (!EnvelopeCholesky(L, na, na, envelope, sc.invDiag.data())) return false;
    for (int p = 0; p < na; ++p) {
      const RContactRow& r = m_rows[sc.index[sc.map[p]]];
      x[p] = target(r) - b[sc.map[p]];
    }
    EnvelopeCholeskySolve(L, na, na, envelope, x);
    // Iterative refinement against K itself: the ridge biases the answer in the directions
    // of K whose eigenvalue s is small against it (a heavy body's, about 1/M), and each
    // correction through the same factor multiplies that bias by ridge / (s + ridge). The
    // light body's directions converge at once; at 1:1e7 it takes 5 to 10 corrections, at
    // 1:1e9 about 34 (x0.67 each); without them the light box is squeezed out. Corrections
    // go on while the velocity residual is above rounding (1e-12 m/s) and falls by at least
    // 5% a pass. At
    // 1:1e10 it falls by less (x0.95): the loop stops with 0.09 m/s left, and that ratio
    // breaks (README, stability envelope); a per-row ridge, tried, made stacks worse. The
    // corrections leave the null space of four coplanar points alone (its residual is 0).
    constexpr int kMaxRefinements = 64;
    constexpr RScalar kRefined = 1e-12;  // m/s
    RScalar* residual = sc.residual.data();
    RScalar previous = std::numeric_limits<RScalar>::infinity();
    // Each active row's active columns within [lo, hi]: [columnsFrom, columnsTo) of map,
    // the same every pass.
    for (int p = 0; p < na; ++p) {
      const int i = map[p];
      int q = static_cast<int>(std::lower_bound(map, map + na, sc.lo[i]) - map);
      sc.columnsFrom[p] = q;
      while (q < na && map[q] <= sc.hi[i]) ++q;
      sc.columnsTo[p] = q;
    }
    for (int pass = 0; pass < kMaxRefinements; ++pass) {
      RScalar largest = 0;
      for (int p = 0; p < na; ++p) {
        const int i = map[p];
        RScalar v = b[i];
        for (int q = sc.columnsFrom[p]; q < sc.columnsTo[p]; ++q) v += K[i * ld + map[q]] * x[q];
        residual[p] = target(m_rows[sc.index[i]]) - v;
        largest = std::max(largest, std::abs(residual[p]));
      }
      if (largest <= kRefined || !(largest < RScalar(0.95) * previous)) break;
      previous = largest;
      EnvelopeCholeskySolve(L, na, na, envelope, residual);
      for (int p = 0; p < na; ++p) x[p] += residual[p];
    }
    bool changed = false;
    RScalar most = 0;  // the largest active impulse (N s)
    for (int p = 0; p < na; ++p) {
      most = std::max(most, std::abs(x[p]));
      changed = changed || x[p] < 0;
    }
    if (changed) {
      std::fill(sc.dropped.begin(), sc.dropped.begin() + m, char(0));
      for (int p = 0; p < na; ++p) {
        if (x[p] < 0) sc.active[sc.map[p]] = false, sc.dropped[sc.map[p]] = 1;
      }
      continue;
    }
    // The rows the last change dropped for pulling come back only if they miss by more than
    // the ridge's velocity error, ridge times the impulses: a row whose pull comes from the
    // ridge (one of four coplanar points, under a 30 kg box a 2e5 N beam drives into a
    // station) misses by less than that without it, and taking it back on such a miss
    // cycles (drop, add, drop) until the rounds run out, when the island keeps its passes'
    // answer: rounding would decide the outcome (the space game 1e6 m out would part 45 m
    // from the game at the origin, on a miss of 1.2e-9 m/s against a tolerance of 1e-9).
    const RScalar droppedTolerance = std::max(kTolerance, ridge * most);
    for (int i = 0; i < m; ++i) {
      if (sc.active[i]) continue;
      RScalar v = b[i];
      for (int p = static_cast<int>(std::lower_bound(map, map + na, sc.lo[i]) - map);
           p < na && map[p] <= sc.hi[i]; ++p) {
        v += K[i * ld + map[p]] * x[p];
      }
      const RContactRow& r = m_rows[sc.index[i]];
      if (v < target(r) - (sc.dropped[i] ? droppedTolerance : kTolerance)) sc.active[i] = true, changed = true;
    }
    if (changed) continue;
    // Converged: apply the differences.
    int p = 0;
    for (int i = 0; i < m; ++i) {
      RContactRow& r = m_rows[sc.index[i]];
      const RScalar next = sc.active[i] ? x[p++] : RScalar(0);
      RScalar& current = lambda(r);
      const RScalar d = next - current;
      current = next;
      if (d == 0) continue;
      RSolverBody& sa = m_solverBodies[r.a];
      RSolverBody& sb = m_solverBodies[r.b];
      if (pseudo) {
        Push(r.n, d, sa, sb, sa.vp, sa.wp, sb.vp, sb.wp);
        continue;
      }
      Push(r.n, d, sa, sb, sa.v, sa.w, sb.v, sb.w);
    }
    // Friction back inside the cones of the new normal impulses.
    if (!pseudo) {
      for (int i = 0; i < m; ++i) {
        const std::uint32_t blk = m_rows[sc.index[i]].block;
        if (i == 0 || blk != m_rows[sc.index[i - 1]].block) SolvePatch(m_blocks[blk], true, phase);
      }
    }
    return true;
  }
  return false;
}

}  // namespace REngine
