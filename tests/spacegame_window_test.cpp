// rengine-spacegame in a window (#17), under a virtual display (xvfb-run, Mesa's software
// OpenGL): the autoplay run twice ends on the same state hash, and its last frame, written
// as a PNG, shows a scene: many colours, none of them covering the screen.
#include <gtest/gtest.h>
#include <stb_image.h>

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

GameRun Autoplay(const std::string& name) {
  const std::string dir = RENGINE_SPACEGAME_OUT;
  const std::string png = dir + "/" + name + ".png", err = dir + "/" + name + ".stderr";
  std::remove(png.c_str());
  // -a: a free display number (ctest may run other tests beside this one). Under the
  // sanitizers (tools/sanitize.sh) the game's leaks are checked by spacegame_tests; here the
  // X server's client libraries and Mesa, which keep allocations for the process's life,
  // would be reported as the game's.
  const std::string command =
      "ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:detect_leaks=0\" " + std::string(RENGINE_XVFB_RUN) +
      " -a -s '-screen 0 800x600x24' " + RENGINE_SPACEGAME + " --autoplay --frames " +
      std::to_string(kFrames) + " --width " + std::to_string(kWidth) + " --height " +
      std::to_string(kHeight) + " --screenshot " + png + " 2> " + err;
  GameRun r;
  r.exitCode = std::system(command.c_str());
  std::ifstream in(err);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) r.lastLine = line;
  return r;
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

  int w = 0, h = 0, channels = 0;
  const std::string png = std::string(RENGINE_SPACEGAME_OUT) + "/autoplay-a.png";
  unsigned char* pixels = stbi_load(png.c_str(), &w, &h, &channels, 3);
  ASSERT_NE(pixels, nullptr) << png;
  EXPECT_EQ(w, kWidth);
  EXPECT_EQ(h, kHeight);
  std::unordered_map<unsigned, int> counts;
  for (int i = 0; i < w * h; ++i) {
    const unsigned char* p = pixels + 3 * i;
    ++counts[unsigned(p[0]) << 16 | unsigned(p[1]) << 8 | unsigned(p[2])];
  }
  stbi_image_free(pixels);
  int most = 0;
  for (const auto& [colour, n] : counts) most = std::max(most, n);
  const double share = double(most) / double(w * h);
  std::printf("last frame: %zu colours, the commonest on %.1f%% of the pixels\n", counts.size(),
              100 * share);
  EXPECT_GT(counts.size(), 500u);
  EXPECT_LT(share, 0.9);
}
