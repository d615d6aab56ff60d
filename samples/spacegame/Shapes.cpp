#include "Shapes.h"

#include <REngineMath/RFunctions.h>
#include <REngineMath/RQuaternion.h>

#include <cmath>
#include <utility>
#include <vector>

namespace spacegame {
using namespace REngine;

namespace {

// A lumpy rock: points on a Fibonacci sphere, each pushed in or out by up to a quarter of the
// radius, and the whole squashed along one axis per variant, so that the three variants of a
// size read as different rocks.
RShape Rock(double radius, int variant, Rng& rng) {
  constexpr int kPoints = 28;
  const RVec3 squash = variant == 0   ? RVec3(1.0, 0.8, 1.1)
                       : variant == 1 ? RVec3(1.2, 0.9, 0.75)
                                      : RVec3(0.85, 1.05, 0.95);
  std::vector<RVec3> points;
  points.reserve(kPoints);
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int i = 0; i < kPoints; ++i) {
    const double y = 1 - 2 * (i + 0.5) / kPoints;
    const double r = std::sqrt(1 - y * y), phi = golden * i;
    const RVec3 unit(r * REngine::Cos(phi), y, r * REngine::Sin(phi));
    points.push_back(radius * rng.Uniform(0.75, 1.15) * unit.cwiseProduct(squash));
  }
  return RShape::Hull(std::move(points));
}

// Fuselage along +z: a hexagonal body that narrows to a nose at z = kShipNose and to an
// engine block at the back; wings and a fin as thin hulls beside it.
RShape Ship() {
  std::vector<RCompoundChild> parts;
  auto add = [&parts](RShape child, double density) {
    RCompoundChild c;
    c.shape = std::move(child);
    c.density = density;
    parts.push_back(std::move(c));
  };
  const double nose = GameShapes::kShipNose;
  add(RShape::Hull({{0, 0, nose},
            {-1.4, -0.9, 1},
            {1.4, -0.9, 1},
            {-1.6, 0.3, 1},
            {1.6, 0.3, 1},
            {0, 1.2, 1},
            {-1.4, -1.0, -5},
            {1.4, -1.0, -5},
            {-1.6, 0.5, -5},
            {1.6, 0.5, -5},
            {0, 1.3, -5},
            {0, -1.2, -5}}),
      600);
  add(RShape::Hull({{1.4, -0.3, 1.5},
            {1.4, 0.2, 1.5},
            {7, -0.1, -3.5},
            {7, 0.1, -3.5},
            {1.4, -0.3, -4},
            {1.4, 0.2, -4}}),
      300);
  add(RShape::Hull({{-1.4, -0.3, 1.5},
            {-1.4, 0.2, 1.5},
            {-7, -0.1, -3.5},
            {-7, 0.1, -3.5},
            {-1.4, -0.3, -4},
            {-1.4, 0.2, -4}}),
      300);
  add(RShape::Hull({{-0.15, 1.0, -1},
            {0.15, 1.0, -1},
            {-0.1, 3.2, -4.5},
            {0.1, 3.2, -4.5},
            {-0.15, 1.1, -5},
            {0.15, 1.1, -5}}),
      300);
  return RShape::Compound(std::move(parts));
}

// A wheel station about S's y axis: the hub, four spokes and a ring of twelve boxes, one
// compound body so that the game moves it as one (kinematic, spinning). Symmetric about the
// axis, so its centre of mass is on it and spinning it moves nothing but its rotation.
RShape Station() {
  std::vector<RCompoundChild> parts;
  auto add = [&parts](RShape child, const RVec3& p, const RQuat& q) {
    RCompoundChild c;
    c.shape = std::move(child);
    c.position_S = p;
    c.q_SC = q;
    parts.push_back(std::move(c));
  };
  add(RShape::Cylinder(6, GameShapes::kStationHubHalfHeight), RVec3::Zero(), RQuat::Identity());
  const double R = GameShapes::kStationRingRadius;
  constexpr int kSegments = 12;
  const double halfChord = R * REngine::Sin(kPi / kSegments) / REngine::Cos(kPi / kSegments) + 0.4;  // overlap the joints
  for (int k = 0; k < kSegments; ++k) {
    const double a = 2 * kPi * k / kSegments;
    const RQuat q = REngine::QuatAxisAngle(RVec3::UnitY(), -a);
    add(RShape::Box(RVec3(2.5, GameShapes::kStationRingHalfAxial, halfChord)), q * RVec3(R, 0, 0), q);
  }
  const double spokeInner = 6, spokeOuter = R - 2.5;
  for (int k = 0; k < 4; ++k) {
    const double a = 2 * kPi * k / 4 + kPi / kSegments;
    const RQuat q = REngine::QuatAxisAngle(RVec3::UnitY(), -a);
    const double mid = 0.5 * (spokeInner + spokeOuter);
    add(RShape::Box(RVec3(0.5 * (spokeOuter - spokeInner), 1.2, 1.2)), q * RVec3(mid, 0, 0), q);
  }
  return RShape::Compound(std::move(parts));
}

// The cargo bay: an open box of triangles (floor and three walls, open towards +z), the
// station's static inside where debris comes to rest. A mesh: static geometry of any shape.
RShape Bay() {
  const double w = GameShapes::kBayHalfWidth, h = GameShapes::kBayWallHeight;
  return RShape::Mesh({{-w, 0, -w}, {w, 0, -w}, {w, 0, w}, {-w, 0, w},   // floor 0..3
                       {-w, h, -w}, {w, h, -w}, {w, h, w}, {-w, h, w}},  // wall tops 4..7
                      {{0, 2, 1}, {0, 3, 2},                             // floor
                       {0, 1, 5}, {0, 5, 4},                             // back wall (z = -w)
                       {1, 2, 6}, {1, 6, 5},                             // +x wall
                       {3, 0, 4}, {3, 4, 7}});                           // -x wall
}

}  // namespace

GameShapes MakeGameShapes(std::uint64_t seed) {
  GameShapes s;
  Rng rng(seed);
  for (int size = 0; size < kRockSizes; ++size)
    for (int v = 0; v < kRockVariants; ++v)
      s.rocks[size][v] = PrepareShape(Rock(kRockRadius[size], v, rng));
  s.ship = PrepareShape(Ship());
  s.station = PrepareShape(Station());
  s.bay = PrepareShape(Bay());
  s.crate = PrepareShape(RShape::Box(RVec3::Constant(1.0)));
  s.missile = PrepareShape(RShape::Capsule(0.35, 1.4));
  s.debris = PrepareShape(RShape::Box(RVec3(0.45, 0.3, 0.2)));
  return s;
}

}  // namespace spacegame
