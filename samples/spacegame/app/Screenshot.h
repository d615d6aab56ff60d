// The frame just drawn (the back buffer, before the swap) to a PNG file.
#pragma once

#include <string>

namespace spacegame {

// Throws std::runtime_error when the file cannot be written.
void WriteScreenshot(const std::string& path, int width, int height);

}  // namespace spacegame
