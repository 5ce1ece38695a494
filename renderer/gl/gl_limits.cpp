#include "renderer/gl/gl_limits.h"

#include <glad/gl.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

namespace vplab {

namespace {

// GL_NVX_gpu_memory_info and GL_ATI_meminfo enums (not in the core profile header).
constexpr GLenum kNvxCurrentAvailableVidmem = 0x9049;  // kB
constexpr GLenum kAtiTextureFreeMemory = 0x87FC;       // kB, first of four values

bool hasExtension(const char* name) {
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i) {
    const char* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
    if (e && std::strcmp(e, name) == 0) return true;
  }
  return false;
}

double availableSystemBytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kb = 0;
  std::string unit;
  while (meminfo >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024.0;
  return 4.0 * 1024 * 1024 * 1024;  // no /proc: assume a small machine
}

}  // namespace

GlLimits queryGlLimits() {
  GlLimits limits;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &limits.maxTextureSize);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &limits.maxArrayLayers);
  glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &limits.max3dTextureSize);
  GLint viewport[2] = {0, 0}, renderbuffer = 0;
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbuffer);
  limits.maxFramebufferSize = std::min({viewport[0], viewport[1], renderbuffer});
  glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &limits.maxTextureBufferSize);
  GLint kb[4] = {0, 0, 0, 0};
  if (hasExtension("GL_NVX_gpu_memory_info")) {
    glGetIntegerv(kNvxCurrentAvailableVidmem, kb);
    limits.memorySource = "GPU memory free (GL_NVX_gpu_memory_info)";
  } else if (hasExtension("GL_ATI_meminfo")) {
    glGetIntegerv(kAtiTextureFreeMemory, kb);
    limits.memorySource = "GPU texture memory free (GL_ATI_meminfo)";
  }
  while (glGetError() != GL_NO_ERROR) {
  }
  if (kb[0] > 0) {
    limits.memoryBytes = 0.5 * 1024.0 * kb[0];
  } else {
    limits.memoryBytes = 0.5 * availableSystemBytes();
    limits.memorySource = "available system memory (the driver reports none)";
  }
  return limits;
}

std::string formatBytes(double bytes) {
  std::ostringstream s;
  s.precision(3);
  if (bytes >= 1024.0 * 1024 * 1024)
    s << bytes / (1024.0 * 1024 * 1024) << " GiB";
  else
    s << bytes / (1024.0 * 1024) << " MiB";
  return s.str();
}

}  // namespace vplab
