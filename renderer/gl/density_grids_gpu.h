#pragma once
// The preview's density grids on the GPU (docs/theory.md §22, docs/methods.md "Smoke in the preview"), one per grid
// medium, in the storage densityGridStorage() picks for each (renderer/gl/density_grid_storage.h): grid g in its own
// R32F 3D texture on unit TextureUnit::MediaDensity + g, or as a NanoVDB grid in the one storage buffer bound at
// BufferBinding::MediaDensityGrid, at a byte offset of its own (shaders/common/medium.glsl reads both).
// One buffer for all NanoVDB grids rather than one each: PNanoVDB.h's GLSL reader reads a single storage array
// (pnanovdb_buf_data), and addresses a grid by its byte offset in it, so grids in separate buffers would each need a
// reader of their own.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "renderer/gl/density_grid_storage.h"
#include "renderer/gl/resources.h"

namespace vplab {

class DensityGridsGpu {
 public:
  struct Wanted {
    std::shared_ptr<const DensityGrid> grid;
    DensityGridStorage storage = DensityGridStorage::Texture;
  };
  /// Makes grid g `wanted[g]`. A grid already held in the same storage (at any index) is kept as it is: only the new
  /// ones are uploaded, and where the NanoVDB buffer is laid out anew the grids it keeps are copied within the GPU.
  /// Throws std::runtime_error, holding no grid then, when the NanoVDB grids together exceed the context's largest
  /// storage block.
  void update(const std::vector<Wanted>& wanted);
  int count() const { return static_cast<int>(held_.size()); }
  DensityGridStorage storage(int g) const { return held_[g].storage; }
  /// The byte offset of grid g's NanoVDB grid in the buffer (meaningful for the Buffer storage).
  std::size_t bufferOffset(int g) const { return held_[g].offset; }
  /// scatteringWeightedDensity (renderer/gl/media_pass.h) of grid g, computed once per upload.
  float weightedDensity(int g) const { return held_[g].weightedDensity; }
  /// Where grid g is and what it takes, e.g. "3D texture, 34x50x34 voxels, 0.22 MiB".
  std::string summary(int g) const;
  /// Grids uploaded since construction (a test's view of what a change re-uploads).
  int uploads() const { return uploads_; }
  /// Binds every grid's texture to its unit, and the buffer where it holds any grid.
  void bind() const;

 private:
  struct Held {
    std::shared_ptr<const DensityGrid> grid;  // kept, so that a new grid is never taken for it at the same address
    DensityGridStorage storage = DensityGridStorage::Texture;
    float weightedDensity = 0.0f;
    GlTexture texture;                  // Texture storage
    std::size_t offset = 0, bytes = 0;  // Buffer storage: its NanoVDB grid's range in buffer_
  };
  std::vector<Held> held_;
  GlBuffer buffer_;
  std::size_t bufferBytes_ = 0;  // the NanoVDB grids' bytes in buffer_ (0: none)
  int uploads_ = 0;
};

}  // namespace vplab
