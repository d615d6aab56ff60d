// rengine-spacegame and rengine-view in a window, under a virtual display (xvfb-run,
// Mesa's software OpenGL): the game's autoplay run twice ends on the same state hash, and its
// last frame, written as a PNG, shows a scene: many colours, none of them covering the
// screen; --record keeps every K-th frame without changing the hash; rengine-view plays a
// trajectory of rengine-sim's and shows it the same way.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

constexpr int kFrames = 150;  // the first missile goes off near frame 125
constexpr int kWidth = 640, kHeight = 360;

struct GameRun {
  int exitCode = -1;
  std::string lastLine;  // the last line of stderr
};

// Distinct colours of a PNG, the share of the pixels the commonest one covers, and the share
// that is lit (a channel above 60 of 255: shapes, not the near-black sky; stars are points).
struct Picture {
  int width = 0, height = 0;
  std::size_t colours = 0;
  double commonest = 1;
  double lit = 0;
};
Picture Look(const std::string& png) {
  Picture p;
  int channels = 0;
  unsigned char* pixels = stbi_load(png.c_str(), &p.width, &p.height, &channels, 3);
  if (!pixels) return p;
  std::unordered_map<unsigned, int> counts;
  int lit = 0;
  for (int i = 0; i < p.width * p.height; ++i) {
    const unsigned char* c = pixels + 3 * i;
    ++counts[unsigned(c[0]) << 16 | unsigned(c[1]) << 8 | unsigned(c[2])];
    lit += std::max({c[0], c[1], c[2]}) > 60;
  }
  p.lit = double(lit) / double(p.width * p.height);
  stbi_image_free(pixels);
  int most = 0;
  for (const auto& [colour, n] : counts) most = std::max(most, n);
  p.colours = counts.size();
  p.commonest = double(most) / double(p.width * p.height);
  return p;
}

// A command under the virtual display, its stderr to a file; its exit code and last line.
GameRun UnderXvfb(const std::string& command, const std::string& err) {
  // -a: a free display number (ctest may run other tests beside this one). Under the
  // sanitizers (tools/sanitize.sh) the game's leaks are checked by spacegame_tests; here the
  // X server's client libraries and Mesa, which keep allocations for the process's life,
  // would be reported as the game's.
  const std::string line = "ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:detect_leaks=0\" " +
                           std::string(RENGINE_XVFB_RUN) + " -a -s '-screen 0 800x600x24' " +
                           command + " 2> " + err;
  GameRun r;
  r.exitCode = std::system(line.c_str());
  std::ifstream in(err);
  for (std::string text; std::getline(in, text);)
    if (!text.empty()) r.lastLine = text;
  return r;
}

GameRun Autoplay(const std::string& name) {
  const std::string dir = RENGINE_SPACEGAME_OUT;
  const std::string png = dir + "/" + name + ".png", err = dir + "/" + name + ".stderr";
  std::remove(png.c_str());
  return UnderXvfb(std::string(RENGINE_SPACEGAME) + " --autoplay --frames " +
                       std::to_string(kFrames) + " --width " + std::to_string(kWidth) +
                       " --height " + std::to_string(kHeight) + " --screenshot " + png,
                   err);
}

std::string HashOf(const std::string& line) {
  const std::size_t at = line.find("hash=");
  return at == std::string::npos ? std::string() : line.substr(at + 5);
}

}  // namespace

TEST(SpaceGameWindow, TheAutoplayRepeatsAndItsLastFrameShowsAScene) {
  const GameRun a = Autoplay("autoplay-a");
  const GameRun b = Autoplay("autoplay-b");
  std::printf("run a: %s\nrun b: %s\n", a.lastLine.c_str(), b.lastLine.c_str());
  ASSERT_EQ(a.exitCode, 0) << a.lastLine;
  ASSERT_EQ(b.exitCode, 0) << b.lastLine;
  EXPECT_EQ(a.lastLine.rfind("frames=" + std::to_string(kFrames) + " ", 0), 0u) << a.lastLine;
  ASSERT_FALSE(HashOf(a.lastLine).empty());
  EXPECT_EQ(HashOf(a.lastLine), HashOf(b.lastLine));

  const Picture p = Look(std::string(RENGINE_SPACEGAME_OUT) + "/autoplay-a.png");
  EXPECT_EQ(p.width, kWidth);
  EXPECT_EQ(p.height, kHeight);
  std::printf("last frame: %zu colours, the commonest on %.1f%% of the pixels, %.1f%% lit\n",
              p.colours, 100 * p.commonest, 100 * p.lit);
  EXPECT_GT(p.colours, 500u);
  EXPECT_LT(p.commonest, 0.9);
  EXPECT_GT(p.lit, 0.1);
}

// --record DIR --record-every 10 on a 30-frame autoplay: DIR/frame_00000.png to frame_00002.png
// (frames 10, 20 and 30) at the window's size, no fourth; and the hash of the run with
// --record is the hash of the run without (reading frames back touches no physics). Bad
// --record arguments are usage errors (exit code 2) before any window opens.
TEST(SpaceGameWindow, RecordKeepsEveryKthFrameAndLeavesTheHash) {
  namespace fs = std::filesystem;
  const std::string out = RENGINE_SPACEGAME_OUT, dir = out + "/record-frames";
  fs::remove_all(dir);
  const std::string game =
      std::string(RENGINE_SPACEGAME) + " --autoplay --frames 30 --width 320 --height 180";
  const GameRun plain = UnderXvfb(game, out + "/record-plain.stderr");
  const GameRun recorded =
      UnderXvfb(game + " --record " + dir + " --record-every 10", out + "/record.stderr");
  std::printf("without --record: %s\nwith --record:    %s\n", plain.lastLine.c_str(),
              recorded.lastLine.c_str());
  ASSERT_EQ(plain.exitCode, 0) << plain.lastLine;
  ASSERT_EQ(recorded.exitCode, 0) << recorded.lastLine;
  ASSERT_FALSE(HashOf(plain.lastLine).empty());
  EXPECT_EQ(HashOf(recorded.lastLine), HashOf(plain.lastLine));

  ASSERT_TRUE(fs::is_directory(dir));
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) files += entry.is_regular_file();
  EXPECT_EQ(files, 3u);
  for (int i = 0; i < 3; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%05d.png", i);
    const Picture p = Look(dir + name);
    EXPECT_EQ(p.width, 320) << name;
    EXPECT_EQ(p.height, 180) << name;
    EXPECT_GT(p.colours, 100u) << name;
  }

  // Parsed before the window opens: no virtual display needed.
  for (const std::string& bad : std::vector<std::string>{
           " --autoplay --record-every 0 --record " + dir, " --autoplay --record-every 10",
           " --record " + dir, " --autoplay --frames 5 --record " + dir + " --record-every 6",
           " --autoplay --record /dev/null/frames", " --autoplay --record"}) {
    const std::string line =
        std::string(RENGINE_SPACEGAME) + bad + " 2> " + out + "/record-usage.stderr";
    const int code = std::system(line.c_str());
    EXPECT_TRUE(WIFEXITED(code) && WEXITSTATUS(code) == 2) << bad << ": " << code;
  }
}

// Played (not the autoplay) for 40 frames with no key pressed: the wall-clock loop runs, reads
// the keyboard, takes the steps the elapsed time owes (how many depends on the machine), and
// quits cleanly. The hash is not compared: wall-clock frames differ from run to run.
TEST(SpaceGameWindow, PlayedUntouchedTheGameRunsItsClockLoop) {
  const std::string dir = RENGINE_SPACEGAME_OUT;
  const GameRun r =
      UnderXvfb(std::string(RENGINE_SPACEGAME) + " --frames 40 --width 320 --height 200",
                dir + "/play.stderr");
  std::printf("played: %s\n", r.lastLine.c_str());
  ASSERT_EQ(r.exitCode, 0) << r.lastLine;
  EXPECT_EQ(r.lastLine.rfind("frames=40 steps=", 0), 0u) << r.lastLine;
}

// The shared cloud of 1000 boxes run by rengine-sim for a second, played back by rengine-view for
// 30 frames: every body drawn, and a picture, not a blank screen.
TEST(SpaceGameWindow, RengineViewPlaysATrajectoryOfRengineSim) {
  const std::string dir = RENGINE_SPACEGAME_OUT;
  const std::string scene = std::string(RENGINE_SCENES) + "/debris_cloud_1000.json";
  const std::string csv = dir + "/view-cloud.csv", png = dir + "/view-cloud.png";
  std::remove(png.c_str());
  const std::string sim = std::string(RENGINE_SIM) + " " + scene + " --steps 60 --quiet --out " +
                          csv + " 2> " + dir + "/view-cloud.sim.stderr";
  ASSERT_EQ(std::system(sim.c_str()), 0) << sim;
  const GameRun r =
      UnderXvfb(std::string(RENGINE_VIEW) + " " + scene + " " + csv +
                    " --frames 30 --width 640 --height 360 --no-hud --screenshot " + png,
                dir + "/view-cloud.stderr");
  std::printf("rengine-view: %s\n", r.lastLine.c_str());
  ASSERT_EQ(r.exitCode, 0) << r.lastLine;
  EXPECT_EQ(r.lastLine.rfind("frames=30 ", 0), 0u) << r.lastLine;
  EXPECT_NE(r.lastLine.find("bodies=1000"), std::string::npos) << r.lastLine;
  const Picture p = Look(png);
  std::printf(
      "rengine-view frame: %zu colours, the commonest on %.1f%% of the pixels, %.1f%% lit\n",
      p.colours, 100 * p.commonest, 100 * p.lit);
  EXPECT_EQ(p.width, 640);
  EXPECT_GT(p.colours, 200u);
  // A cloud is mostly sky between its boxes: the sky may take more than in the game's frame.
  EXPECT_LT(p.commonest, 0.95);
  EXPECT_GT(p.lit, 0.05);
}
