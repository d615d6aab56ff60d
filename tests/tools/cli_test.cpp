// rengine-sim as its users see it: the CSV contract of docs/scene-format.md (rows, times,
// poses, numbers, names), the summary line and its hash, determinism and the reference
// scenes' pinned hashes, and actions that add and remove bodies. Runs the built binary
// through the shell.
#include <gtest/gtest.h>
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

// The determinism gate: each reference scene's (scenes/) final-state hash is pinned, and
// two runs agree. A change that alters the physics on purpose changes a hash: re-pin it here
// with the reason in the commit message. A change that should not (a refactoring, a speed-up
// of an exact shortcut) must leave every hash as it is. The same pins hold with clang, on
// 64-bit ARM with gcc, at -O2 and -O3 (tools/cross_check.sh).
TEST_F(Cli, ReferenceScenesKeepTheirPinnedHashes) {
  const struct {
    const char* scene;
    const char* hash;
  } pins[] = {
      {"asteroid_field_500", "6838cf8a41a323df"}, {"box_pile_1000", "98b9de0293971f56"},
      {"box_stack_10", "15c7e33cb50b3227"},       {"box_stack_20", "f5ff07194df8205d"},
      {"debris_cloud_1000", "4795c2fcfe674f96"},  {"dzhanibekov", "b63229bbe454cb51"},
      {"head_on_elastic", "0faffadb61f4169c"},    {"newtons_cradle", "35de15fdaada2f98"},
      {"character_walk", "97a65051ad1e02ae"},
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
