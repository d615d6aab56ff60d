// rengine-sim's answers to a game's questions: the scene's rays (--rays) and the contact
// events (--events) of docs/scene-format.md, written as CSV, and their bad input.
#include <REngineMath/RMath.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/CliRunner.h"

using namespace REngine;
using namespace REngine::test;

// --rays: the scene's rays answered after their steps (the state of row k, actions included):
// a sphere of radius 1 flying at x = 10 - 100 t towards the origin, a box behind it, rays
// along +x from the origin. Distances are closed forms (x(t) - 1), normals face the ray,
// `all` lists every body nearest first, `mask` skips by category, a miss is one row with an
// empty body and distance inf.
TEST_F(Cli, RaysAreAnsweredAfterTheirSteps) {
  const std::string scene = R"({"dt": 0.01, "steps": 10, "bodies": [
      {"name": "ball", "shape": {"type": "sphere", "radius": 1}, "position": [10, 0, 0],
       "velocity": [-100, 0, 0]},
      {"name": "crate, big", "shape": {"type": "box", "half_extents": [1, 1, 1]},
       "position": [20, 0, 0], "category": 2}],
    "actions": [{"step": 7, "remove": "ball"}],
    "rays": [
      {"name": "laser", "step": 5, "origin": [0, 0, 0], "direction": [3, 0, 0], "max_distance": 100},
      {"name": "laser", "step": 0, "origin": [0, 0, 0], "direction": [1, 0, 0], "max_distance": 100,
       "all": true},
      {"name": "masked", "step": 0, "origin": [0, 0, 0], "direction": [1, 0, 0],
       "max_distance": 100, "mask": 2},
      {"name": "short", "step": 0, "origin": [0, 0, 0], "direction": [1, 0, 0], "max_distance": 8.5},
      {"name": "laser", "step": 7, "origin": [0, 0, 0], "direction": [1, 0, 0], "max_distance": 100},
      {"name": "inside", "step": 10, "origin": [20.5, 0, 0], "direction": [0, 1, 0],
       "max_distance": 0}]})";
  const Result r = Run(Quote(Write("s.json", scene)) + " --out " + Quote(Path("t.csv")) +
                       " --rays " + Quote(Path("rays.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(ReadFile(Path("rays.csv")));
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "step,ray,body,distance,x,y,z,nx,ny,nz");
  while (std::getline(in, line)) {
    std::vector<std::string> fields(1);  // every field, trailing empty ones included
    for (char c : line) {
      if (c == ',') {
        fields.emplace_back();
      } else {
        fields.back().push_back(c);
      }
    }
    rows.push_back(fields);
  }
  // Step order, then list order within a step; the box's name is quoted (it holds a comma).
  const std::vector<std::vector<std::string>> expect = {
      {"0", "laser", "ball", "9", "9", "0", "0", "-1", "0", "0"},
      {"0", "laser", "\"crate", " big\"", "19", "19", "0", "0", "-1", "0", "0"},
      {"0", "masked", "\"crate", " big\"", "19", "19", "0", "0", "-1", "0", "0"},
      {"0", "short", "", "inf", "", "", "", "", "", ""},
      // After 5 steps of 0.01 s the ball's centre is at 10 - 5 = 5 m.
      {"5", "laser", "ball", "4", "4", "0", "0", "-1", "0", "0"},
      // Removed after step 7: the crate is what the laser meets.
      {"7", "laser", "\"crate", " big\"", "19", "19", "0", "0", "-1", "0", "0"},
      // Starting inside: distance 0 at the origin, the normal facing the ray.
      {"10", "inside", "\"crate", " big\"", "0", "20.5", "0", "0", "-0", "-1", "-0"}};
  ASSERT_EQ(rows.size(), expect.size()) << ReadFile(Path("rays.csv"));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), expect[i].size()) << i;
    for (std::size_t k = 0; k < rows[i].size(); ++k) {
      if (k >= 3 && !expect[i][k].empty() && expect[i][k] != "inf" && expect[i][k][0] != '"' &&
          expect[i][k].back() != '"') {
        EXPECT_NEAR(std::stod(rows[i][k]), std::stod(expect[i][k]), 1e-12) << i << " " << k;
      } else {
        EXPECT_EQ(rows[i][k], expect[i][k]) << i << " " << k;
      }
    }
  }
  // Rays read the world and change nothing: the same hash without --rays.
  const Result plain = Run(Quote(Path("s.json")) + " --out " + Quote(Path("t2.csv")));
  EXPECT_EQ(plain.LastErrLine().substr(plain.LastErrLine().find("hash=")),
            r.LastErrLine().substr(r.LastErrLine().find("hash=")));
  EXPECT_EQ(ReadFile(Path("t.csv")), ReadFile(Path("t2.csv")));
}

TEST_F(Cli, BadRaysExitTwoNamingThePath) {
  const std::string body = R"({"name": "a", "shape": {"type": "sphere", "radius": 1}})";
  auto scene = [&](const std::string& ray) {
    return R"({"dt": 0.01, "steps": 10, "bodies": [)" + body + R"(], "rays": [)" + ray + "]}";
  };
  const std::string ok = R"("name": "r", "step": 1, "origin": [0, 0, 0], "direction": [1, 0, 0])";
  struct Case {
    std::string scene, mustContain;
  };
  const std::vector<Case> cases = {
      {scene("{" + ok + "}"), "rays[0].max_distance: required field is missing"},
      {scene("{" + ok + R"(, "max_distance": -1})"), "rays[0].max_distance"},
      {scene("{" + ok + R"(, "max_distance": 1e999})"), "rays[0].max_distance"},
      {scene(R"({"name": "r", "step": 1, "origin": [0, 0, 0], "direction": [0, 0, 0], "max_distance": 1})"),
       "rays[0].direction: must have a non-zero length"},
      {scene(R"({"name": "r", "step": 1, "origin": [0, "x", 0], "direction": [1, 0, 0], "max_distance": 1})"),
       "rays[0].origin[1]"},
      {scene(R"({"name": "r", "step": 1, "origin": [2e15, 0, 0], "direction": [1, 0, 0], "max_distance": 1})"),
       "rays[0].origin"},
      {scene("{" + ok + R"(, "max_distance": 1, "mask": 4294967296})"), "rays[0].mask"},
      {scene("{" + ok + R"(, "max_distance": 1, "all": 1})"), "rays[0].all"},
      {scene("{" + ok + R"(, "max_distance": 1, "lenght": 1})"), "rays[0].lenght: unknown field"},
      {scene("{" + ok + R"(, "max_distance": 1}, {)" + ok + R"(, "max_distance": 2})"),
       "rays[1].name: \"r\" is already the name of a ray at step 1"},
      {scene(R"({"name": "r", "step": 11, "origin": [0, 0, 0], "direction": [1, 0, 0], "max_distance": 1})"),
       "rays[0].step: is after the last step (10)"},
      {R"({"bodies": [], "rays": {}})", "rays: must be an array"},
  };
  for (const Case& c : cases) {
    Write("keep.csv", "earlier run\n");
    const Result r = Run(Quote(Write("bad.json", c.scene)) + " --rays " + Quote(Path("keep.csv")));
    EXPECT_EQ(r.code, 2) << c.scene << "\n" << r.err;
    EXPECT_NE(r.err.find("bad.json: " + c.mustContain), std::string::npos) << r.err;
    EXPECT_EQ(ReadFile(Path("keep.csv")), "earlier run\n");  // never truncated by bad input
  }
  // The same ray name at two steps is fine; --steps that cuts a ray off is not.
  const std::string twice = scene("{" + ok + R"(, "max_distance": 1}, {"name": "r", "step": 2,
      "origin": [0, 0, 0], "direction": [1, 0, 0], "max_distance": 1})");
  EXPECT_EQ(Run(Quote(Write("twice.json", twice)) + " --rays " + Quote(Path("r.csv"))).code, 0);
  const Result cut = Run(Quote(Path("twice.json")) + " --steps 1 --rays " + Quote(Path("r.csv")));
  EXPECT_EQ(cut.code, 2);
  EXPECT_NE(cut.err.find("rays[1].step"), std::string::npos) << cut.err;
  // An unwritable rays file.
  const Result dir = Run(Quote(Path("twice.json")) + " --rays " + Quote(Path("no/such/dir/r.csv")));
  EXPECT_EQ(dir.code, 2);
  EXPECT_NE(dir.err.find("no/such/dir/r.csv"), std::string::npos) << dir.err;
}

// --events: begin and end rows (docs/scene-format.md, "Events CSV") in zero g, dt 0.01 s. A
// crate rests on the wall's top from the start (begin in step 1) and is removed after step
// 10 (end in step 11); a missile that does not respond crosses a 10 cm sensor at 1000 m/s
// inside step 1 (begin and end); a ball added after step 0 in the slot "tmp" freed (so
// created after the wall, named second though its handle is lower) meets the wall 0.53 m
// away at 10 m/s, 0.053 s in, and bounces off (e = 1) inside step 6 with impulse
// 2 m v = 40 N s. Normals point from body_a to body_b; the hash is the same without --events.
TEST_F(Cli, EventsAreWrittenAsBeginAndEndRows) {
  const std::string scene = R"({"dt": 0.01, "steps": 20, "bodies": [
      {"name": "tmp", "shape": {"type": "sphere", "radius": 0.1}, "position": [0, 50, 0]},
      {"name": "wall", "shape": {"type": "box", "half_extents": [0.5, 5, 5]}, "static": true,
       "restitution": 1, "friction": 0},
      {"name": "sensor", "shape": {"type": "box", "half_extents": [0.05, 5, 5]}, "static": true,
       "responds": false, "position": [10, 0, 0]},
      {"name": "missile", "shape": {"type": "box", "half_extents": [0.1, 0.1, 0.1]},
       "responds": false, "position": [5.37, 0, 0], "velocity": [1000, 0, 0]},
      {"name": "crate", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]},
       "position": [0, 5.5, 0]}],
    "actions": [{"step": 0, "remove": "tmp"},
      {"step": 0, "add": {"name": "ball", "shape": {"type": "sphere", "radius": 0.5}, "mass": 2,
       "position": [-1.53, 0, 0], "velocity": [10, 0, 0], "restitution": 1, "friction": 0}},
      {"step": 10, "remove": "crate"}]})";
  const Result r = Run(Quote(Write("e.json", scene)) + " --out " + Quote(Path("t.csv")) + " --events " +
                       Quote(Path("events.csv")));
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(ReadFile(Path("events.csv")));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "step,time,event,body_a,body_b,x,y,z,nx,ny,nz,normal_impulse,tangent_impulse");
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) rows.push_back(Split(line));
  struct Expect {
    std::string step, time, event, a, b;
    RVec3 normal;
    double normalImpulse;
  };
  const std::vector<Expect> expect = {
      {"1", "0.01", "begin", "wall", "crate", RVec3(0, 1, 0), 0},
      {"1", "0.01", "begin", "sensor", "missile", RVec3(-1, 0, 0), 0},
      {"1", "0.01", "end", "sensor", "missile", RVec3(-1, 0, 0), 0},
      {"6", "0.059999999999999998", "begin", "wall", "ball", RVec3(-1, 0, 0), 40},
      {"6", "0.059999999999999998", "end", "wall", "ball", RVec3(-1, 0, 0), 40},
      {"11", "0.11", "end", "wall", "crate", RVec3(0, 1, 0), 0}};
  ASSERT_EQ(rows.size(), expect.size()) << ReadFile(Path("events.csv"));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::vector<std::string>& f = rows[i];
    ASSERT_EQ(f.size(), 13u) << i;
    EXPECT_EQ(f[0], expect[i].step) << i;
    EXPECT_EQ(f[1], expect[i].time) << i;
    EXPECT_EQ(f[2], expect[i].event) << i;
    EXPECT_EQ(f[3], expect[i].a) << i;
    EXPECT_EQ(f[4], expect[i].b) << i;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(std::stod(f[8 + k]), expect[i].normal[k], 1e-12) << i;
    EXPECT_NEAR(std::stod(f[11]), expect[i].normalImpulse, 1e-12 * 40) << i;
    EXPECT_EQ(std::stod(f[12]), 0) << i;
  }
  // The missile enters the sensor at its face, x = 9.95; the ball meets the wall at x = -0.5.
  EXPECT_NEAR(std::stod(rows[1][5]), 9.95, 1e-9);
  EXPECT_NEAR(std::stod(rows[3][5]), -0.5, 1e-9);
  // Events observe: the same trajectory and hash without them.
  const Result plain = Run(Quote(Path("e.json")) + " --out " + Quote(Path("t2.csv")));
  EXPECT_EQ(plain.LastErrLine().substr(plain.LastErrLine().find("hash=")),
            r.LastErrLine().substr(r.LastErrLine().find("hash=")));
  EXPECT_EQ(ReadFile(Path("t.csv")), ReadFile(Path("t2.csv")));
}

// An events file that cannot be written: exit 2 naming it, before any step.
TEST_F(Cli, UnwritableEventsFileExitsTwoNamingIt) {
  const std::string scene = R"({"dt": 0.01, "steps": 5, "bodies": [
      {"name": "a", "shape": {"type": "sphere", "radius": 1}}]})";
  const Result r = Run(Quote(Write("s.json", scene)) + " --out " + Quote(Path("t.csv")) + " --events " +
                       Quote(Path("no/such/dir/e.csv")));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no/such/dir/e.csv: cannot open for writing"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("hash="), std::string::npos) << r.err;
  // --describe writes no events: the two do not go together.
  EXPECT_EQ(Run(Quote(Path("s.json")) + " --describe --events " + Quote(Path("e.csv"))).code, 2);
}
