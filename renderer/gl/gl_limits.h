#pragma once
// What the current GL context can hold, for the checks that refuse settings before any rendering (a failed
// allocation reports GL_OUT_OF_MEMORY and can leave a driver's context unusable, or crash it).

#include <string>

namespace vplab {

struct GlLimits {
  int maxTextureSize = 0;
  int maxArrayLayers = 0;
  int max3dTextureSize = 0;  ///< the longest side of a density grid's 3D texture (renderer/gl/density_grid_storage.h)
  /// Largest framebuffer the context renders (min of GL_MAX_VIEWPORT_DIMS and GL_MAX_RENDERBUFFER_SIZE).
  int maxFramebufferSize = 0;
  /// Texels of a buffer texture (GL_MAX_TEXTURE_BUFFER_SIZE): the compensation's tap buffers (renderer/gl/ssbc_pass.h).
  int maxTextureBufferSize = 0;
  /// Bytes of texture memory the preview lets itself allocate: half of what the driver reports free
  /// (GL_NVX_gpu_memory_info, GL_ATI_meminfo) or, for drivers that report nothing (software rasterisers and
  /// integrated GPUs allocate system memory), half of the system's available memory.
  double memoryBytes = 0;
  /// Where memoryBytes came from, for the error message.
  std::string memorySource;
};

/// Queries the current context (needs one).
GlLimits queryGlLimits();

/// Bytes as "1.5 GiB" / "300 MiB".
std::string formatBytes(double bytes);

}  // namespace vplab
