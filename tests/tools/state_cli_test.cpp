// rengine-sim --save-state N:FILE and --load-state FILE (docs/scene-format.md, "The
// rengine-sim command line"): a run started in a new process from the state saved after
// step N ends with the uninterrupted run's hash=, and writes the same trajectory rows and
// contact events from step N on; a file that is not such a state, or is another scene's, is
// bad input (exit 2, the file named).
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "state/RStateFormat.h"  // the header's layout and checksum: to forge a state's tag
#include "support/CliRunner.h"
#include "support/ReferenceScenes.h"

using namespace REngine::test;

namespace {

// A game in a file: a stack the drops wake, spawns and removals before and after the save,
// an impulse and a velocity set after it, a kinematic turntable carrying a box, a satellite
// tumbling near its intermediate axis, a sensor (events without response).
const std::string kGame = R"({"gravity": [0, -9.81, 0], "dt": 0.016666666666666666, "steps": 240,
  "bodies": [
    {"name": "ground", "shape": {"type": "box", "half_extents": [20, 0.5, 20]}, "static": true,
     "position": [0, -0.5, 0]},
    {"name": "a", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "position": [0, 0.5, 0]},
    {"name": "b", "shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "position": [0.1, 1.5, 0]},
    {"name": "c", "shape": {"type": "hull", "points": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0.6, 0.6, 0.6]]},
     "position": [3, 3, 0], "angular_velocity": [1, 2, 0.5]},
    {"name": "sat", "shape": {"type": "box", "half_extents": [0.2, 0.5, 0.9]}, "gravity_scale": 0,
     "position": [0, 10, 5], "angular_velocity": [0.01, 3, 0.02]},
    {"name": "sensor", "shape": {"type": "box", "half_extents": [1, 1, 1]}, "static": true, "responds": false,
     "position": [3, 0.5, 0]},
    {"name": "turntable", "shape": {"type": "box", "half_extents": [1.5, 0.2, 1.5]}, "kind": "kinematic",
     "position": [-5, 0.2, 0], "angular_velocity": [0, 1, 0]},
    {"name": "rider", "shape": {"type": "box", "half_extents": [0.3, 0.3, 0.3]}, "friction": 0.8,
     "position": [-4, 0.71, 0]}],
  "actions": [
    {"step": 20, "add": {"name": "drop1", "shape": {"type": "sphere", "radius": 0.4}, "position": [0.1, 6, 0]}},
    {"step": 50, "remove": "c"},
    {"step": 100, "impulse": {"body": "a", "impulse": [1, 0, 0]}},
    {"step": 130, "add": {"name": "drop2", "shape": {"type": "box", "half_extents": [0.3, 0.3, 0.3]},
                          "position": [0, 8, 0.2], "ignore": ["sat"]}},
    {"step": 150, "set_velocity": {"body": "rider", "velocity": [0, 3, 0]}},
    {"step": 180, "remove": "b"}]})";

}  // namespace

// The reference scenes (scenes/): the 10-box stack saved at step 300 of 600 (asleep by
// then), the 1000-box pile saved at steps 60 (contacts, warm starts, bodies resting towards
// sleep) and 75 (a few steps before the whole pile falls asleep: rest times decide that
// step) of 120. The load runs on two threads, the uninterrupted run on one.
TEST_F(Cli, ReferenceScenesLoadedFromAStateEndWithTheUninterruptedHash) {
  struct Case {
    const char* scene;
    std::uint64_t steps, save;
  };
  for (const Case& c : {Case{"box_stack_10", 600, 300}, Case{"box_pile_1000", 120, 60}, Case{"box_pile_1000", 120, 75}}) {
    SCOPED_TRACE(std::string(c.scene) + " saved at step " + std::to_string(c.save));
    const std::string scene = Quote(ReferenceScenePath(c.scene)) + " --steps " + std::to_string(c.steps);
    const Result whole = Run(scene + " --threads 1 --out " + Quote(Path("whole.csv")));
    ASSERT_EQ(whole.code, 0) << whole.err;
    const Result first = Run(scene + " --threads 1 --out /dev/null --save-state " + std::to_string(c.save) + ":" +
                             Path("state.bin").string());
    ASSERT_EQ(first.code, 0) << first.err;
    EXPECT_EQ(Hash(first), Hash(whole)) << "saving changed the run";
    const Result loaded = Run(scene + " --threads 2 --out " + Quote(Path("loaded.csv")) + " --load-state " +
                              Quote(Path("state.bin")));
    ASSERT_EQ(loaded.code, 0) << loaded.err;
    EXPECT_EQ(Hash(loaded), Hash(whole));
    EXPECT_EQ(RowsFrom(ReadFile(Path("loaded.csv")), 0), RowsFrom(ReadFile(Path("whole.csv")), c.save))
        << "the loaded run's trajectory starts at the saved step and matches from there";
  }
}

// A scene with actions before and after the save: the state holds what the actions up to
// step N did (a spawn, a removal), the load runs only the later ones, and the trajectory and
// the events from step N on are those of the run that never stopped. Saved at step 0 too
// (before anything ran), and loaded and saved again: the same bytes.
TEST_F(Cli, AGameWithActionsContinuesFromItsState) {
  const std::string scene = Quote(Write("game.json", kGame));
  const Result whole = Run(scene + " --threads 1 --out " + Quote(Path("whole.csv")) + " --events " +
                           Quote(Path("whole_events.csv")));
  ASSERT_EQ(whole.code, 0) << whole.err;
  for (std::uint64_t save : {0, 90, 140}) {
    SCOPED_TRACE("saved at step " + std::to_string(save));
    const std::string state = Path("state" + std::to_string(save) + ".bin").string();
    const Result first = Run(scene + " --out /dev/null --save-state " + std::to_string(save) + ":" + state);
    ASSERT_EQ(first.code, 0) << first.err;
    const Result loaded = Run(scene + " --threads 2 --out " + Quote(Path("loaded.csv")) + " --events " +
                              Quote(Path("loaded_events.csv")) + " --load-state " + Quote(state) +
                              " --save-state " + std::to_string(save) + ":" + Path("again.bin").string());
    ASSERT_EQ(loaded.code, 0) << loaded.err;
    EXPECT_EQ(Hash(loaded), Hash(whole));
    EXPECT_EQ(RowsFrom(ReadFile(Path("loaded.csv")), 0), RowsFrom(ReadFile(Path("whole.csv")), save));
    // Events of the steps after the save (the first step's need the pairs touching at the
    // save: the saving run tracks them although it writes no events).
    EXPECT_EQ(RowsFrom(ReadFile(Path("loaded_events.csv")), 0), RowsFrom(ReadFile(Path("whole_events.csv")), save + 1));
    EXPECT_EQ(ReadFile(Path("again.bin")), ReadFile(state)) << "load, then save at once: the same bytes";
  }
  EXPECT_FALSE(RowsFrom(ReadFile(Path("whole_events.csv")), 91).empty()) << "no events after the save to compare";
}

// Bad input, exit 2, the file named: a text file, an empty file, a cut state, another
// scene's state, a state beyond the run's steps, a missing file; and --save-state's own
// mistakes.
TEST_F(Cli, BadStatesExitTwoNamingTheFile) {
  const std::string game = Quote(Write("game.json", kGame));
  const std::string stack = Quote(ReferenceScenePath("box_stack_10"));
  ASSERT_EQ(Run(game + " --out /dev/null --save-state 60:" + Path("game.bin").string()).code, 0);
  ASSERT_EQ(Run(stack + " --out /dev/null --save-state 60:" + Path("stack.bin").string()).code, 0);
  const std::string state = ReadFile(Path("game.bin"));
  Write("cut.bin", state.substr(0, state.size() / 2));
  Write("text.bin", "step,time,body\n0,0,a\n");
  Write("empty.bin", "");
  struct Case {
    std::string args, file, says;
  };
  const std::vector<Case> cases = {
      {stack + " --load-state " + Quote(Path("text.bin")), Path("text.bin").string(), "not a REngine world state"},
      {stack + " --load-state " + Quote(Path("empty.bin")), Path("empty.bin").string(), "not a REngine world state (0 bytes)"},
      {game + " --load-state " + Quote(Path("cut.bin")), Path("cut.bin").string(), "cut short"},
      {stack + " --load-state " + Quote(Path("game.bin")), Path("game.bin").string(), "saved from another scene"},
      {game + " --dt 0.01 --load-state " + Quote(Path("game.bin")), Path("game.bin").string(), "another step size"},
      {stack + " --steps 50 --load-state " + Quote(Path("stack.bin")), Path("stack.bin").string(), "beyond the 50 steps"},
      {game + " --load-state " + Quote(Path("missing.bin")), Path("missing.bin").string(), "cannot open the state"},
      {game + " --save-state 241:" + Path("x.bin").string(), "--save-state", "step 241 is not among the steps"},
      {game + " --load-state " + Quote(Path("game.bin")) + " --save-state 59:" + Path("x.bin").string(),
       "--save-state", "(60 to 240)"},
      {game + " --save-state 12", "--save-state", "must be STEP:FILE"},
      {game + " --save-state -1:" + Path("x.bin").string(), "--save-state", "must be STEP:FILE"},
      {game + " --save-state 5:" + Path("no/such/dir/x.bin").string(), Path("no/such/dir/x.bin").string(),
       "cannot open for writing"},
  };
  for (const Case& c : cases) {
    const Result r = Run(c.args + " --out /dev/null");
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find("error: " + c.file), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.args << "\n" << r.err;
  }
}

// What is not a file of bounded size is refused before it is read (exit 2, the path named):
// a directory, a device that never ends, a file past the 1 GiB a state may be (sparse: it
// takes no disk).
TEST_F(Cli, AStateThatIsNoRegularFileOrTooLargeExitsTwoNamingThePath) {
  const std::string stack = Quote(ReferenceScenePath("box_stack_10"));
  std::filesystem::create_directory(Path("dir"));
  Write("huge.bin", "");
  std::filesystem::resize_file(Path("huge.bin"), (std::uintmax_t(1) << 30) + 1);
  struct Case {
    std::string file, says;
  };
  for (const Case& c : {Case{Path("dir").string(), "not a regular file"}, Case{"/dev/zero", "not a regular file"},
                        Case{Path("huge.bin").string(), "it is 1073741825 bytes, more than the 1073741824"}}) {
    const Result r = Run(stack + " --out /dev/null --load-state " + Quote(c.file));
    EXPECT_EQ(r.code, 2) << c.file << "\n" << r.err;
    EXPECT_NE(r.err.find("error: " + c.file + ": cannot read the state: " + c.says), std::string::npos) << r.err;
  }
}

namespace {

// A state whose scene tag is rewritten to another scene's (the tag is a hash, not a
// signature): the 8 bytes after the 32-byte header, the checksum made right.
std::string Retagged(std::string state, std::uint64_t tag) {
  std::vector<std::uint8_t> bytes(state.begin(), state.end());
  REngine::state::StoreU64(bytes.data() + REngine::state::kHeaderBytes, tag);
  REngine::state::Seal(bytes);
  return std::string(bytes.begin(), bytes.end());
}

// The tag this run computes, from the refusal of a state with another tag ("this run's X)").
std::uint64_t TagOfRun(const Result& refused) {
  const std::size_t at = refused.err.find("this run's ");
  return at == std::string::npos ? 0 : std::stoull(refused.err.substr(at + 11, 16), nullptr, 16);
}

const std::string kJoints = R"({"gravity": [0, -9.81, 0], "steps": 40, "bodies": [
    {"name": "ground", "shape": {"type": "box", "half_extents": [5, 0.5, 5]}, "static": true},
    {"name": "arm", "shape": {"type": "box", "half_extents": [1, 0.1, 0.1]}, "position": [1, 2, 0]},
    {"name": "bob", "shape": {"type": "sphere", "radius": 0.2}, "position": [2, 1, 0], "friction": 0.5}],
  "joints": [
    {"name": "shoulder", "type": "hinge", "a": "arm", "b": "ground", "anchor": [0, 2, 0], "axis": [0, 0, 1],
     "limits": [-1.5, 1.5], "motor": {"speed": 1, "max_force": 50}},
    {"name": "wrist", "type": "ball", "a": "bob", "b": "arm", "anchor": [2, 2, 0]}]})";

}  // namespace

// A state whose tag is forged onto a scene that defines its joints or bodies otherwise is
// refused by the scene's path of the first field that differs, not run with the state's
// values.
TEST_F(Cli, AStateRetaggedForAnotherSceneIsRefusedByTheFirstDifference) {
  const std::string original = Quote(Write("joints.json", kJoints));
  ASSERT_EQ(Run(original + " --out /dev/null --save-state 20:" + Path("joints.bin").string()).code, 0);
  const std::string saved = ReadFile(Path("joints.bin"));
  struct Case {
    std::string from, to, field;
  };
  for (const Case& c : {Case{"\"limits\": [-1.5, 1.5]", "\"limits\": [-1, 1]", "joints[0].limits"},
                        Case{"\"max_force\": 50", "\"max_force\": 5", "joints[0].motor"},
                        Case{"\"type\": \"ball\"", "\"type\": \"fixed\"", "joints[1].type"},
                        Case{"\"friction\": 0.5", "\"friction\": 0.25", "bodies[2].friction"}}) {
    std::string text = kJoints;
    ASSERT_NE(text.find(c.from), std::string::npos) << c.from;
    text.replace(text.find(c.from), c.from.size(), c.to);
    const std::string other = Quote(Write("other.json", text));
    const std::uint64_t tag = TagOfRun(Run(other + " --out /dev/null --load-state " + Quote(Path("joints.bin"))));
    ASSERT_NE(tag, 0u) << c.to;
    Write("forged.bin", Retagged(saved, tag));
    const Result r = Run(other + " --out /dev/null --load-state " + Quote(Path("forged.bin")));
    EXPECT_EQ(r.code, 2) << c.to << "\n" << r.err;
    EXPECT_NE(r.err.find("error: " + Path("forged.bin").string() + ": " + c.field + ": "), std::string::npos)
        << c.to << "\n" << r.err;
  }
  // The tag rewritten to the original scene's own: the same scene, loaded.
  const std::uint64_t own = TagOfRun(Run(original + " --out /dev/null --load-state " + Quote(Write("x.bin", Retagged(saved, 1)))));
  Write("same.bin", Retagged(saved, own));
  EXPECT_EQ(Run(original + " --out /dev/null --load-state " + Quote(Path("same.bin"))).code, 0);
}
