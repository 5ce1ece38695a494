#pragma once
// A table of lights (the direct light's samples, the VPLs) that a screen pass sums over, read from uniform blocks, and
// its interleaved draw (common/interleaved.glsl).

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "renderer/gl/resources.h"
#include "renderer/gl/screen_pass.h"
#include "renderer/gl/shader.h"
#include "renderer/gl/texture_units.h"

namespace vplab {

/// How a table is split into uniform-block ranges: llvmpipe reads uniform blocks faster than storage buffers, so a
/// table longer than a block is drawn in ranges.
struct UniformTableLayout {
  std::size_t elementBytes = 0;
  int capacity = 1;   ///< elements per block
  int alignment = 1;  ///< a bound range starts at a multiple of this many elements
};

/// A block holds what GL_MAX_UNIFORM_BLOCK_SIZE allows, at most 1024 elements (so that the shader's array stays small
/// where a driver allows very large blocks); a range is bound from an element whose byte offset is a multiple of
/// GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT. Needs a current context.
UniformTableLayout uniformTableLayout(std::size_t elementBytes);
/// "NAME capacity": the define that sizes the shader's array.
std::string uniformTableDefine(const char* name, const UniformTableLayout& layout);

/// Lights [begin, end) of a table that share one bound set of shadow maps and one program.
struct LightChunk {
  int begin = 0, end = 0;
  /// Which set of maps (LightTable::bindChunk's argument), and its first light (the shader's uFirstLight).
  int maps = 0, mapsBegin = 0;
  /// The program that draws these lights; nullptr: the one drawInterleavedLightTable is given.
  ShaderProgram* program = nullptr;
};

struct LightTable {
  const GlBuffer* buffer = nullptr;
  BufferBinding binding = BufferBinding::Vpls;
  UniformTableLayout layout;
  std::vector<LightChunk> chunks;
  /// Binds a set of maps and sets their uniforms on `program`; may be empty.
  std::function<void(int maps, ShaderProgram& program)> bindChunk;
  /// Draw a subset's block even where the range holds none of the subset's lights: the VPL gather's glossy receivers
  /// take every VPL of the range (common/gather.glsl), whichever subset their pixel has.
  bool drawEmptySubsets = false;
};

/// Draws `table` with `program` (or each chunk's own) into the interleaved layout of `raw`: for each subset, one draw
/// per uniform-block range of each chunk. A single draw per subset replaces its block's texels (every fragment writes),
/// so it needs neither a clear nor blending; several draws add up. Each draw is a step of `slices`, drawn in bands
/// under a budget (a draw's sum is complete on its own and a pixel's draws keep their order, so the rest can follow
/// later and the texels do not depend on where a call stopped).
void drawInterleavedLightTable(ShaderProgram& program, Target& raw, const InterleavedLayout& layout,
                               const LightTable& table, const GlVertexArray& vao, PassSlices& slices);

}  // namespace vplab
