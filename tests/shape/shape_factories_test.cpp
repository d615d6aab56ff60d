// RShape's factories: each sets its type and exactly the fields that type reads, so a body
// made from one is the body a scene file's shape makes; a size nobody gave is refused rather
// than taken as a default, and a field the type does not read, set anyway, is refused naming
// it, by PrepareShape, RRigidBody and RBodies::Add alike.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RScene.h>
#include <REnginePhysics/RShape.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <utility>
#include <vector>

using namespace REngine;

namespace {

// Every field of two shapes, children included.
void ExpectSameShape(const RShape& a, const RShape& b, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.radius, b.radius);
  EXPECT_EQ(a.halfHeight, b.halfHeight);
  EXPECT_EQ(a.halfExtents, b.halfExtents);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.children.size(), b.children.size());
  for (std::size_t i = 0; i < a.children.size(); ++i) {
    ExpectSameShape(a.children[i].shape, b.children[i].shape, what + " child " + std::to_string(i));
    EXPECT_EQ(a.children[i].position_S, b.children[i].position_S);
    EXPECT_EQ(a.children[i].q_SC.coeffs(), b.children[i].q_SC.coeffs());
    EXPECT_EQ(a.children[i].density, b.children[i].density);
  }
}

// The field RBodyError names when `shape` is made into a body, three ways (PrepareShape,
// RRigidBody, RBodies::Add, which must then hold no body); "" when all three accept it.
std::string RefusedField(const RShape& shape) {
  std::string prepared, constructed, added;
  try {
    PrepareShape(shape);
  } catch (const RBodyError& e) {
    prepared = e.Field();
  }
  RBodyDef def;
  def.shape = shape;
  def.kind = RBodyKind::kStatic;  // (a mesh is for static and kinematic bodies)
  try {
    RRigidBody body(def);
  } catch (const RBodyError& e) {
    constructed = e.Field();
  }
  RBodies bodies;
  try {
    bodies.Add(def);
  } catch (const RBodyError& e) {
    added = e.Field();
    EXPECT_EQ(bodies.Size(), 0u);
  }
  EXPECT_EQ(prepared, constructed);
  EXPECT_EQ(prepared, added);
  return prepared;
}

RShape UnitCube() {
  std::vector<RVec3> corners;
  for (int i = 0; i < 8; ++i) corners.emplace_back(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  return RShape::Hull(corners);
}

RShape Square() {
  return RShape::Mesh({RVec3(-1, 0, -1), RVec3(1, 0, -1), RVec3(1, 0, 1), RVec3(-1, 0, 1)}, {{{0, 2, 1}}, {{0, 3, 2}}});
}

RCompoundChild Child(RShape shape, const RVec3& position_S, RScalar density = 1) {
  RCompoundChild c;
  c.shape = std::move(shape);
  c.position_S = position_S;
  c.density = density;
  return c;
}

}  // namespace

// Each factory sets its type and its own fields, and leaves every other field as RShape
// leaves it (0, empty); the shape's volume is the solid's.
TEST(ShapeFactories, EachSetsItsTypeAndOnlyTheFieldsItReads) {
  const RShape sphere = RShape::Sphere(0.5);
  EXPECT_EQ(sphere.type, RShapeType::kSphere);
  EXPECT_EQ(sphere.radius, 0.5);
  const RShape box = RShape::Box(RVec3(1, 0.5, 2));
  EXPECT_EQ(box.type, RShapeType::kBox);
  EXPECT_EQ(box.halfExtents, RVec3(1, 0.5, 2));
  const RShape capsule = RShape::Capsule(0.2, 1.5);
  EXPECT_EQ(capsule.type, RShapeType::kCapsule);
  EXPECT_EQ(capsule.radius, 0.2);
  EXPECT_EQ(capsule.halfHeight, 1.5);
  const RShape cylinder = RShape::Cylinder(0.5, 0.1);
  EXPECT_EQ(cylinder.type, RShapeType::kCylinder);
  EXPECT_EQ(cylinder.radius, 0.5);
  EXPECT_EQ(cylinder.halfHeight, 0.1);
  const RShape hull = UnitCube();
  EXPECT_EQ(hull.type, RShapeType::kHull);
  EXPECT_EQ(hull.points.size(), 8u);
  const RShape mesh = Square();
  EXPECT_EQ(mesh.type, RShapeType::kMesh);
  EXPECT_EQ(mesh.points.size(), 4u);
  EXPECT_EQ(mesh.triangles.size(), 2u);
  const RShape compound = RShape::Compound({Child(box, RVec3(-2, 0, 0)), Child(sphere, RVec3(2, 0, 0), 3)});
  EXPECT_EQ(compound.type, RShapeType::kCompound);
  ASSERT_EQ(compound.children.size(), 2u);

  for (const RShape* s : {&sphere, &box, &capsule, &cylinder, &hull, &mesh, &compound}) {
    const RShapeType t = s->type;
    const bool round = t == RShapeType::kSphere || t == RShapeType::kCapsule || t == RShapeType::kCylinder;
    if (!round) {
      EXPECT_EQ(s->radius, 0);
    }
    if (t != RShapeType::kCapsule && t != RShapeType::kCylinder) {
      EXPECT_EQ(s->halfHeight, 0);
    }
    if (t != RShapeType::kBox) {
      EXPECT_EQ(s->halfExtents, RVec3::Zero());
    }
    if (t != RShapeType::kHull && t != RShapeType::kMesh) {
      EXPECT_TRUE(s->points.empty());
    }
    if (t != RShapeType::kMesh) {
      EXPECT_TRUE(s->triangles.empty());
    }
    if (t != RShapeType::kCompound) {
      EXPECT_TRUE(s->children.empty());
    }
    EXPECT_EQ(RefusedField(*s), "") << int(t);
  }

  EXPECT_NEAR(ComputeMassProperties(sphere).volume, 4.0 / 3 * kPi * 0.125, 1e-15);
  EXPECT_NEAR(ComputeMassProperties(box).volume, 8.0, 1e-15);
  EXPECT_NEAR(ComputeMassProperties(capsule).volume, kPi * 0.04 * 3 + 4.0 / 3 * kPi * 0.008, 1e-15);
  EXPECT_NEAR(ComputeMassProperties(cylinder).volume, kPi * 0.25 * 0.2, 1e-15);
  EXPECT_NEAR(ComputeMassProperties(hull).volume, 1.0, 1e-15);
  EXPECT_NEAR(ComputeMassProperties(compound).volume, 8.0 + 3 * 4.0 / 3 * kPi * 0.125, 1e-13);
}

// A factory's shape is field for field the shape the scene reader makes of the same JSON:
// a body made either way is the same body.
TEST(ShapeFactories, TheSceneReaderMakesTheSameShapes) {
  const RScene scene = ParseScene(R"({"bodies": [
      {"name": "sphere", "shape": {"type": "sphere", "radius": 0.5}},
      {"name": "box", "shape": {"type": "box", "half_extents": [1, 0.5, 2]}},
      {"name": "capsule", "shape": {"type": "capsule", "radius": 0.2, "half_height": 1.5}},
      {"name": "cylinder", "shape": {"type": "cylinder", "radius": 0.5, "half_height": 0.1}},
      {"name": "hull", "shape": {"type": "hull", "points": [[-0.5, -0.5, -0.5], [0.5, -0.5, -0.5],
          [-0.5, 0.5, -0.5], [0.5, 0.5, -0.5], [-0.5, -0.5, 0.5], [0.5, -0.5, 0.5], [-0.5, 0.5, 0.5],
          [0.5, 0.5, 0.5]]}},
      {"name": "mesh", "static": true, "shape": {"type": "mesh",
          "vertices": [[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], "triangles": [[0, 2, 1], [0, 3, 2]]}},
      {"name": "compound", "shape": {"type": "compound", "children": [
          {"shape": {"type": "box", "half_extents": [1, 0.5, 2]}, "position": [-2, 0, 0]},
          {"shape": {"type": "sphere", "radius": 0.5}, "position": [2, 0, 0], "density": 3}]}}]})",
                                  "factories.json");
  const std::vector<RShape> made = {
      RShape::Sphere(0.5),
      RShape::Box(RVec3(1, 0.5, 2)),
      RShape::Capsule(0.2, 1.5),
      RShape::Cylinder(0.5, 0.1),
      UnitCube(),
      Square(),
      RShape::Compound({Child(RShape::Box(RVec3(1, 0.5, 2)), RVec3(-2, 0, 0)),
                        Child(RShape::Sphere(0.5), RVec3(2, 0, 0), 3)})};
  ASSERT_EQ(scene.bodies.size(), made.size());
  for (std::size_t i = 0; i < made.size(); ++i) ExpectSameShape(scene.bodies[i].shape, made[i], scene.bodies[i].name);
}

// RShape's sizes start at 0: a body whose shape nobody gave, or whose size nobody gave, is
// refused naming the missing size, not made a 0.5 m sphere or box.
TEST(ShapeFactories, ASizeNobodyGaveIsRefused) {
  EXPECT_EQ(RefusedField(RShape{}), "shape.radius");  // RBodyDef's shape left as it is
  RShape box;
  box.type = RShapeType::kBox;
  EXPECT_EQ(RefusedField(box), "shape.half_extents");
  RShape capsule;
  capsule.type = RShapeType::kCapsule;
  capsule.radius = 0.2;
  EXPECT_EQ(RefusedField(capsule), "shape.half_height");
  RShape cylinder;
  cylinder.type = RShapeType::kCylinder;
  cylinder.halfHeight = 0.2;
  EXPECT_EQ(RefusedField(cylinder), "shape.radius");
  RShape hull;
  hull.type = RShapeType::kHull;
  EXPECT_EQ(RefusedField(hull), "shape.points");
  EXPECT_EQ(RefusedField(RShape::Compound({})), "shape.children");
  EXPECT_EQ(RefusedField(RShape::Compound({Child(RShape{}, RVec3::Zero())})), "shape.children[0].shape.radius");
  EXPECT_EQ(RefusedField(RShape::Sphere(0)), "shape.radius");
  EXPECT_EQ(RefusedField(RShape::Box(RVec3(1, 0, 1))), "shape.half_extents");
}

// A field the type does not read, set anyway (meant for another type, or left from one), is
// refused naming it, in a body's shape and in a compound's child.
TEST(ShapeFactories, AFieldTheTypeDoesNotReadIsRefused) {
  struct Case {
    RShape shape;
    std::function<void(RShape&)> stray;
    const char* field;
  };
  const std::vector<Case> cases = {
      {RShape::Box(RVec3::Constant(0.5)), [](RShape& s) { s.radius = 0.5; }, "shape.radius"},
      {RShape::Hull(UnitCube().points), [](RShape& s) { s.radius = 0.5; }, "shape.radius"},
      {RShape::Sphere(0.5), [](RShape& s) { s.halfHeight = 1; }, "shape.half_height"},
      {RShape::Box(RVec3::Constant(0.5)), [](RShape& s) { s.halfHeight = 1; }, "shape.half_height"},
      {RShape::Sphere(0.5), [](RShape& s) { s.halfExtents = RVec3::Constant(0.5); }, "shape.half_extents"},
      {RShape::Capsule(0.2, 1), [](RShape& s) { s.halfExtents.x() = 1; }, "shape.half_extents"},
      {RShape::Cylinder(0.2, 1), [](RShape& s) { s.points = UnitCube().points; }, "shape.points"},
      {RShape::Box(RVec3::Constant(0.5)), [](RShape& s) { s.points = UnitCube().points; }, "shape.points"},
      {UnitCube(), [](RShape& s) { s.triangles = {{{0, 1, 2}}}; }, "shape.triangles"},
      {RShape::Sphere(0.5), [](RShape& s) { s.children = {Child(RShape::Sphere(1), RVec3::Zero())}; }, "shape.children"},
      {Square(), [](RShape& s) { s.radius = 1; }, "shape.radius"},
      {RShape::Compound({Child(RShape::Sphere(1), RVec3::Zero())}), [](RShape& s) { s.halfExtents = RVec3::Ones(); },
       "shape.half_extents"},
      // A non-number in a field the type does not read is no more ignored than a number.
      {RShape::Box(RVec3::Constant(0.5)), [](RShape& s) { s.radius = std::nan(""); }, "shape.radius"},
  };
  for (const Case& c : cases) {
    RShape s = c.shape;
    ASSERT_EQ(RefusedField(s), "") << c.field;
    c.stray(s);
    EXPECT_EQ(RefusedField(s), c.field);
    const RShape compound = RShape::Compound({Child(RShape::Sphere(1), RVec3::Zero()), Child(s, RVec3(3, 0, 0))});
    if (s.type != RShapeType::kCompound && s.type != RShapeType::kMesh) {
      EXPECT_EQ(RefusedField(compound), std::string("shape.children[1].") + c.field);
    }
  }
}
