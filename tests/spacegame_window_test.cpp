// rengine-spacegame and rengine-view in a window (#17), under a virtual display (xvfb-run,
// Mesa's software OpenGL): the game's autoplay run twice ends on the same state hash, and its
// last frame, written as a PNG, shows a scene: many colours, none of them covering the
// screen; rengine-view plays a trajectory of rengine-sim's and shows it the same way.
#include <gtest/gtest.h>
#include <stb_image.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unordered_map>

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
  const std::string scene = std::string(RENGINE_SHARED_SCENES) + "/debris_cloud_1000.json";
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
