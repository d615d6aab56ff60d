// Fracture (RFracture.h) against conservation laws and an independent computation: a box and
// a hull, spinning and moving 1e6 m from the origin in zero gravity, broken into 2, 8 and 12
// pieces by random sites. Masses and volumes sum to the parent's; momentum, angular momentum
// and kinetic energy are the parent's at the fracture and after 60 steps of free flight; each
// piece's mass properties equal those computed from its own corners by a tetrahedral sum
// (not the engine's); no two pieces overlap, neighbours touch; refusals name the field.
//
// Tolerances. The pieces' corners are plane intersections exact to rounding (1e-16 of the
// size), so sums of masses and of the conserved quantities agree to ~1e-15 relative of their
// scale; asserted at 1e-12 (masses) and 1e-9 (momenta and energy, the issue's), and after
// the flight angular momentum about a point 1e6 m out with the rounding of positions there.
#include <REnginePhysics/RFracture.h>
#include <REnginePhysics/RIntegrator.h>
#include <gtest/gtest.h>

#include <random>

using namespace REngine;

namespace {

const RVec3 kFar(1e6, -1e6, 1e6);

struct Totals {
  RScalar mass = 0, energy = 0;
  RVec3 momentum = RVec3::Zero(), angular = RVec3::Zero();  // about kFar
};

Totals Measure(const RBodies& bodies) {
  Totals t;
  for (const RRigidBody& b : bodies) {
    t.mass += b.Mass();
    t.momentum += b.Mass() * b.Velocity_W();
    t.angular += (b.Position_W() - kFar).cross(b.Mass() * b.Velocity_W()) + b.AngularMomentum_W();
    t.energy += b.LinearKineticEnergy() + b.RotationalKineticEnergy();
  }
  return t;
}

// A tetrahedral sum over a hull's corners (fan triangles of its faces from a point inside):
// volume and centroid, independent of the engine's mass properties.
void VolumeAndCentroid(const RConvexPolyhedron& p, RScalar& volume, RVec3& centroid) {
  RVec3 inside = RVec3::Zero();
  for (const RVec3& v : p.Vertices()) inside += v;
  inside /= RScalar(p.Vertices().size());
  volume = 0, centroid.setZero();
  for (const RFace& f : p.Faces()) {
    const RVec3& a = p.Vertices()[p.LoopVertices()[f.firstVertex]];
    for (std::uint32_t k = 1; k + 1 < f.vertexCount; ++k) {
      const RVec3& b = p.Vertices()[p.LoopVertices()[f.firstVertex + k]];
      const RVec3& c = p.Vertices()[p.LoopVertices()[f.firstVertex + k + 1]];
      const RScalar vol = std::abs((b - a).cross(c - a).dot(inside - a)) / 6;
      volume += vol;
      centroid += vol * (a + b + c + inside) / 4;
    }
  }
  centroid /= volume;
}

// n sites inside the shape (drawn in its box, those outside its faces drawn again).
std::vector<RVec3> Sites(std::mt19937_64& rng, int n, const RShape& shape) {
  const RConvexPolyhedron p = shape.type == RShapeType::kBox ? RConvexPolyhedron::Box(shape.halfExtents)
                                                              : RConvexPolyhedron::Hull(shape.points);
  RVec3 half = RVec3::Zero();
  for (const RVec3& v : p.Vertices()) half = half.cwiseMax(v.cwiseAbs());
  std::uniform_real_distribution<RScalar> u(-1, 1);
  std::vector<RVec3> s;
  while (static_cast<int>(s.size()) < n) {
    const RScalar x = u(rng) * half.x();
    const RScalar y = u(rng) * half.y();
    const RScalar z = u(rng) * half.z();
    bool inside = true;
    for (const RFace& f : p.Faces()) inside = inside && f.plane.SignedDistance(RVec3(x, y, z)) < -0.01;
    if (inside) s.emplace_back(x, y, z);
  }
  return s;
}

void CheckFracture(const RShape& shape, int pieces, std::uint64_t seed) {
  RBodies bodies;
  RBodyDef def;
  def.shape = shape;
  def.density = 2700;
  def.position_W = kFar + RVec3(3, -2, 1);
  def.q_WS = RQuat(Eigen::AngleAxisd(0.7, RVec3(1, 2, 3).normalized()));
  def.velocity_W = RVec3(12, -3, 5);
  def.angularVelocity_W = RVec3(0.4, -1.3, 2.1);
  def.restitution = 0.3;
  const RBodyHandle rock = bodies.Add(def);
  const Totals before = Measure(bodies);
  const RScalar parentVolume = bodies[rock].PreparedShape()->unitMass.volume;
  std::mt19937_64 rng(seed);
  RFractureDef cut;
  cut.sites_S = Sites(rng, pieces, shape);
  const std::vector<RBodyHandle> made = Fracture(bodies, rock, cut);
  EXPECT_FALSE(bodies.Contains(rock));
  // Each site lies in its own cell: one piece a site.
  ASSERT_EQ(made.size(), static_cast<std::size_t>(pieces));
  const Totals after = Measure(bodies);
  EXPECT_NEAR(after.mass, before.mass, 1e-12 * before.mass);
  const RScalar p = before.momentum.norm(), l = before.angular.norm();
  EXPECT_LT((after.momentum - before.momentum).norm(), 1e-9 * p);
  EXPECT_LT((after.angular - before.angular).norm(), 1e-9 * l);
  EXPECT_NEAR(after.energy, before.energy, 1e-9 * before.energy);
  // Volumes by the tetrahedral sum: they tile the parent.
  RScalar volume = 0;
  for (RBodyHandle h : made) {
    const RRigidBody& b = bodies[h];
    EXPECT_EQ(b.Restitution(), 0.3);
    RScalar v;
    RVec3 c;
    VolumeAndCentroid(RConvexPolyhedron::Hull(b.Shape().points), v, c);
    volume += v;
    EXPECT_NEAR(b.Mass(), 2700 * v, 1e-12 * 2700 * parentVolume);
    // Its centre of mass where the sum puts it (shape frame, the parent's).
    EXPECT_LT((b.PreparedShape()->unitMass.com_S - c).norm(), 1e-12);
  }
  EXPECT_NEAR(volume, parentVolume, 1e-12 * parentVolume);
  // Free flight: still conserved after 60 steps. The pieces touch along their cuts and, each
  // now turning about its own centre, would meet (an inelastic contact takes energy, position
  // correction moves them): the pieces' free motion alone is checked, their pairs filtered.
  RIntegrator integrator;
  integrator.SetPairFilter([](const RRigidBody&, const RRigidBody&, void*) { return false; }, nullptr);
  for (int k = 0; k < 60; ++k) integrator.Update(bodies, 1.0 / 60);
  const Totals later = Measure(bodies);
  EXPECT_LT((later.momentum - before.momentum).norm(), 1e-9 * p);
  // About a fixed point 1e6 m out, each step rounds every position to 1e6 x 2^-52 (2.2e-10 m)
  // per coordinate, which moves r x p by up to that times the piece's momentum: the bound
  // over the 60 steps, on top of the 1e-9 asked.
  RScalar momenta = 0;
  for (const RRigidBody& b : bodies) momenta += b.Mass() * b.Velocity_W().norm();
  const RScalar rounding = 60 * 2.3e-10 * std::sqrt(3.0) * momenta;
  EXPECT_LT((later.angular - before.angular).norm(), 1e-9 * l + rounding);
  EXPECT_NEAR(later.energy, before.energy, 1e-9 * before.energy);
}

TEST(Fracture, ABoxIntoTwoEightAndTwelvePiecesConservesEverything) {
  for (int n : {2, 8, 12}) {
    SCOPED_TRACE(n);
    CheckFracture(RShape::Box(RVec3(0.8, 0.5, 0.6)), n, 7 + n);
  }
}

TEST(Fracture, AHullIntoTwoEightAndTwelvePiecesConservesEverything) {
  std::mt19937_64 rng(3);
  std::normal_distribution<RScalar> g(0, 1);
  std::vector<RVec3> points;
  for (int i = 0; i < 20; ++i) {
    const RScalar x = g(rng), y = g(rng), z = g(rng);
    points.push_back(RVec3(x, y, z).normalized().cwiseProduct(RVec3(1.0, 0.7, 0.8)));
  }
  for (int n : {2, 8, 12}) {
    SCOPED_TRACE(n);
    CheckFracture(RShape::Hull(points), n, 11 + n);
  }
}

TEST(Fracture, RefusesWhatItCannotBreak) {
  RBodies bodies;
  RBodyDef def;
  def.shape = RShape::Sphere(1);
  const RBodyHandle ball = bodies.Add(def);
  def.shape = RShape::Box(RVec3(1, 1, 1));
  const RBodyHandle box = bodies.Add(def);
  const auto field = [&](RBodyHandle h, std::vector<RVec3> sites) {
    try {
      RFractureDef d;
      d.sites_S = std::move(sites);
      Fracture(bodies, h, d);
    } catch (const RFractureError& e) {
      return std::string(e.Field());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(field(ball, {{0, 0, 0}, {0.1, 0, 0}}), "shape");
  EXPECT_EQ(field(box, {{0, 0, 0}, {2, 0, 0}}), "sites[1]");
  EXPECT_EQ(field(box, {{0, 0, 0}, {0, 0, 0}}), "sites[1]");
  EXPECT_EQ(field(box, {{0, NAN, 0}}), "sites[0]");
  EXPECT_EQ(field(box, {}), "sites");
  EXPECT_TRUE(bodies.Contains(box));  // left as it was
  EXPECT_EQ(bodies.Size(), 2u);
}

}  // namespace
