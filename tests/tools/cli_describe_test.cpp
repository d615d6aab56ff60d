// rengine-sim --describe (docs/scene-format.md): each body's world mass properties, against
// the closed forms of a box, a sphere, a tetrahedron's hull, a cylinder, a compound and a
// capsule. Runs the built binary through the shell.
#include <REngineMath/RQuaternion.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

#include "support/CliRunner.h"

using namespace REngine;
using namespace REngine::test;

TEST_F(Cli, DescribeGivesWorldMassProperties) {
  const RVec4 q = RVec4(0.9, 0.1, 0.3, 0.2).normalized();
  const std::string scene = SceneOf({
      {"box", R"("shape": {"type": "box", "half_extents": [0.5, 1, 1.5]}, "mass": 2,
                 "position": [1, 2, 3], "orientation": [0.9, 0.1, 0.3, 0.2])"},
      {"ball", R"("shape": {"type": "sphere", "radius": 0.5}, "density": 2,
                  "position": [-1, 0, 0])"},
      {"ground", R"("shape": {"type": "box", "half_extents": [50, 0.5, 50]}, "static": true)"},
  });
  const Result r = Run(Quote(Write("describe.json", scene)) + " --describe");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json list = nlohmann::json::parse(r.out);
  ASSERT_TRUE(list.is_array());
  ASSERT_EQ(list.size(), 3u);

  const auto vec = [](const nlohmann::json& j) {
    return RVec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  };
  for (const nlohmann::json& body : list) {
    const nlohmann::json& moments = body["principal_moments"];
    const nlohmann::json& axes = body["principal_axes"];
    ASSERT_EQ(moments.size(), 3u);
    ASSERT_EQ(axes.size(), 3u);
    EXPECT_LE(moments[0].get<double>(), moments[1].get<double>()) << body["name"];
    EXPECT_LE(moments[1].get<double>(), moments[2].get<double>()) << body["name"];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        EXPECT_NEAR(vec(axes[i]).dot(vec(axes[j])), i == j ? 1.0 : 0.0, 1e-14) << body["name"];
      }
    }
  }

  // Box: I = m (b^2 + c^2) / 3 and cyclically for half extents (a, b, c); ascending, the
  // moments are about the local z, y and x axes, which the orientation turns into the world.
  const nlohmann::json& box = list[0];
  EXPECT_EQ(box["name"], "box");
  EXPECT_EQ(box["mass"].get<double>(), 2.0);
  EXPECT_LT((vec(box["com"]) - RVec3(1, 2, 3)).norm(), 1e-15);
  const double m = 2, a = 0.5, b = 1, c = 1.5;
  const RVec3 moments(m * (a * a + b * b) / 3, m * (a * a + c * c) / 3, m * (b * b + c * c) / 3);
  const RMat3 R_WS = QuatFromWXYZ(q).toRotationMatrix();
  const int localAxis[3] = {2, 1, 0};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(box["principal_moments"][i].get<double>(), moments[i], 1e-14);
    EXPECT_NEAR(std::abs(vec(box["principal_axes"][i]).dot(R_WS.col(localAxis[i]))), 1.0, 1e-14);
  }

  const nlohmann::json& ball = list[1];
  const double ballMass = 2 * 4.0 / 3 * kPi * 0.125;
  EXPECT_NEAR(ball["mass"].get<double>(), ballMass, 1e-14);
  EXPECT_EQ(vec(ball["com"]), RVec3(-1, 0, 0));
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(ball["principal_moments"][i].get<double>(), 0.4 * ballMass * 0.25, 1e-14);
  }

  const nlohmann::json& ground = list[2];
  EXPECT_EQ(ground["mass"].get<double>(), 0.0);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(ground["principal_moments"][i].get<double>(), 0.0);
}

// A hull's mass properties against the closed form for a tetrahedron: the affine image
// x = A u of the unit tetrahedron has volume |det A| / 6, centroid A (1,1,1) / 4 and second
// moment |det A| A M A^T with M = (1 + delta_ij) / 120. Each reported axis must be an
// eigenvector of the world inertia tensor with the reported moment.
TEST_F(Cli, DescribeGivesExactHullMassProperties) {
  const std::string scene = SceneOf({
      {"rock", R"("shape": {"type": "hull", "points": [[0, 0, 0], [2, 0, 0], [0, 1, 0], [0, 0, 3],
                                                      [0.2, 0.2, 0.2]]},
                  "density": 3, "position": [10, -4, 1e6], "orientation": [0.9, 0.1, 0.3, 0.2])"},
  });
  const Result r = Run(Quote(Write("hull.json", scene)) + " --describe");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json body = nlohmann::json::parse(r.out)[0];
  const auto vec = [](const nlohmann::json& j) {
    return RVec3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
  };
  RMat3 A = RVec3(2, 1, 3).asDiagonal();
  RMat3 M;
  M << 2, 1, 1, 1, 2, 1, 1, 1, 2;
  M /= 120;
  const double rho = 3, volume = A.determinant() / 6;
  const RVec3 centroid_S = A * RVec3::Constant(0.25);
  const RMat3 C = rho * (A.determinant() * A * M * A.transpose() -
                         volume * centroid_S * centroid_S.transpose());
  const RMat3 I_S = C.trace() * RMat3::Identity() - C;
  const RMat3 R_WS = QuatFromWXYZ(RVec4(0.9, 0.1, 0.3, 0.2).normalized()).toRotationMatrix();
  const RMat3 I_W = R_WS * I_S * R_WS.transpose();

  EXPECT_NEAR(body["mass"].get<double>(), rho * volume, 1e-14);
  EXPECT_LT((vec(body["com"]) - (RVec3(10, -4, 1e6) + R_WS * centroid_S)).norm(), 1e-9);
  for (int i = 0; i < 3; ++i) {
    const RVec3 axis = vec(body["principal_axes"][i]);
    const double moment = body["principal_moments"][i].get<double>();
    EXPECT_NEAR(axis.norm(), 1, 1e-14);
    EXPECT_LT((I_W * axis - moment * axis).norm(), 1e-13 * I_W.norm()) << i;
  }
  EXPECT_LT(body["principal_moments"][0].get<double>(), body["principal_moments"][1].get<double>());
  EXPECT_LT(body["principal_moments"][1].get<double>(), body["principal_moments"][2].get<double>());
}

// A cylinder's --describe: mass rho pi r^2 (2h), moments m r^2 / 2 about its axis and
// m (3 r^2 + (2h)^2) / 12 across it, the axis turned into the world by the orientation.
TEST_F(Cli, DescribeGivesACylindersClosedFormMassProperties) {
  const std::string scene = SceneOf({
      {"drum", R"("shape": {"type": "cylinder", "radius": 0.8, "half_height": 0.3}, "density": 2,
                  "position": [1, 2, 3], "orientation": [0.7071067811865476, 0, 0, 0.7071067811865476])"},
  });
  const Result r = Run(Quote(Write("cylinder.json", scene)) + " --describe");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json list = nlohmann::json::parse(r.out);
  ASSERT_EQ(list.size(), 1u);
  const double pi = 3.14159265358979323846, m = 2 * pi * 0.64 * 0.6;
  EXPECT_NEAR(list[0]["mass"].get<double>(), m, 1e-13);
  const double axial = m * 0.64 / 2, across = m * (3 * 0.64 + 0.36) / 12;
  // Sorted ascending: across (0.19 m) below axial (0.32 m) for this flat drum.
  EXPECT_NEAR(list[0]["principal_moments"][0].get<double>(), across, 1e-13);
  EXPECT_NEAR(list[0]["principal_moments"][1].get<double>(), across, 1e-13);
  EXPECT_NEAR(list[0]["principal_moments"][2].get<double>(), axial, 1e-13);
  // The axis (the shape's y) turned 90 degrees about z: the world's x.
  const nlohmann::json& axis = list[0]["principal_axes"][2];
  EXPECT_NEAR(std::abs(axis[0].get<double>()), 1, 1e-15);
  EXPECT_NEAR(list[0]["com"][2].get<double>(), 3, 1e-15);
}

// A compound's --describe: two unit cubes side by side along the scene's x, densities 1 and 3:
// mass 4, centre 0.25 towards the dense one, moments 4/6 about the long axis and
// 4/6 + 0.75^2 + 3 (0.25^2) across (parallel axes by hand).
TEST_F(Cli, DescribeGivesACompoundsUnionMassProperties) {
  const std::string scene = SceneOf({
      {"pair", R"("shape": {"type": "compound", "children": [
                    {"shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "position": [-0.5, 0, 0]},
                    {"shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "position": [0.5, 0, 0], "density": 3}]},
                  "position": [1, 2, 3])"},
  });
  const Result r = Run(Quote(Write("compound.json", scene)) + " --describe");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json list = nlohmann::json::parse(r.out);
  ASSERT_EQ(list.size(), 1u);
  EXPECT_NEAR(list[0]["mass"].get<double>(), 4, 1e-13);
  EXPECT_NEAR(list[0]["com"][0].get<double>(), 1.25, 1e-14);
  EXPECT_NEAR(list[0]["principal_moments"][0].get<double>(), 4.0 / 6, 1e-13);
  EXPECT_NEAR(list[0]["principal_moments"][2].get<double>(), 4.0 / 6 + 0.5625 + 0.1875, 1e-13);
  EXPECT_NEAR(std::abs(list[0]["principal_axes"][0][0].get<double>()), 1, 1e-12);  // the long axis: x
}

// A capsule's --describe: its mass from the density and its volume, pi r^2 (2h) + 4/3 pi r^3,
// and its moments, about its axis m_c r^2/2 + 2/5 m_s r^2 (the smallest, for this one) and
// across it m_c (h^2/3 + r^2/4) + m_s (2/5 r^2 + h^2 + 3/4 h r), the axis turned into the
// world by the scene's orientation.
TEST_F(Cli, DescribeGivesACapsulesClosedFormMassProperties) {
  const std::string scene = SceneOf({
      {"missile", R"("shape": {"type": "capsule", "radius": 0.25, "half_height": 1.5}, "density": 3,
                     "position": [4, 5, 6], "orientation": [0.7071067811865476, 0.7071067811865476, 0, 0])"},
  });
  const Result r = Run(Quote(Write("capsule.json", scene)) + " --describe");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json list = nlohmann::json::parse(r.out);
  ASSERT_EQ(list.size(), 1u);
  const double pi = 3.14159265358979323846, rho = 3, rr = 0.25, h = 1.5;
  const double mc = rho * pi * rr * rr * 2 * h, ms = rho * 4.0 / 3 * pi * rr * rr * rr;
  EXPECT_NEAR(list[0]["mass"].get<double>(), mc + ms, 1e-13);
  const double axial = mc * rr * rr / 2 + ms * 2.0 / 5 * rr * rr;
  const double across = mc * (h * h / 3 + rr * rr / 4) + ms * (2.0 / 5 * rr * rr + h * h + 0.75 * h * rr);
  EXPECT_NEAR(list[0]["principal_moments"][0].get<double>(), axial, 1e-13);
  EXPECT_NEAR(list[0]["principal_moments"][1].get<double>(), across, 1e-13);
  EXPECT_NEAR(list[0]["principal_moments"][2].get<double>(), across, 1e-13);
  // The axis (the shape's y) turned 90 degrees about x: the world's z.
  const nlohmann::json& axis = list[0]["principal_axes"][0];
  EXPECT_NEAR(std::abs(axis[2].get<double>()), 1, 1e-15);
  EXPECT_NEAR(list[0]["com"][0].get<double>(), 4, 1e-15);
}
