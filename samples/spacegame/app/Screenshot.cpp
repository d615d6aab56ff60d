#include "Screenshot.h"

#include <epoxy/gl.h>
// libstb-dev builds stb's implementations into libstb: the header alone here.
#include <stb_image_write.h>

#include <stdexcept>
#include <vector>

namespace spacegame {

void WriteScreenshot(const std::string& path, int width, int height) {
  std::vector<unsigned char> rgb(std::size_t(width) * std::size_t(height) * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  // GL's rows run bottom-up, PNG's top-down.
  stbi_flip_vertically_on_write(1);
  if (!stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3))
    throw std::runtime_error("cannot write " + path);
}

}  // namespace spacegame
