#pragma once
// One shadow map per VPL, from cube faces (layers of a 2D array): a whole cube (6 layers) for a medium VPL, which
// lights every direction, and a hemicube (3 layers) for a surface VPL, which lights only the half-space its geometric
// normal points into. A hemicube looks along the normal (a full face) and along the four tangent directions with the
// normal up, keeping only the upper half of each of these side faces, and packs two halves into one layer: +s above
// -s, +t above -t. It costs half the texels of a cube.
//
// Why cubes and not paraboloids or octahedral maps: a cube face is an ordinary perspective projection, so a triangle's
// edges stay straight in it and its coverage is exact. Paraboloid and octahedral maps are non-linear: a triangle's
// edges must curve and only come out right for finely tessellated geometry, while vplab's scenes are mostly a few
// large quads (the Cornell box walls are two triangles each) whose paraboloid images would be badly wrong near the
// caster, which is exactly where VPL shadows matter. Cubes also sample with hardware PCF. The faces are stored as
// layers of a 2D texture array (not a cube-map array) and the lookup picks the face itself
// (shaders/common/shadow.glsl): on llvmpipe a 2D-array PCF fetch is several times cheaper than seamless cube filtering,
// at the price of clamping the 2x2 filter at face edges. Each face is shadowMapSize / 2 texels wide: 6 (S/2)^2 = 1.5
// S^2 texels per whole cube, close to one S x S paraboloid, and half that per hemicube. Depth stores the radial
// distance / far, so one comparison works on every face.
//
// The maps are drawn on the CPU (renderer/gl/distance_raster.h: the nearest triangle along each texel's ray), a caster
// per work item on every core, and uploaded. Drawn by GL through a geometry shader that fanned each triangle out to the
// faces, llvmpipe took about 9 ns per texel on two threads (the fragment shader writes the depth, so every covered
// texel runs it): 36 ms for 291 hemicubes of 64^2 on the Cornell box, and a cold start compiled three more shaders
// (docs/benchmarks.md "VPL maps on the CPU").
//
// A caster's layers follow from its index alone: casters with whole cubes come first (gatherOrder puts medium VPLs
// first), so caster c of a chunk whose first w casters have whole cubes starts at layer 3 c + 3 min(c, w).

#include <algorithm>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/gl/ism.h"
#include "renderer/gl/resources.h"
#include "renderer/scene/scene.h"

namespace vplab {

class CubeShadowMaps {
 public:
  CubeShadowMaps() = default;
  /// Draws the maps of the casters from caster `first` on (medium ones, with whole cubes, must come first); faces are
  /// faceSize texels wide. far: largest distance stored. With outOfTime, draws a batch of casters at a time and stops
  /// after one once it says so: returns the first caster not drawn (the next call's `first`, with the same casters), or
  /// -1 when every map is drawn. The maps do not depend on where it stopped, nor on the thread count.
  int render(const Scene& scene, const std::vector<VplCaster>& casters, int faceSize, float far, int threads,
             int first = 0, const std::function<bool()>& outOfTime = {});
  /// Draws again only the maps of the casters `moved` names (indices into `casters`, which holds as many casters as
  /// the last render, each as large a map as before, with the same face size and far): the others keep their maps.
  /// With outOfTime it stops after a batch once it says so and returns the first entry of `moved` not drawn, else -1.
  int renderMoved(const Scene& scene, const std::vector<VplCaster>& casters, const std::vector<int>& moved, int threads,
                  int first = 0, const std::function<bool()>& outOfTime = {});

  /// Casters are split into chunks of at most GL_MAX_ARRAY_TEXTURE_LAYERS layers, each one texture.
  int chunkCount() const { return static_cast<int>(chunks_.size()); }
  int chunkBegin(int chunk) const { return chunkBegins_[static_cast<std::size_t>(chunk)]; }
  int chunkEnd(int chunk) const { return chunkBegins_[static_cast<std::size_t>(chunk) + 1]; }
  /// How many of the chunk's casters (its first ones) have whole cubes; the rest have hemicubes.
  int chunkWholeCubes(int chunk) const {
    return std::clamp(wholeCubes_ - chunkBegin(chunk), 0, chunkEnd(chunk) - chunkBegin(chunk));
  }
  const GlTexture& chunkTexture(int chunk) const { return chunks_[static_cast<std::size_t>(chunk)]; }
  int casterCount() const { return static_cast<int>(firstLayers_.size()); }
  float far() const { return far_; }

 private:
  /// Chunks, whole cubes and each caster's first layer for `casters`.
  void layOut(const std::vector<VplCaster>& casters);
  int layersOf(int caster) const { return caster < wholeCubes_ ? 6 : 3; }
  /// Draws the maps of casters order[begin, end) and uploads them into their chunks; returns `end`, or the first of
  /// them not drawn when outOfTime said so after a batch.
  int drawCasters(const Scene& scene, const std::vector<VplCaster>& casters, const std::vector<int>& order, int begin,
                  int end, int threads, const std::function<bool()>& outOfTime);

  std::vector<GlTexture> chunks_;
  std::vector<int> chunkBegins_{0};
  std::vector<int> firstLayers_;
  int wholeCubes_ = 0;
  int maxLayers_ = 1;  // GL_MAX_ARRAY_TEXTURE_LAYERS
  int faceSize_ = 0;
  float far_ = 1.0f;
  // A batch's maps before their upload, kept between updates (a fresh buffer costs its size in page faults).
  std::vector<uint16_t> staging_;
};

}  // namespace vplab
