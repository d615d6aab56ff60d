// rengine-sim with characters (docs/scene-format.md, "Characters"): the scene's character
// walks, climbs, jumps onto a one-way ledge and stands, as rows of the trajectory and rows of
// --events; the same bits on any thread count and after a saved state; every bad value
// refused with exit 2 and its JSON path.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "support/CliRunner.h"
#include "support/ReferenceScenes.h"

#include <cmath>

using namespace REngine;
using namespace REngine::test;

namespace {

std::string Hash(const std::string& err) {
  const std::size_t at = err.rfind("hash=");
  return at == std::string::npos ? "" : err.substr(at + 5, 16);
}

TEST_F(Cli, CharacterWalksClimbsJumpsOntoTheOneWayLedgeAndStands) {
  const Result r = Run(Quote(ReferenceScenePath("character_walk")) + " --out " + Quote(Path("t.csv")) +
                       " --events " + Quote(Path("e.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<Row> player = RowsOf(ParseCsv(ReadFile(Path("t.csv"))), "player");
  ASSERT_EQ(player.size(), 601u);
  // Steps 1 to 60 on the level tiles at 3 m/s: x = 3 t exactly, the height unchanged.
  for (int k = 1; k <= 60; ++k) {
    EXPECT_NEAR(Position(player[k]).x(), 3 * k / 60.0, 1e-12) << k;
    EXPECT_NEAR(Position(player[k]).y(), 0.901, 1e-12) << k;
    EXPECT_NEAR(Velocity(player[k]).x(), 3, 1e-9) << k;
  }
  // On the 0.25 m step (x 6 to 8) at step 150, back on the tiles by 180.
  EXPECT_NEAR(Position(player[150]).y(), 0.25 + 0.901, 1e-9);
  EXPECT_NEAR(Position(player[180]).y(), 0.901, 1e-9);
  // Jumped at 6 m/s at step 190 under the one-way ledge (top at 1.7 m, x 10.5 to 13.5): up
  // through it, on it at step 270.
  EXPECT_NEAR(Position(player[270]).y(), 1.7 + 0.901, 1e-9);
  // Off its end and back on the tiles, standing still from step 330.
  EXPECT_NEAR(Position(player[600]).y(), 0.901, 1e-9);
  EXPECT_EQ(Position(player[600]).x(), Position(player[400]).x());
  const std::string events = ReadFile(Path("e.csv"));
  EXPECT_NE(events.find(",begin,player,step,"), std::string::npos);
  EXPECT_NE(events.find(",begin,player,ledge,"), std::string::npos);
  EXPECT_NE(events.find(",end,player,ledge,"), std::string::npos);
}

TEST_F(Cli, CharacterRunsAreTheSameOnAnyThreadCountAndAfterASavedState) {
  const std::string scene = Quote(ReferenceScenePath("character_walk"));
  const Result one = Run(scene + " --threads 1 --out " + Quote(Path("1.csv")));
  const Result two = Run(scene + " --threads 2 --out " + Quote(Path("2.csv")));
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_EQ(Hash(one.err), Hash(two.err));
  EXPECT_EQ(ReadFile(Path("1.csv")), ReadFile(Path("2.csv")));
  // Saved mid-jump (step 200) and run on from there: the same rows.
  const Result saved = Run(scene + " --save-state 200:" + Quote(Path("s.state")) + " --out " + Quote(Path("a.csv")));
  ASSERT_EQ(saved.code, 0) << saved.err;
  const Result loaded = Run(scene + " --load-state " + Quote(Path("s.state")) + " --out " + Quote(Path("b.csv")));
  ASSERT_EQ(loaded.code, 0) << loaded.err;
  EXPECT_EQ(Hash(loaded.err), Hash(one.err));
  EXPECT_EQ(RowsFrom(ReadFile(Path("a.csv")), 201), RowsFrom(ReadFile(Path("b.csv")), 201));
}

TEST_F(Cli, BadCharacterValuesAreRefusedWithTheirJsonPath) {
  const nlohmann::json base = nlohmann::json::parse(ReadFile(ReferenceScenePath("character_walk")));
  struct Case {
    const char* pointer;
    nlohmann::json value;
    const char* path;
  };
  const Case cases[] = {
      {"/characters/0/max_slope_deg", 90, "characters[0].max_slope_deg"},
      {"/characters/0/max_slope_deg", -1, "characters[0].max_slope_deg"},
      {"/characters/0/step_height", -0.1, "characters[0].step_height"},
      {"/characters/0/mass", 0, "characters[0].mass"},
      {"/characters/0/max_push_force", "a lot", "characters[0].max_push_force"},
      {"/characters/0/up", {0, 2, 0}, "characters[0].up"},
      {"/characters/0/shape/radius", -0.3, "characters[0].shape.radius"},
      {"/characters/0/position", {0, 1e300, 0}, "characters[0].position"},
      {"/characters/0/name", "tile3", "characters[0].name"},
      {"/characters/0/inputs/1/step", 0, "characters[0].inputs[1].step"},
      {"/characters/0/inputs/0/jump", 0, "characters[0].inputs[0].jump"},
      {"/characters/0/inputs/0/velocity", {1, "x", 0}, "characters[0].inputs[0].velocity[1]"},
      {"/characters/0/inputs/4/step", 601, "characters[0].inputs[4].step"},
      {"/characters/0/speed", 3, "characters[0].speed"},
      {"/bodies/21/one_way", 1, "bodies[21].one_way"},
  };
  for (const Case& c : cases) {
    nlohmann::json scene = base;
    scene[nlohmann::json::json_pointer(c.pointer)] = c.value;
    const Result r = Run(Quote(Write("bad.json", scene.dump())) + " --steps 1 --out " + Quote(Path("t.csv")));
    EXPECT_EQ(r.code, 2) << c.pointer << "\n" << r.err;
    EXPECT_NE(r.err.find(std::string(": ") + c.path + ": "), std::string::npos) << c.pointer << "\n" << r.err;
  }
  // Zero gravity with no up.
  nlohmann::json scene = base;
  scene["gravity"] = {0, 0, 0};
  const Result r = Run(Quote(Write("bad.json", scene.dump())) + " --steps 1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("characters[0].up: "), std::string::npos) << r.err;
}

}  // namespace
