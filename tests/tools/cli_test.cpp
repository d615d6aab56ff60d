// rengine-sim as its users see it: exit codes, messages, the CSV and --describe contracts
// of docs/scene-format.md, and determinism. Runs the built binary through the shell.
#include <REngineMath/RQuaternion.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/CliRunner.h"
#include "support/ReferenceScenes.h"

using namespace REngine;
using namespace REngine::test;

TEST_F(Cli, HeadOnElasticRunsAndWritesTheContractsCsv) {
  const Result r =
      Run(Quote(ReferenceScenePath("head_on_elastic")) + " --out " + Quote(Path("t.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.out, "");  // the trajectory went to the file
  const std::string csv = ReadFile(Path("t.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\n')), kHeader);
  const std::vector<Row> rows = ParseCsv(csv);
  ASSERT_EQ(rows.size(), 2u * 241);  // steps 0..240, bodies a and b
  EXPECT_EQ(rows[0].body, "a");
  EXPECT_EQ(rows[1].body, "b");
  EXPECT_EQ(rows.back().step, 240u);
}

TEST_F(Cli, WritesToStandardOutputByDefault) {
  const Result r = Run(Quote(ReferenceScenePath("head_on_elastic")) + " --steps 3");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(ParseCsv(r.out).size(), 2u * 4);
}

TEST_F(Cli, RowsAtStepZeroEveryKthStepAndTheLast) {
  struct Case {
    std::string options;
    std::vector<std::uint64_t> steps;
  };
  std::vector<std::uint64_t> by7;
  for (std::uint64_t s = 0; s <= 240; s += 7) by7.push_back(s);
  by7.push_back(240);  // the last step, not a multiple of 7
  const std::vector<Case> cases = {
      {"--every 7", by7},
      {"--every 60", {0, 60, 120, 180, 240}},  // the last step once, though a multiple of 60
      {"--every 1000", {0, 240}},
      {"--steps 3", {0, 1, 2, 3}},
      {"--steps 0", {0}},
      {"--steps 5 --every 2", {0, 2, 4, 5}},
  };
  const double dt = 0.008333333333333333;  // the scene's
  for (const Case& c : cases) {
    const Result r = Run(Quote(ReferenceScenePath("head_on_elastic")) + " " + c.options);
    ASSERT_EQ(r.code, 0) << c.options << ": " << r.err;
    const std::vector<Row> rows = ParseCsv(r.out);
    ASSERT_EQ(rows.size(), 2 * c.steps.size()) << c.options;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      EXPECT_EQ(rows[i].step, c.steps[i / 2]) << c.options;
      EXPECT_EQ(rows[i].body, i % 2 ? "b" : "a") << c.options;
      // time is step * dt as a product, to the last bit
      EXPECT_EQ(rows[i].time, static_cast<double>(rows[i].step) * dt) << c.options;
    }
  }
}

TEST_F(Cli, DtOptionOverridesTheScene) {
  // One step of 0.5 s: the spheres (gap 3 m, closing at 4 m/s) do not meet within it.
  const Result r = Run(Quote(ReferenceScenePath("head_on_elastic")) + " --steps 1 --dt 0.5");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> rows = ParseCsv(r.out);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[3].time, 0.5);
  EXPECT_EQ(rows[3].state[0], 2 + 0.5 * -1.0);  // b: x0 + t v, free flight
}

// The scene's pose goes in and comes out unchanged, also for a hull, whose body frame
// (centre of mass, principal axes) differs from the frame the scene gives.
TEST_F(Cli, StepZeroRowIsTheScenePose) {
  const std::string scene = SceneOf({
      {"box", R"("shape": {"type": "box", "half_extents": [0.5, 1, 1.5]}, "mass": 2,
                 "position": [1.5, -2.25, 3], "orientation": [0.9, 0.1, 0.3, 0.2],
                 "velocity": [0.25, -1, 2], "angular_velocity": [0.3, -0.7, 1.1])"},
      {"ball", R"("shape": {"type": "sphere", "radius": 0.5}, "position": [-4, 0.5, 7],
                  "orientation": [0.5, -0.5, 0.5, 0.5], "velocity": [1, 2, 3],
                  "angular_velocity": [-2, 0.5, 0.25])"},
      {"rock", R"("shape": {"type": "hull", "points": [[0, 0, 0], [2, 0, 0], [0, 1, 0], [0, 0, 3]]},
                  "position": [1, 2, 3], "orientation": [0.9, 0.1, 0.3, 0.2],
                  "velocity": [0, 0, 1], "angular_velocity": [0.1, 0.2, 0.3])"},
  });
  const Result r = Run(Quote(Write("pose.json", scene)) + " --steps 0");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> rows = ParseCsv(r.out);
  ASSERT_EQ(rows.size(), 3u);
  struct Expected {
    RVec3 x;
    RVec4 q;
    RVec3 v, w;
  };
  const std::vector<Expected> expected = {
      {{1.5, -2.25, 3}, RVec4(0.9, 0.1, 0.3, 0.2).normalized(), {0.25, -1, 2}, {0.3, -0.7, 1.1}},
      {{-4, 0.5, 7}, RVec4(0.5, -0.5, 0.5, 0.5), {1, 2, 3}, {-2, 0.5, 0.25}},
      {{1, 2, 3}, RVec4(0.9, 0.1, 0.3, 0.2).normalized(), {0, 0, 1}, {0.1, 0.2, 0.3}},
  };
  for (std::size_t b = 0; b < 3; ++b) {
    const std::array<double, 13>& s = rows[b].state;
    const Expected& e = expected[b];
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(s[i], e.x[i], 1e-15) << rows[b].body << " x" << i;
      EXPECT_NEAR(s[7 + i], e.v[i], 1e-15) << rows[b].body << " v" << i;
      EXPECT_NEAR(s[10 + i], e.w[i], 1e-15) << rows[b].body << " w" << i;
    }
    // The same rotation, written with the scene's sign.
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(s[3 + i], e.q[i], 1e-15) << rows[b].body << " q" << i;
  }
}

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

TEST_F(Cli, SummaryIsTheLastLineAndTheOnlyOneWithoutATerminal) {
  for (const char* quiet : {"", " --quiet"}) {
    const Result r = Run(Quote(ReferenceScenePath("head_on_elastic")) + " --out " +
                         Quote(Path("t.csv")) + quiet);
    ASSERT_EQ(r.code, 0) << r.err;
    // stderr is a file here, not a terminal: no progress display, only the summary.
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(std::regex_match(
        r.LastErrLine(),
        std::regex(R"(steps=240 bodies=2 ms_per_step=[0-9.e+-]+ hash=[0-9a-f]{16})")))
        << r.err;
  }
}

// The hash is FNV-1a 64 over the final state's doubles; the CSV's 17 digits give them back
// exactly, so it can be recomputed from the last rows.
TEST_F(Cli, HashIsFnv1aOfTheFinalState) {
  const Result r = Run(Quote(ReferenceScenePath("box_stack_10")) + " --steps 50 --every 50");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> rows = ParseCsv(r.out);
  ASSERT_EQ(rows.size(), 2u * 11);
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (std::size_t i = 11; i < rows.size(); ++i) {
    unsigned char bytes[sizeof rows[i].state];
    std::memcpy(bytes, rows[i].state.data(), sizeof bytes);
    for (unsigned char byte : bytes) h = (h ^ byte) * 0x100000001b3ULL;
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  EXPECT_NE(r.LastErrLine().find(std::string("hash=") + hex), std::string::npos) << r.err;
}

TEST_F(Cli, RunsAreDeterministic) {
  std::string hash[2], csv[2];
  for (int i = 0; i < 2; ++i) {
    const fs::path out = Path("run" + std::to_string(i) + ".csv");
    const Result r = Run(Quote(ReferenceScenePath("debris_cloud_1000")) + " --steps 60 --out " +
                         Quote(out));
    ASSERT_EQ(r.code, 0) << r.err;
    hash[i] = r.LastErrLine().substr(r.LastErrLine().find("hash="));
    csv[i] = ReadFile(out);
  }
  EXPECT_EQ(hash[0], hash[1]);
  EXPECT_TRUE(csv[0] == csv[1]) << "trajectories differ";
  EXPECT_EQ(ParseCsv(csv[0]).size(), 1000u * 61);
}

// Every number is written as printf's %.17g writes it, for values across the whole double
// range (rengine-sim formats them itself, for speed).
TEST_F(Cli, NumbersAreWrittenAsPrintfG17) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> exponent(-320, 300), mantissa(1, 10);
  std::bernoulli_distribution negative(0.5);
  const auto number = [&](double maxExponent) {
    const double x = mantissa(rng) * std::pow(10.0, std::min(exponent(rng), maxExponent));
    return negative(rng) ? -x : x;
  };
  char text[64];
  const auto g17 = [&](double x) {
    std::snprintf(text, sizeof text, "%.17g", x);
    return std::string(text);
  };
  std::vector<std::pair<std::string, std::string>> bodies;
  const std::vector<double> special = {0.1, 1.0 / 3, 1e16, 99999999999999999.0, 1e17,
                                       123456789.125, 1e-5, 9.9999999999999995e-6, 5e-324,
                                       1e-11, 0.000123, -2.5};
  for (int i = 0; i < 200; ++i) {
    const double x = i < static_cast<int>(special.size()) ? special[i] : number(300);
    bodies.push_back(
        {"b" + std::to_string(i),
         // Positions are accepted within 1e15 m; velocities over the whole range.
         kSphere + ", \"position\": [" + g17(number(14)) + ", " + g17(number(14)) + ", " +
             g17(number(14)) + "], \"velocity\": [" + g17(x) + ", " +
             g17(number(300)) + ", " + g17(number(300)) + "], \"angular_velocity\": [" +
             g17(number(100)) + ", " + g17(number(100)) + ", " + g17(number(100)) +
             "], \"orientation\": [" + g17(number(1)) + ", " + g17(number(1)) + ", " +
             g17(number(1)) + ", 1]"});
  }
  const Result r = Run(Quote(Write("numbers.json", SceneOf(bodies))) + " --steps 0");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  int checked = 0;
  while (std::getline(in, line)) {
    const std::vector<std::string> f = Split(line);
    ASSERT_EQ(f.size(), 16u);
    for (std::size_t i = 3; i < f.size(); ++i, ++checked) {
      EXPECT_EQ(f[i], g17(std::strtod(f[i].c_str(), nullptr))) << line;
    }
  }
  EXPECT_EQ(checked, 200 * 13);
}

TEST_F(Cli, NamesWithCommasOrQuotesAreQuotedInTheCsv) {
  const Result r = Run(Quote(Write("names.json", SceneOf({{R"(a,\"b\")", kSphere}}))) +
                       " --steps 0");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\n0,0,\"a,\"\"b\"\"\",0,"), std::string::npos) << r.out;
}

TEST_F(Cli, BadScenesExitTwoNamingTheFileAndTheField) {
  struct Case {
    std::string scene, mustContain;
  };
  const std::vector<Case> cases = {
      {SceneOf({{"a", R"("shape": {"type": "sphere", "radius": -1})"}}),
       "bodies[0].shape.radius"},
      {SceneOf({{"a", kSphere + R"(, "frction": 0.5)"}}), "bodies[0].frction"},
      {SceneOf({{"a", kSphere}, {"a", kSphere}}), "bodies[1].name"},
      {SceneOf({{"a", kSphere + R"(, "orientation": [0, 0, 0, 0])"}}), "bodies[0].orientation"},
      {SceneOf({{"a", R"("shape": {"type": "hull",
                                   "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]})"}}),
       "bodies[0].shape.points"},
      {SceneOf({{"a", kSphere}}, R"("dt": 1e999)"), "dt"},
      // A cylinder as flat as a coin of 1e-5 of its radius: refused when the body is made.
      {SceneOf({{"a", R"("shape": {"type": "cylinder", "radius": 1, "half_height": 1e-5})"}}),
       "bodies[0].shape.half_height"},
      {"{\"bodies\": [\n  {\"name\": \"a\",}\n]}", "invalid JSON at line 2, column 16"},
  };
  for (const Case& c : cases) {
    // A trajectory from an earlier run must survive a bad scene.
    Write("keep.csv", "earlier run\n");
    const Result r = Run(Quote(Write("bad scene.json", c.scene)) + " --out " +
                         Quote(Path("keep.csv")));
    EXPECT_EQ(r.code, 2) << c.scene;
    EXPECT_NE(r.err.find("bad scene.json: " + c.mustContain), std::string::npos) << r.err;
    EXPECT_EQ(ReadFile(Path("keep.csv")), "earlier run\n");
  }
}

TEST_F(Cli, BadCommandLinesExitTwo) {
  const std::string scene = Quote(ReferenceScenePath("head_on_elastic"));
  struct Case {
    std::string args, mustContain;
  };
  const std::vector<Case> cases = {
      {scene + " --every 0", "--every"},
      {scene + " --every -3", "--every"},
      {scene + " --dt -1", "--dt"},
      {scene + " --dt 0", "--dt"},
      {scene + " --dt inf", "--dt"},
      {scene + " --dt nan", "--dt"},
      {scene + " --steps -1", "--steps"},
      {scene + " --steps 2.5", "--steps"},
      {scene + " --steps ten", "--steps"},
      {scene + " --bogus", "--bogus"},
      {scene + " --describe --steps 3", "--describe"},
      {"", "scene"},
      {Quote(Path("missing.json")), "missing.json"},
      {scene + " --out " + Quote(Path("no/such/dir/t.csv")), "no/such/dir/t.csv"},
  };
  for (const Case& c : cases) {
    const Result r = Run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.mustContain), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_EQ(Run("--help").code, 0);
}

// A body flung towards the largest double leaves the world (1e15 m of the origin) in its
// first step of 1 s: put back, reported, and the run stops there.
TEST_F(Cli, NonFiniteBodyExitsOneNamingItAndTheStep) {
  const std::string scene = SceneOf({
      {"calm", kSphere},
      {"runaway", kSphere + R"(, "position": [1e15, 0, 0], "velocity": [8e307, 0, 0])"},
  });
  const Result r = Run(Quote(Write("overflow.json", scene)) + " --dt 1 --out " +
                       Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.LastErrLine(), "error: body 'runaway' became non-finite or left the world (1e15 m) at step 1") << r.err;
  // The rows before the failure are kept, to find its cause.
  EXPECT_EQ(ParseCsv(ReadFile(Path("t.csv"))).size(), 2u * 1);
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

// A hull body runs through the simulator: a tumbling rock in zero gravity.
TEST_F(Cli, HullSceneRuns) {
  const std::string scene = SceneOf({
      {"rock", R"("shape": {"type": "hull", "points": [[0, 0, 0], [2, 0, 0], [0, 1, 0], [0, 0, 3],
                                                      [1, 1, 1]]},
                  "velocity": [1, 0, 0], "angular_velocity": [0.3, 2, -1])"},
  });
  const Result r = Run(Quote(Write("rock.json", scene)) + " --steps 120 --quiet --out " +
                       Quote(Path("rock.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("hash="), std::string::npos);
}

// Untrusted scenes cannot crash or hang the CLI: a value nested 100k deep must not crash it
// (SIGSEGV), a body name with a control character must not go raw into the CSV; the work a scene
// asks for is bounded by documented limits, and --max-seconds stops a run that takes too long.
TEST_F(Cli, HostileScenesGetExitTwoNotACrash) {
  const std::string deep = "{\"gravity\": " + std::string(100000, '[') +
                           std::string(100000, ']') + ", \"bodies\": []}";
  Result r = Run(Quote(Write("deep.json", deep)) + " --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 2) << r.err.substr(0, 300);
  EXPECT_NE(r.err.find("nested deeper than 64"), std::string::npos) << r.err.substr(0, 300);
  r = Run(Quote(Write("name.json", SceneOf({{"bad\\u0000name", kSphere}}))));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bodies[0].name"), std::string::npos) << r.err;
  const std::string one = Quote(Write("one.json", SceneOf({{"ball", kSphere}})));
  r = Run(one + " --steps 100000001 --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("steps"), std::string::npos) << r.err;
  // 1e8 steps of one body are allowed, and --max-seconds stops them early with exit 1 and
  // the rows so far.
  r = Run(one + " --steps 100000000 --every 1000 --max-seconds 0.05 --out " + Quote(Path("t.csv")));
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.LastErrLine().find("--max-seconds 0.05 reached"), std::string::npos) << r.err;
  EXPECT_GE(ParseCsv(ReadFile(Path("t.csv"))).size(), 2u);
  EXPECT_EQ(Run(one + " --max-seconds -1").code, 2);
}

// The determinism gate: each reference scene's (scenes/) final-state hash is pinned, and
// two runs agree. A change that alters the physics on purpose changes a hash: re-pin it here
// with the reason in the commit message. A change that should not (a refactoring, a speed-up
// of an exact shortcut) must leave every hash as it is.
TEST_F(Cli, ReferenceScenesKeepTheirPinnedHashes) {
  const struct {
    const char* scene;
    const char* hash;
  } pins[] = {
      {"box_pile_1000", "9f1701dea466135b"},     {"box_stack_10", "15c7e33cb50b3227"},
      {"debris_cloud_1000", "d4103f47e4d4be83"}, {"dzhanibekov", "c436ffe2bfd0195c"},
      {"head_on_elastic", "0faffadb61f4169c"},
  };
  for (const auto& pin : pins) {
    const std::string scene = Quote(std::string(RENGINE_SCENES) + "/" + pin.scene + ".json");
    std::string first;
    // Three runs, on 1, 2 and 4 threads: the hash must not depend on the thread count.
    for (int run = 0; run < 3; ++run) {
      const Result r = Run(scene + " --quiet --threads " + std::to_string(1 << run) + " --out " +
                           Quote(Path("t.csv")));
      ASSERT_EQ(r.code, 0) << pin.scene << "\n" << r.err;
      const std::string line = r.LastErrLine();
      const std::size_t at = line.find("hash=");
      ASSERT_NE(at, std::string::npos) << line;
      const std::string hash = line.substr(at + 5, 16);
      if (run == 0) first = hash;
      EXPECT_EQ(hash, first) << pin.scene << ": the run on " << (1 << run)
                             << " threads differs from the run on one";
      EXPECT_EQ(hash, pin.hash) << pin.scene << " now ends with hash=" << hash
                                << ". If the physics changed on purpose, pin the new hash in "
                                   "this test and say why in the commit message.";
    }
  }
}

// Actions in a scene: a body's rows run from the step it is added at (the actions of step k
// come before row k) to the step before it is removed; the summary's body count is the
// bodies live at the end. A scene whose action names a body that does not exist at its step
// is bad input.
TEST_F(Cli, ActionsAddAndRemoveBodiesRowByRow) {
  const std::string scene = R"({"dt": 0.01, "steps": 10, "bodies": [
      {"name": "a", "shape": {"type": "sphere", "radius": 0.5}}],
    "actions": [
      {"step": 3, "add": {"name": "b", "shape": {"type": "sphere", "radius": 0.5},
                          "position": [5, 0, 0], "velocity": [1, 0, 0]}},
      {"step": 7, "remove": "a"}]})";
  const Result r = Run(Quote(Write("s.json", scene)) + " --out " + Quote(Path("t.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.LastErrLine().find("bodies=1 "), std::string::npos) << r.LastErrLine();
  std::vector<std::uint64_t> stepsA, stepsB;
  for (const Row& row : ParseCsv(ReadFile(Path("t.csv")))) {
    (row.body == "a" ? stepsA : stepsB).push_back(row.step);
    if (row.body == "b") {
      EXPECT_NEAR(row.state[0], 5 + 0.01 * (static_cast<double>(row.step) - 3), 1e-12);
    }
  }
  EXPECT_EQ(stepsA, (std::vector<std::uint64_t>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(stepsB, (std::vector<std::uint64_t>{3, 4, 5, 6, 7, 8, 9, 10}));

  const Result bad = Run(Quote(Write("bad.json", R"({"bodies": [], "actions": [
      {"step": 2, "remove": "ghost"}]})")));
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("actions[0].remove: no body is named \"ghost\" at step 2"), std::string::npos)
      << bad.err;
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
