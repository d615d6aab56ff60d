// The hull builder on arbitrary point clouds: RHullError, or a polyhedron the engine can
// use (the invariants RConvexPolyhedron::Hull promises, checked independently here).
//
// Input: a mode byte, then points. Mode even: raw doubles (NaN, 1e300, subnormals).
// Mode odd: small integers on a grid of 10^-k m about an offset, which makes duplicates,
// coplanar and collinear subsets, needles and slivers common.
#include <REnginePhysics/RConvexPolyhedron.h>

#include "FuzzInput.h"

#include <algorithm>
#include <vector>

using namespace REngine;
using namespace REngine::fuzz;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const std::uint8_t mode = in.Byte();
  const int count = 4 + in.Byte() % 60;
  std::vector<RVec3> points;
  if (mode % 2 == 0) {
    for (int i = 0; i < count && !in.Empty(); ++i) points.push_back(in.RawVec());
  } else {
    const double grid = std::pow(10.0, -double(in.Byte() % 13));  // 1 m .. 1e-12 m
    RVec3 offset = in.Vec(-1e7, 1e7);
    offset *= double(in.Byte() % 2);
    for (int i = 0; i < count && !in.Empty(); ++i) {
      const double scale = (in.Byte() % 4 == 0) ? 1e6 : 1.0;  // a few far points: needles
      const auto c = [&] { return double(static_cast<std::int8_t>(in.Byte())); };
      const double x = c(), y = c(), z = c();
      points.push_back(offset + grid * scale * RVec3(x, y, z));
    }
  }
  RConvexPolyhedron h;
  try {
    h = RConvexPolyhedron::Hull(points);
  } catch (const RHullError&) {
    return 0;
  }
  // The polyhedron's own extent about its vertex mean, for the relative tolerances.
  const std::vector<RVec3>& v = h.Vertices();
  RVec3 mean = RVec3::Zero();
  for (const RVec3& p : v) mean += p;
  mean /= double(v.size());
  double extent = 0;
  for (const RVec3& p : v) extent = std::max(extent, (p - mean).cwiseAbs().maxCoeff());
  RENGINE_FUZZ_CHECK(extent > 0 && std::isfinite(extent), "extent %g", extent);
  const long V = long(v.size()), E = long(h.Edges().size()), F = long(h.Faces().size());
  RENGINE_FUZZ_CHECK(V - E + F == 2, "V %ld E %ld F %ld", V, E, F);
  for (const REdge& e : h.Edges()) RENGINE_FUZZ_CHECK(e.f0 != e.f1, "edge with one face");
  double thinnest = 1e300;
  for (const RFace& f : h.Faces()) {
    RENGINE_FUZZ_CHECK(f.vertexCount >= 3, "face of %u vertices", f.vertexCount);
    RENGINE_FUZZ_CHECK(std::abs(f.plane.normal.norm() - 1) <= 1e-9, "normal length %.17g",
                       f.plane.normal.norm());
    double lowest = f.plane.offset;
    for (const RVec3& p : v) {
      // Hull's tolerance is 1e-9 of the cloud's extent about the cloud's centroid, at most
      // twice this one; and a cloud 1e7 m out rounds n . p to ~1e-16 of |p|.
      const double s = f.plane.SignedDistance(p);
      RENGINE_FUZZ_CHECK(s <= 2e-9 * extent + 1e-15 * p.cwiseAbs().maxCoeff(),
                         "vertex %.3g outside a face (extent %.3g)", s, extent);
      lowest = std::min(lowest, f.plane.normal.dot(p));
    }
    thinnest = std::min(thinnest, f.plane.offset - lowest);
  }
  // Hull measures the width about the cloud's centroid; here the planes are those of the
  // cloud's own frame, whose rounding (1e-16 of the distance from its origin) counts.
  const double far = mean.cwiseAbs().maxCoeff();
  RENGINE_FUZZ_CHECK(thinnest >= 0.5e-4 * extent - 4e-15 * far, "thinnest %.3g of extent %.3g",
                     thinnest, extent);
  const RPolyhedronMass m = h.MassProperties();
  RENGINE_FUZZ_CHECK(m.volume > 0 && std::isfinite(m.volume) && AllFinite(m.centroid) &&
                         AllFinite(m.inertia),
                     "volume %g", m.volume);
  return 0;
}
