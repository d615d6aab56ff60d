#include <REnginePhysics/RConvexPolyhedron.h>
#include <REngineMath/RFunctions.h>
#include <REnginePhysics/RLimits.h>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <utility>

namespace REngine {

namespace {

// Thinnest hull accepted, as a fraction of its extent (the largest coordinate about its
// centroid): its width along every face normal must reach this. A thinner one is a needle or
// a sliver: its inertia about the long axis is tiny against the others (a needle 1e-9 thick
// dropped on the ground was flung at 16 km/s), and its face normals come from rounding. At
// 1e-4, a 100 m panel may be 1 cm thick.
constexpr RScalar kMinThickness = 1e-4;
// Every vertex on or below every face plane, to this fraction of the extent.
constexpr RScalar kInsideTolerance = 1e-9;
// Face planes closer than this (unit normals, and offsets relative to the extent) are one
// plane: 1e-9 rad is far above rounding (1e-14) and far below any modelled bevel.
constexpr RScalar kCoplanar = 1e-9;

// Newell's normal of a polygon loop: robust for nearly degenerate and non-planar loops,
// and its length is twice the polygon's area.
RVec3 NewellNormal(const std::vector<RVec3>& v, const std::uint32_t* loop, std::uint32_t n) {
  RVec3 sum = RVec3::Zero();
  for (std::uint32_t i = 0; i < n; ++i) {
    const RVec3& a = v[loop[i]];
    const RVec3& b = v[loop[(i + 1) % n]];
    sum += a.cross(b);
  }
  return sum;
}

// Owns a qhull run and frees it on every path out.
struct QhullRun {
  qhT qh;
  FILE* err;
  QhullRun() : err(std::tmpfile()) { qh_zero(&qh, err); }
  ~QhullRun() {
    int curlong = 0, totlong = 0;
    qh_freeqhull(&qh, !qh_ALL);
    qh_memfreeshort(&qh, &curlong, &totlong);
    if (err) std::fclose(err);
  }
  QhullRun(const QhullRun&) = delete;
  QhullRun& operator=(const QhullRun&) = delete;
};

}  // namespace

RConvexPolyhedron RConvexPolyhedron::Box(const RVec3& e) {
  RConvexPolyhedron p;
  p.m_boxHalf = e.cwiseAbs(), p.m_isBox = true;  // (the corners of -e are those of e)
  for (int i = 0; i < 8; ++i) {
    p.m_vertices.emplace_back((i & 1) ? e.x() : -e.x(), (i & 2) ? e.y() : -e.y(),
                              (i & 4) ? e.z() : -e.z());
  }
  // Loops counter-clockwise seen from outside (right-handed about the outward normal).
  const std::uint32_t loops[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5},   // -x, +x
                                     {0, 1, 5, 4}, {2, 6, 7, 3},   // -y, +y
                                     {0, 2, 3, 1}, {4, 5, 7, 6}};  // -z, +z
  for (int f = 0; f < 6; ++f) {
    RFace face;
    face.firstVertex = static_cast<std::uint32_t>(p.m_loops.size());
    face.vertexCount = 4;
    p.m_loops.insert(p.m_loops.end(), loops[f], loops[f] + 4);
    const int axis = f / 2;
    face.plane.normal = RVec3::Zero();
    face.plane.normal[axis] = (f % 2) ? 1 : -1;
    face.plane.offset = e[axis];
    p.m_faces.push_back(face);
  }
  p.BuildTopology();
  return p;
}

void RConvexPolyhedron::SetTriangle(const RVec3& a, const RVec3& b, const RVec3& c) {
  m_isBox = false;
  m_vertices.resize(3);
  m_vertices[0] = a, m_vertices[1] = b, m_vertices[2] = c;
  const RVec3 n = (b - a).cross(c - a).normalized();
  m_faces.resize(2);
  m_faces[0] = RFace{RPlane{n, n.dot(a)}, 0, 3};
  m_faces[1] = RFace{RPlane{-n, -n.dot(a)}, 3, 3};
  static constexpr std::uint32_t kLoops[6] = {0, 1, 2, 0, 2, 1};
  m_loops.assign(kLoops, kLoops + 6);
  static constexpr REdge kEdges[3] = {{0, 1, 0, 1}, {1, 2, 0, 1}, {0, 2, 0, 1}};
  m_edges.assign(kEdges, kEdges + 3);
  static constexpr std::uint32_t kStart[4] = {0, 2, 4, 6}, kAdjacent[6] = {1, 2, 0, 2, 0, 1};
  m_adjStart.assign(kStart, kStart + 4);
  m_adj.assign(kAdjacent, kAdjacent + 6);
  m_maxRadius = std::max({a.norm(), b.norm(), c.norm()});
}

RConvexPolyhedron RConvexPolyhedron::Hull(const std::vector<RVec3>& points) {
  if (points.size() < 4) {
    throw RHullError("a hull needs at least 4 points that are not coplanar, got " +
                     std::to_string(points.size()));
  }
  for (const RVec3& p : points) {
    if (!AllFinite(p)) throw RHullError("a hull point is not finite");
    if (!(p.cwiseAbs().maxCoeff() <= kMaxCoordinate)) {
      throw RHullError("a hull point lies beyond 1e12 m of the shape frame's origin");
    }
  }
  // Work about the centroid: a cloud 1e7 m from the origin keeps its digits.
  RVec3 centroid = RVec3::Zero();
  for (const RVec3& p : points) centroid += p;
  centroid /= static_cast<RScalar>(points.size());
  std::vector<coordT> coords;
  coords.reserve(points.size() * 3);
  RScalar extent = 0;
  for (const RVec3& p : points) {
    const RVec3 q = p - centroid;
    extent = std::max(extent, q.cwiseAbs().maxCoeff());
    coords.insert(coords.end(), {q.x(), q.y(), q.z()});
  }
  if (!(extent > 0)) throw RHullError("all hull points are the same point");

  QhullRun run;
  qhT* qh = &run.qh;
  // Default options: 3-d hull, coplanar facets merged into polygons (Qhull's 'C-0'), so a
  // box given as 8 corners plus face points yields 6 quadrilaterals, as SAT and clipping need.
  char options[] = "qhull";
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False,
                                options, nullptr, run.err);
  if (code != 0) {
    throw RHullError("the points are coplanar or collinear: a hull needs 4 points that span a "
                     "solid");
  }

  RConvexPolyhedron poly;
  // Qhull vertex -> our index, in qhull's point order (deterministic: input order).
  std::vector<int> index(points.size(), -1);
  {
    std::vector<int> used;
    vertexT* vertex;
    FORALLvertices { used.push_back(qh_pointid(qh, vertex->point)); }
    std::sort(used.begin(), used.end());
    for (int id : used) {
      index[id] = static_cast<int>(poly.m_vertices.size());
      poly.m_vertices.push_back(points[id] - centroid);
    }
  }
  // Faces: collect each facet's vertices and order them by angle about the facet's centre.
  // Facets are taken in order of their smallest vertex index for a deterministic layout.
  struct RawFace {
    std::vector<std::uint32_t> loop;
    RVec3 normal;
  };
  std::vector<RawFace> raw;
  facetT* facet;
  FORALLfacets {
    RawFace f;
    f.normal = RVec3(facet->normal[0], facet->normal[1], facet->normal[2]);
    vertexT *vertex, **vertexp;
    FOREACHvertex_(facet->vertices) {
      f.loop.push_back(static_cast<std::uint32_t>(index[qh_pointid(qh, vertex->point)]));
    }
    RVec3 c = RVec3::Zero();
    for (std::uint32_t i : f.loop) c += poly.m_vertices[i];
    c /= static_cast<RScalar>(f.loop.size());
    RVec3 u, w;
    OrthonormalBasis(f.normal.normalized(), u, w);
    std::vector<std::pair<RScalar, std::uint32_t>> byAngle;
    for (std::uint32_t i : f.loop) {
      const RVec3 d = poly.m_vertices[i] - c;
      byAngle.emplace_back(Atan2(d.dot(w), d.dot(u)), i);
    }
    // (u, w, n) is right-handed, so increasing angle is counter-clockwise seen from outside.
    std::sort(byAngle.begin(), byAngle.end());
    for (std::size_t i = 0; i < f.loop.size(); ++i) f.loop[i] = byAngle[i].second;
    // Start each loop at its smallest index (deterministic, independent of qhull's order).
    std::rotate(f.loop.begin(), std::min_element(f.loop.begin(), f.loop.end()), f.loop.end());
    raw.push_back(std::move(f));
  }
  // Qhull merges facets within its own roundoff estimate, which comes from the centred
  // coordinates and misses the rounding of the input (a box 100 m out can come back with
  // a face split in two), and a merged facet keeps vertices that are corners only to
  // rounding. Either breaks what the narrow phase relies on: strictly convex faces (for
  // clipping) and vertices that are true corners (else hill climbing can stop at a reflex
  // corner far from the maximum). So: faces whose planes agree within kCoplanar are one
  // face, and a vertex stays only where at least three distinct face planes meet.
  const std::size_t nRaw = raw.size();
  std::vector<RVec3> rawN(nRaw);
  std::vector<RVec3> rawNewell(nRaw);
  std::vector<RScalar> rawD(nRaw);
  for (std::size_t f = 0; f < nRaw; ++f) {
    rawNewell[f] = NewellNormal(poly.m_vertices, raw[f].loop.data(),
                                static_cast<std::uint32_t>(raw[f].loop.size()));
    rawN[f] = rawNewell[f].norm() > 0 ? rawNewell[f].normalized() : raw[f].normal.normalized();
    rawD[f] = rawN[f].dot(poly.m_vertices[raw[f].loop[0]]);
  }
  // Group by plane (two faces of a convex polyhedron in one plane are parts of one face).
  std::vector<std::size_t> group(nRaw);
  for (std::size_t f = 0; f < nRaw; ++f) {
    group[f] = f;
    for (std::size_t g = 0; g < f; ++g) {
      if (group[g] == g && (rawN[f] - rawN[g]).norm() <= kCoplanar &&
          std::abs(rawD[f] - rawD[g]) <= kCoplanar * extent) {
        group[f] = g;
        break;
      }
    }
  }
  // Distinct planes at each vertex.
  std::vector<std::vector<std::size_t>> planesAt(poly.m_vertices.size());
  for (std::size_t f = 0; f < nRaw; ++f) {
    for (std::uint32_t v : raw[f].loop) {
      auto& list = planesAt[v];
      if (std::find(list.begin(), list.end(), group[f]) == list.end()) list.push_back(group[f]);
    }
  }
  std::vector<int> newIndex(poly.m_vertices.size(), -1);
  std::vector<RVec3> corners;
  for (std::size_t v = 0; v < poly.m_vertices.size(); ++v) {
    if (planesAt[v].size() >= 3) {
      newIndex[v] = static_cast<int>(corners.size());
      corners.push_back(poly.m_vertices[v]);
    }
  }
  poly.m_vertices = std::move(corners);
  // One face per plane: its corners ordered by angle about their centroid (a strictly
  // convex polygon now), counter-clockwise about the area-weighted normal.
  std::vector<RawFace> faces;
  for (std::size_t g = 0; g < nRaw; ++g) {
    if (group[g] != g) continue;
    RVec3 newell = RVec3::Zero();
    std::vector<std::uint32_t> members;
    for (std::size_t f = 0; f < nRaw; ++f) {
      if (group[f] != g) continue;
      newell += rawNewell[f];
      for (std::uint32_t v : raw[f].loop) {
        if (newIndex[v] >= 0) members.push_back(static_cast<std::uint32_t>(newIndex[v]));
      }
    }
    std::sort(members.begin(), members.end());
    members.erase(std::unique(members.begin(), members.end()), members.end());
    if (members.size() < 3) continue;
    RawFace face;
    face.normal = newell.normalized();
    RVec3 c = RVec3::Zero();
    for (std::uint32_t i : members) c += poly.m_vertices[i];
    c /= static_cast<RScalar>(members.size());
    RVec3 u, w;
    OrthonormalBasis(face.normal, u, w);
    std::vector<std::pair<RScalar, std::uint32_t>> byAngle;
    for (std::uint32_t i : members) {
      const RVec3 d = poly.m_vertices[i] - c;
      byAngle.emplace_back(Atan2(d.dot(w), d.dot(u)), i);
    }
    std::sort(byAngle.begin(), byAngle.end());
    for (const auto& [angle, i] : byAngle) face.loop.push_back(i);
    std::rotate(face.loop.begin(), std::min_element(face.loop.begin(), face.loop.end()),
                face.loop.end());
    faces.push_back(std::move(face));
  }
  std::sort(faces.begin(), faces.end(),
            [](const RawFace& a, const RawFace& b) { return a.loop < b.loop; });
  for (const RawFace& f : faces) {
    RFace face;
    face.firstVertex = static_cast<std::uint32_t>(poly.m_loops.size());
    face.vertexCount = static_cast<std::uint32_t>(f.loop.size());
    poly.m_loops.insert(poly.m_loops.end(), f.loop.begin(), f.loop.end());
    const RVec3& n = f.normal;
    // The plane must support every vertex of the face: the largest offset over its loop
    // (the merged face is planar only to rounding).
    RScalar d = -std::numeric_limits<RScalar>::infinity();
    for (std::uint32_t i : f.loop) d = std::max(d, n.dot(poly.m_vertices[i]));
    face.plane = RPlane{n, d};
    poly.m_faces.push_back(face);
  }

  poly.BuildTopology();
  poly.Validate(extent);
  return poly.Transformed(RMat3::Identity(), centroid);
}

// What the narrow phase and the mass properties rely on, checked on every hull rather than
// trusted to Qhull and the merging above: unit face normals, a closed surface of the sphere's
// topology (V - E + F = 2, every edge between two faces), every vertex on or inside every
// face plane, a width along every face normal of at least kMinThickness of the extent, and
// finite mass properties of positive volume. Coplanar, collinear and needle-like clouds end
// here.
void RConvexPolyhedron::Validate(RScalar extent) const {
  const auto flat = [] {
    return RHullError("the points span no solid: the hull is flatter than 1e-4 of its size "
                      "(coplanar, collinear or needle-like points)");
  };
  if (m_faces.size() < 4 || m_vertices.size() < 4) throw flat();
  RScalar thinnest = std::numeric_limits<RScalar>::infinity();
  for (const RFace& f : m_faces) {
    if (!(std::abs(f.plane.normal.norm() - 1) <= 1e-9) || !std::isfinite(f.plane.offset)) {
      throw flat();
    }
    RScalar lowest = f.plane.offset;
    for (const RVec3& v : m_vertices) {
      const RScalar s = f.plane.SignedDistance(v);
      if (!(s <= kInsideTolerance * extent)) {
        throw RHullError("the points give no consistent convex hull (a vertex lies outside a "
                         "face): the cloud is degenerate to rounding");
      }
      lowest = std::min(lowest, f.plane.normal.dot(v));
    }
    thinnest = std::min(thinnest, f.plane.offset - lowest);
  }
  if (!(thinnest >= kMinThickness * extent)) throw flat();
  const auto V = static_cast<long>(m_vertices.size()), E = static_cast<long>(m_edges.size()),
             F = static_cast<long>(m_faces.size());
  bool closed = V - E + F == 2;
  for (const REdge& e : m_edges) closed = closed && e.f0 != e.f1;
  if (!closed) {
    throw RHullError("the points give no closed hull (V - E + F != 2): the cloud is "
                     "degenerate to rounding");
  }
  const RPolyhedronMass mass = MassProperties();
  if (!(mass.volume > 0) || !std::isfinite(mass.volume) || !AllFinite(mass.centroid) ||
      !AllFinite(mass.inertia)) {
    throw flat();
  }
}

RConvexPolyhedron RConvexPolyhedron::Transformed(const RMat3& R, const RVec3& t) const {
  RConvexPolyhedron p = *this;
  // Still Box()'s box only where nothing moved.
  p.m_isBox = m_isBox && R == RMat3::Identity() && t.isZero(0);
  for (RVec3& v : p.m_vertices) v = R * v + t;
  for (RFace& f : p.m_faces) {
    f.plane.normal = R * f.plane.normal;
    f.plane.offset += f.plane.normal.dot(t);
  }
  p.m_maxRadius = 0;
  for (const RVec3& v : p.m_vertices) p.m_maxRadius = std::max(p.m_maxRadius, v.norm());
  return p;
}

void RConvexPolyhedron::BuildTopology() {
  // Unique edges from the loops: each undirected edge is met once from each side.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> edgeIndex;
  m_edges.clear();
  for (std::uint32_t f = 0; f < m_faces.size(); ++f) {
    const RFace& face = m_faces[f];
    for (std::uint32_t i = 0; i < face.vertexCount; ++i) {
      const std::uint32_t a = m_loops[face.firstVertex + i];
      const std::uint32_t b = m_loops[face.firstVertex + (i + 1) % face.vertexCount];
      const auto key = std::minmax(a, b);
      const auto it = edgeIndex.find(key);
      if (it == edgeIndex.end()) {
        edgeIndex.emplace(key, static_cast<std::uint32_t>(m_edges.size()));
        m_edges.push_back(REdge{key.first, key.second, f, f});
      } else {
        m_edges[it->second].f1 = f;
      }
    }
  }
  // Vertex adjacency in compressed rows, neighbours sorted.
  std::vector<std::vector<std::uint32_t>> nb(m_vertices.size());
  for (const REdge& e : m_edges) {
    nb[e.v0].push_back(e.v1);
    nb[e.v1].push_back(e.v0);
  }
  m_adjStart.assign(1, 0);
  m_adj.clear();
  for (auto& list : nb) {
    std::sort(list.begin(), list.end());
    m_adj.insert(m_adj.end(), list.begin(), list.end());
    m_adjStart.push_back(static_cast<std::uint32_t>(m_adj.size()));
  }
  m_maxRadius = 0;
  for (const RVec3& v : m_vertices) m_maxRadius = std::max(m_maxRadius, v.norm());
}

// Volume integrals over the solid by the divergence theorem: fan-triangulate every face
// from its first vertex and sum the signed tetrahedra (o, a, b, c) with o a reference point
// inside (the mean vertex, which keeps the terms small far from the origin). For a
// tetrahedron with edge vectors a, b, c from o and volume V = det[a b c] / 6, the second
// moment about o is  V / 20 * (sum_i x_i x_i^T + (sum_i x_i)(sum_i x_i)^T)  over its three
// vertices x_i relative to o (Tonon 2004), so everything is exact up to rounding.
RPolyhedronMass RConvexPolyhedron::MassProperties() const {
  RVec3 o = RVec3::Zero();
  for (const RVec3& v : m_vertices) o += v;
  o /= static_cast<RScalar>(m_vertices.size());
  RScalar volume = 0;
  RVec3 firstMoment = RVec3::Zero();     // integral of (x - o) dV
  RMat3 secondMoment = RMat3::Zero();    // integral of (x - o)(x - o)^T dV
  for (const RFace& f : m_faces) {
    const RVec3 a = m_vertices[m_loops[f.firstVertex]] - o;
    for (std::uint32_t i = 1; i + 1 < f.vertexCount; ++i) {
      const RVec3 b = m_vertices[m_loops[f.firstVertex + i]] - o;
      const RVec3 c = m_vertices[m_loops[f.firstVertex + i + 1]] - o;
      const RScalar v = a.dot(b.cross(c)) / 6;
      const RVec3 s = a + b + c;
      volume += v;
      firstMoment += v * s / 4;
      secondMoment += (v / 20) * (a * a.transpose() + b * b.transpose() + c * c.transpose() +
                                  s * s.transpose());
    }
  }
  RPolyhedronMass m;
  m.volume = volume;
  // A flat polyhedron has no volume and no centroid of its own: Hull refuses it before it
  // asks (the sanitizer's float-divide-by-zero stopped a scene test here once); o stands.
  const RVec3 r = volume != 0 ? RVec3(firstMoment / volume) : RVec3::Zero();  // centroid - o
  m.centroid = o + r;
  // Covariance about the centroid (parallel axis), then inertia = tr(C) I - C.
  const RMat3 C = secondMoment - volume * r * r.transpose();
  m.inertia = C.trace() * RMat3::Identity() - C;
  return m;
}

std::uint32_t RConvexPolyhedron::SupportLinear(const RVec3* v, std::uint32_t n, const RVec3& d) {
  std::uint32_t best = 0;
  RScalar bestDot = v[0].dot(d);
  for (std::uint32_t i = 1; i < n; ++i) {
    const RScalar x = v[i].dot(d);
    if (x > bestDot) bestDot = x, best = i;
  }
  return best;
}

std::uint32_t RConvexPolyhedron::SupportHillClimb(const RVec3* v, const RVec3& d,
                                                  std::uint32_t start) const {
  // Move to the best neighbour while it beats the current vertex in (dot, -index): the pair
  // strictly increases, so the walk ends, and on a convex polyhedron a vertex no neighbour
  // beats has the maximal dot product (the simplex method's argument).
  std::uint32_t cur = start;
  RScalar curDot = v[cur].dot(d);
  for (;;) {
    std::uint32_t next = cur;
    RScalar nextDot = curDot;
    for (std::uint32_t k = m_adjStart[cur]; k < m_adjStart[cur + 1]; ++k) {
      const std::uint32_t j = m_adj[k];
      const RScalar x = v[j].dot(d);
      if (x > nextDot || (x == nextDot && j < next)) next = j, nextDot = x;
    }
    if (next == cur) return cur;
    cur = next, curDot = nextDot;
  }
}

}  // namespace REngine
