#include "renderer/gl/shadow_maps.h"

#include <glad/gl.h>

#include <stdexcept>

#include "renderer/core/parallel.h"
#include "renderer/core/sampling.h"
#include "renderer/gl/distance_raster.h"

namespace vplab {

namespace {

// Casters drawn between two looks at the budget (outOfTime), per thread: a hemicube of 64^2 takes about 0.1 ms.
constexpr int kBatchPerThread = 8;
// Without a budget: batches small enough that the staging buffer is reused instead of growing to every map's size (a
// fresh buffer costs its size in page faults: 28 MB for 291 hemicubes of 128^2), large enough that starting the
// threads is not what the batch costs.
constexpr int kUnbudgetedBatchPerThread = 32;
// Whatever the batch, its staging buffer holds at most this many bytes of maps, and a batch at least one caster per
// thread: at the largest faces (1024^2) a whole cube is 12 MB.
constexpr std::size_t kStagingBytes = std::size_t{16} << 20;
// What lies nearer than this fraction of `far` along a face's axis is not drawn.
constexpr float kNearFraction = 1e-5f;

// A hemicube's five views in the order of its layers (shaders/common/shadow.glsl hemicubeShadowCoordinates): along the
// normal (x = s, y = t), then along +s, -s (x = t) and +t, -t (x = s), each with the normal up and only its upper half.
// The frame is the one the lookup builds (shaders/common/math.glsl orthonormalFrame, the same as Frame).
std::vector<DistanceRasterizer::Perspective> hemicubeViews(glm::vec3 n, int size) {
  const Frame f(n);
  const int half = size / 2;
  return {{f.s, f.t, n, 0}, {f.t, n, f.s, half}, {f.t, n, -f.s, half}, {f.s, n, f.t, half}, {f.s, n, -f.t, half}};
}

// Distance / far as a 16-bit depth, as GL stores a fragment depth in a DEPTH_COMPONENT16 texture; 1 where nothing lies
// (kNoOccluder).
inline uint16_t depth16(float distance, float inverseFar) {
  const float depth = std::min(distance * inverseFar, 1.0f);
  return static_cast<uint16_t>(depth * 65535.0f + 0.5f);
}

}  // namespace

void CubeShadowMaps::layOut(const std::vector<VplCaster>& casters) {
  GLint maxLayers = 0;
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  maxLayers_ = std::max(6, static_cast<int>(maxLayers));
  wholeCubes_ = 0;
  while (wholeCubes_ < static_cast<int>(casters.size()) && casters[static_cast<std::size_t>(wholeCubes_)].inMedium)
    ++wholeCubes_;
  for (std::size_t i = static_cast<std::size_t>(wholeCubes_); i < casters.size(); ++i)
    if (casters[i].inMedium)
      throw std::logic_error("CubeShadowMaps: medium VPLs must come before surface VPLs (gatherOrder)");
  chunkBegins_.assign(1, 0);
  firstLayers_.resize(casters.size());
  int layer = 0;
  for (int c = 0; c < static_cast<int>(casters.size()); ++c) {
    if (layer + layersOf(c) > maxLayers_) {
      chunkBegins_.push_back(c);
      layer = 0;
    }
    firstLayers_[static_cast<std::size_t>(c)] = layer;
    layer += layersOf(c);
  }
  if (!casters.empty()) chunkBegins_.push_back(static_cast<int>(casters.size()));
}

int CubeShadowMaps::render(const Scene& scene, const std::vector<VplCaster>& casters, int faceSize, float far,
                           int threads, int first, const std::function<bool()>& outOfTime) {
  // The layers each chunk needs now, against what its texture holds.
  std::vector<int> held;
  for (const GlTexture& t : chunks_) held.push_back(t.layers());
  layOut(casters);
  far_ = far;
  const int chunks = static_cast<int>(chunkBegins_.size()) - 1;
  auto layersNeeded = [&](int c) { return firstLayers_[chunkEnd(c) - 1] + layersOf(chunkEnd(c) - 1); };
  // Keep the textures while they hold the maps: a new VPL set has about as many VPLs as the last (225-281 for 256
  // expected on the smoke box), and a fresh array costs its size in page faults, as llvmpipe zero-fills it (for 281
  // whole cubes at 128^2, 55 MB: about 100 ms on a 2-core VM, docs/benchmarks.md "Smoke in the preview"). An array
  // that grows gets a quarter more than it needs; one that would hold over twice the layers is made anew.
  bool reuse = faceSize == faceSize_ && static_cast<int>(held.size()) == chunks;
  for (int c = 0; reuse && c < chunks; ++c) {
    const int needed = layersNeeded(c);
    reuse = held[static_cast<std::size_t>(c)] >= needed && held[static_cast<std::size_t>(c)] <= 2 * needed;
  }
  if (!reuse) {
    const bool growing = faceSize == faceSize_ && !chunks_.empty();
    chunks_.clear();
    for (int c = 0; c < chunks; ++c) {
      const int needed = layersNeeded(c);
      const int allocated = growing ? std::min(maxLayers_, needed + (needed + 3) / 4) : needed;
      // 16-bit depth: the stored distance / far (far = 2 scene diagonals) is quantised to 3e-5 diagonals, far below
      // the depth bias (0.002 diagonals by default), and the gather, which misses the cache on nearly every shadow
      // fetch, reads half the bytes (8% faster at 640x480, 291 VPLs, k = 4).
      chunks_.push_back(GlTexture(faceSize, faceSize, TextureFormat::Depth16, 1, allocated, true));
      chunks_.back().setDepthCompare(true);
    }
    faceSize_ = faceSize;
  }
  if (casters.empty()) return -1;
  std::vector<int> order(casters.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  const int next = drawCasters(scene, casters, order, std::max(first, 0), casterCount(), threads, outOfTime);
  return next < casterCount() ? next : -1;
}

int CubeShadowMaps::renderMoved(const Scene& scene, const std::vector<VplCaster>& casters,
                                const std::vector<int>& moved, int threads, int first,
                                const std::function<bool()>& outOfTime) {
  if (static_cast<int>(casters.size()) != casterCount() || chunks_.empty())
    throw std::logic_error("CubeShadowMaps::renderMoved: the casters of the last render are not those");
  for (int c = 0; c < casterCount(); ++c)
    if (casters[static_cast<std::size_t>(c)].inMedium != (c < wholeCubes_))
      throw std::logic_error("CubeShadowMaps::renderMoved: a caster's map changed between a cube and a hemicube");
  const int count = static_cast<int>(moved.size());
  const int next = drawCasters(scene, casters, moved, std::max(first, 0), count, threads, outOfTime);
  return next < count ? next : -1;
}

int CubeShadowMaps::drawCasters(const Scene& scene, const std::vector<VplCaster>& casters,
                                const std::vector<int>& order, int begin, int end, int threads,
                                const std::function<bool()>& outOfTime) {
  const int size = faceSize_;
  const std::size_t layerTexels = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  const float inverseFar = 1.0f / far_;
  // A near plane, as a GL projection has: a surface VPL lies on its own triangle up to rounding, and that triangle must
  // not cover its map at distance 0.
  const float near = kNearFraction * far_;
  threads = std::max(1, threads);
  const std::size_t casterBytes = 6 * layerTexels * sizeof(uint16_t);  // a whole cube's, the most a caster has
  const int fitting = static_cast<int>(std::min<std::size_t>(kStagingBytes / casterBytes, 1 << 20));
  const int batch =
      std::max(threads, std::min((outOfTime ? kBatchPerThread : kUnbudgetedBatchPerThread) * threads, fitting));
  // Each thread's rasterizer and one view's distances.
  std::vector<DistanceRasterizer> rasterizers(static_cast<std::size_t>(threads));
  std::vector<std::vector<float>> views(static_cast<std::size_t>(threads), std::vector<float>(layerTexels));
  while (begin < end) {
    const int batchEnd = std::min(end, begin + batch);
    // Caster order[begin + k]'s layers start at layer offset[k] of the batch: casters whose layers follow each other
    // in a chunk are uploaded together.
    std::vector<std::size_t> offset(static_cast<std::size_t>(batchEnd - begin) + 1, 0);
    for (int k = 0; k < batchEnd - begin; ++k)
      offset[static_cast<std::size_t>(k) + 1] =
          offset[static_cast<std::size_t>(k)] +
          static_cast<std::size_t>(layersOf(order[static_cast<std::size_t>(begin + k)]));
    staging_.resize(offset.back() * layerTexels);
    parallelFor(batchEnd - begin, threads, [&](int64_t k, int thread) {
      const int c = order[static_cast<std::size_t>(begin + k)];
      const VplCaster& caster = casters[static_cast<std::size_t>(c)];
      DistanceRasterizer& raster = rasterizers[static_cast<std::size_t>(thread)];
      float* distances = views[static_cast<std::size_t>(thread)].data();
      uint16_t* layers = staging_.data() + offset[static_cast<std::size_t>(k)] * layerTexels;
      // Rows [rowBegin, size) of the view just drawn into `layer`, from row `toRow` on.
      auto store = [&](int layer, int rowBegin, int toRow) {
        uint16_t* out = layers + static_cast<std::size_t>(layer) * layerTexels + static_cast<std::size_t>(toRow) * size;
        const float* in = distances + static_cast<std::size_t>(rowBegin) * size;
        const std::size_t n = static_cast<std::size_t>(size - rowBegin) * size;
        for (std::size_t i = 0; i < n; ++i) out[i] = depth16(in[i], inverseFar);
      };
      if (c < wholeCubes_) {
        // GL's cube faces (distance_raster.h binCube), as shaders/common/shadow.glsl cubeShadowCoordinates reads them.
        raster.binCube(scene, caster.position, size, 1, near);
        for (int f = 0; f < 6; ++f) {
          raster.draw(f, 0.0f, 1, distances);
          store(f, 0, 0);
        }
      } else {
        raster.binPerspective(scene, caster.position, hemicubeViews(caster.normal, size), size, 1, near);
        const int half = size / 2;
        raster.draw(0, 0.0f, 1, distances);
        store(0, 0, 0);
        // The upper halves of the side faces: +s (+t) into the upper half of layer 1 (2), -s (-t) into its lower half.
        for (int side = 0; side < 4; ++side) {
          raster.draw(1 + side, 0.0f, 1, distances);
          store(1 + side / 2, half, side % 2 == 0 ? half : 0);
        }
      }
    });
    for (int k = 0; k < batchEnd - begin;) {
      const int c = order[static_cast<std::size_t>(begin + k)];
      int chunk = 0;
      while (c >= chunkEnd(chunk)) ++chunk;
      int run = 1;
      while (k + run < batchEnd - begin && order[static_cast<std::size_t>(begin + k + run)] == c + run &&
             c + run < chunkEnd(chunk))
        ++run;
      const int layers =
          static_cast<int>(offset[static_cast<std::size_t>(k + run)] - offset[static_cast<std::size_t>(k)]);
      chunks_[static_cast<std::size_t>(chunk)].uploadDepth16Layers(
          firstLayers_[static_cast<std::size_t>(c)], layers,
          staging_.data() + offset[static_cast<std::size_t>(k)] * layerTexels);
      k += run;
    }
    begin = batchEnd;
    if (outOfTime && begin < end && outOfTime()) break;
  }
  return begin;
}

}  // namespace vplab
