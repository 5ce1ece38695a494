#include "renderer/gl/density_grids_gpu.h"

#include <glad/gl.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>

#include "renderer/gl/gl_limits.h"
#include "renderer/gl/media_pass.h"
#include "renderer/gl/texture_units.h"

namespace vplab {

namespace {
// NanoVDB's alignment of a grid in memory (NANOVDB_DATA_ALIGNMENT): each grid in the buffer starts at a multiple.
constexpr std::size_t kNanoVdbAlignment = 32;

// What an over-large buffer is refused with, naming the grids in it.
std::string bufferTooLarge(const std::vector<std::string>& names, std::size_t bytes, double maxBlock) {
  std::string which;
  for (const std::string& n : names) which += (which.empty() ? "'" : ", '") + n + "'";
  const bool one = names.size() == 1;
  return (one ? "density grid " : "density grids ") + which +
         (one ? ": its NanoVDB grid takes " : ": their NanoVDB grids take ") + formatBytes(static_cast<double>(bytes)) +
         (one ? "" : " together") + ", over this GL context's largest storage block (" + formatBytes(maxBlock) +
         "): use a coarser grid, or vplab render";
}
}  // namespace

void DensityGridsGpu::update(const std::vector<Wanted>& wanted) {
  std::vector<Held> next(wanted.size());
  // Per grid: its new NanoVDB words, or where the buffer it is kept from held it.
  std::vector<std::vector<uint32_t>> words(wanted.size());
  std::vector<std::size_t> keptAt(wanted.size(), SIZE_MAX);
  for (std::size_t g = 0; g < wanted.size(); ++g) {
    const Wanted& w = wanted[g];
    auto kept = std::find_if(held_.begin(), held_.end(),
                             [&](const Held& h) { return h.grid == w.grid && h.storage == w.storage; });
    if (kept != held_.end()) {
      if (w.storage == DensityGridStorage::Buffer) keptAt[g] = kept->offset;
      next[g] = std::move(*kept);
      kept->grid.reset();  // taken: a second medium with the same grid gets its own copy
      continue;
    }
    Held& h = next[g];
    h.grid = w.grid;
    h.storage = w.storage;
    h.weightedDensity = scatteringWeightedDensity(*w.grid);
    ++uploads_;
    if (w.storage == DensityGridStorage::Texture) {
      h.texture = GlTexture::volume(w.grid->size, w.grid->values);
    } else {
      words[g] = nanoVdbFloatGrid(*w.grid);
      h.bytes = words[g].size() * sizeof(uint32_t);
    }
  }

  // The buffer's grids one after the other in grid order; laid out anew only where that moves or adds one.
  std::size_t bytes = 0;
  bool unchanged = true;
  std::vector<std::string> names;
  for (std::size_t g = 0; g < next.size(); ++g) {
    if (next[g].storage != DensityGridStorage::Buffer) continue;
    next[g].offset = (bytes + kNanoVdbAlignment - 1) / kNanoVdbAlignment * kNanoVdbAlignment;
    bytes = next[g].offset + next[g].bytes;
    unchanged = unchanged && keptAt[g] == next[g].offset;
    names.push_back(next[g].grid->gridName);
  }
  unchanged = unchanged && bytes == bufferBytes_;
  if (!unchanged) {
    GLint64 maxBlock = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    if (static_cast<double>(bytes) > static_cast<double>(maxBlock)) {
      held_.clear();
      buffer_ = GlBuffer();
      bufferBytes_ = 0;
      throw std::runtime_error(bufferTooLarge(names, bytes, static_cast<double>(maxBlock)));
    }
    GlBuffer laidOut = bytes > 0 ? GlBuffer(bytes) : GlBuffer();
    for (std::size_t g = 0; g < next.size(); ++g) {
      const Held& h = next[g];
      if (h.storage != DensityGridStorage::Buffer) continue;
      if (keptAt[g] != SIZE_MAX)
        glCopyNamedBufferSubData(buffer_.id(), laidOut.id(), static_cast<GLintptr>(keptAt[g]),
                                 static_cast<GLintptr>(h.offset), static_cast<GLsizeiptr>(h.bytes));
      else
        laidOut.upload(words[g].data(), h.bytes, h.offset);
    }
    buffer_ = std::move(laidOut);
    bufferBytes_ = bytes;
  }
  held_ = std::move(next);
}

std::string DensityGridsGpu::summary(int g) const {
  const Held& h = held_[g];
  const glm::ivec3 n = h.grid->size;
  const double bytes = h.storage == DensityGridStorage::Texture ? 4.0 * n.x * n.y * static_cast<double>(n.z)
                                                                : static_cast<double>(h.bytes);
  return std::string(toString(h.storage)) + ", " + std::to_string(n.x) + "x" + std::to_string(n.y) + "x" +
         std::to_string(n.z) + " voxels, " + formatBytes(bytes);
}

void DensityGridsGpu::bind() const {
  for (std::size_t g = 0; g < held_.size(); ++g)
    if (held_[g].texture) held_[g].texture.bind(unit(TextureUnit::MediaDensity) + static_cast<int>(g));
  if (bufferBytes_ > 0) buffer_.bindStorage(binding(BufferBinding::MediaDensityGrid));
}

}  // namespace vplab
