#include "renderer/gl/light_table.h"

#include <glad/gl.h>

#include <algorithm>
#include <numeric>

namespace vplab {

namespace {
// Calls visit(base, begin, end) for consecutive ranges [begin, end) that cover [first, last), each of which fits one
// uniform block bound from element base <= begin on.
template <class F>
void forEachUniformRange(const UniformTableLayout& layout, int first, int last, F&& visit) {
  for (int begin = first; begin < last;) {
    int base = begin / layout.alignment * layout.alignment;
    int end = std::min(last, base + layout.capacity);
    visit(base, begin, end);
    begin = end;
  }
}

// Subset s of a k x k pattern takes the lights i = s, s + k^2, ...; this is how far the first of them lies after
// `rangeBegin`, the first light of a draw's range (common/interleaved.glsl).
int subsetOffset(int rangeBegin, int subset, int k) {
  int k2 = k * k;
  return ((subset - rangeBegin % k2) + k2) % k2;
}
}  // namespace

UniformTableLayout uniformTableLayout(std::size_t elementBytes) {
  UniformTableLayout layout;
  layout.elementBytes = elementBytes;
  GLint blockBytes = 0, offsetAlignment = 1;
  glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &blockBytes);
  glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &offsetAlignment);
  const GLint bytes = static_cast<GLint>(elementBytes);
  layout.capacity = std::clamp(static_cast<int>(blockBytes / bytes), 1, 1024);
  // Element i starts at byte i * elementBytes, a multiple of the alignment when i is a multiple of this.
  layout.alignment = std::max(1, offsetAlignment / std::gcd(offsetAlignment, bytes));
  if (layout.alignment > layout.capacity) throw GlError("uniform buffer offset alignment larger than a block");
  return layout;
}

std::string uniformTableDefine(const char* name, const UniformTableLayout& layout) {
  return std::string(name) + " " + std::to_string(layout.capacity);
}

void drawInterleavedLightTable(ShaderProgram& program, Target& raw, const InterleavedLayout& layout,
                               const LightTable& table, const GlVertexArray& vao, PassSlices& slices) {
  struct Range {
    int chunk, base, begin, end;
  };
  std::vector<Range> ranges;
  for (int c = 0; c < static_cast<int>(table.chunks.size()); ++c)
    forEachUniformRange(table.layout, table.chunks[c].begin, table.chunks[c].end,
                        [&](int base, int begin, int end) { ranges.push_back({c, base, begin, end}); });
  auto programOf = [&](const LightChunk& c) -> ShaderProgram& { return c.program ? *c.program : program; };
  const int k = layout.k;
  const int perSubset = static_cast<int>(ranges.size()), total = k * k * perSubset;
  auto drawn = [&](int subset, const Range& r) {
    return table.drawEmptySubsets || r.begin + subsetOffset(r.begin, subset, k) < r.end;
  };
  raw.framebuffer.bind(layout.blockWidth * k, layout.blockHeight * k);
  // Draws add up (several ranges per subset) or are left out (a subset without lights in a range: a scene with fewer
  // punctual lights than k^2 subsets draws only the subsets that have one), so the blocks start from zero. Where each
  // subset is one draw, that draw writes every texel of its block and no clear is needed (a 640x480 RGBA32F clear
  // took about 1.9 ms of llvmpipe's CPU time at load 7, docs/benchmarks.md "GL preview").
  bool oneDrawPerBlock = perSubset == 1;
  for (int subset = 0; subset < k * k && oneDrawPerBlock; ++subset) oneDrawPerBlock = drawn(subset, ranges.front());
  if (!oneDrawPerBlock) slices.step([&] { raw.framebuffer.clearColor(0, glm::vec4(0.0f)); });
  for (const LightChunk& c : table.chunks) {
    programOf(c).set("uInterleave", k);
    programOf(c).set("uImageSize", glm::ivec2(layout.width, layout.height));
  }
  if (perSubset > 1) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
  }
  int boundChunk = -1;
  for (int draw = 0; draw < total; ++draw) {
    const int subset = draw / perSubset;
    const Range& r = ranges[static_cast<std::size_t>(draw % perSubset)];
    const LightChunk& chunk = table.chunks[static_cast<std::size_t>(r.chunk)];
    ShaderProgram& p = programOf(chunk);
    const int offset = subsetOffset(r.begin, subset, k);
    if (!drawn(subset, r)) continue;
    const int sx = subset % k, sy = subset / k;
    const glm::ivec2 origin(sx * layout.blockWidth, sy * layout.blockHeight);
    slices.bands(glm::ivec4(origin, layout.blockWidth, layout.blockHeight), [&] {
      glViewport(origin.x, origin.y, layout.blockWidth, layout.blockHeight);
      p.set("uSubsetXY", glm::ivec2(sx, sy));
      p.set("uBlockOrigin", origin);
      if (r.chunk != boundChunk) {
        if (table.bindChunk) table.bindChunk(chunk.maps, p);
        p.set("uFirstLight", chunk.mapsBegin);
        boundChunk = r.chunk;
      }
      table.buffer->bindUniformRange(binding(table.binding),
                                     static_cast<std::size_t>(r.base) * table.layout.elementBytes,
                                     static_cast<std::size_t>(r.end - r.base) * table.layout.elementBytes);
      p.set("uUboBase", r.base);
      p.set("uLightBegin", r.begin);
      p.set("uSubsetOffset", offset);
      p.set("uLightEnd", r.end);
      drawFullscreen(p, vao);
    });
  }
  glDisable(GL_BLEND);
}

}  // namespace vplab
