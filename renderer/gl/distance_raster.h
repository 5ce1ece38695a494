#pragma once
// Shadow maps drawn on the CPU (docs/methods.md "Direct light in the preview"): the six faces of a cube map of radial
// distances around a light, or one orthographic map of distances along a directional light; and the VPLs' cube and
// hemicube maps (renderer/gl/shadow_maps.h), whose faces are perspective views in any orientation. Each texel holds
// the distance to the nearest triangle along its centre's ray, plus a slope-scaled bias (none for the VPLs' maps).
//
// Why on the CPU: measured on llvmpipe (docs/benchmarks.md "Preview at scale"), GL spends about 150 ns per
// triangle on one thread setting up triangles that mostly cover no texel centre, so a million triangles took ~220 ms
// per light move; binned by rows and rasterized here on every core it is several times less, and every GL driver gets
// the same maps. On a GPU the upload of a 1024^2 face costs about a millisecond.
//
// A triangle covers a texel when the texel's ray passes through it: three edge planes through the light, each linear in
// the texel's face coordinates (homogeneous rasterization, Olano & Greer 1997), so triangles reaching behind the light
// need no clipping. Each texel keeps the smallest value any triangle gives it, whatever order the triangles come in:
// the maps are the same at any thread count.

#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/scene/scene.h"

namespace vplab {

/// Texel value where no triangle lies along the texel's ray.
inline constexpr float kNoOccluder = 3.0e38f;

class DistanceRasterizer {
 public:
  /// Sorts the scene's triangles into the rows of the six faces of a cube map of size^2 texels around `origin`, faces
  /// in GL's order (+x, -x, +y, -y, +z, -z). Texel (i, j) of face f is the ray along the direction a samplerCube lookup
  /// maps to it (GL 4.6 table 8.19, s = (i + 0.5) / size, t = (j + 0.5) / size).
  /// near: what lies nearer than this along a face's axis is left out, as GL's near plane clips it (a VPL map's own
  /// surface, which passes through its origin up to rounding, would otherwise cover a whole face at distance 0).
  void binCube(const Scene& scene, glm::vec3 origin, int size, int threads, float near = 0.0f);
  /// A perspective map around an origin in any orientation: texel (i, j) is the ray along axis + x s + y t, x = 2 (i +
  /// 0.5) / size - 1 (y from j likewise), as a 90 degree GL projection looking down `axis` with `s` right and `t` up
  /// draws it. Rows below firstRow are not drawn (a hemicube's side face keeps its upper half).
  struct Perspective {
    glm::vec3 s, t, axis;
    int firstRow = 0;
  };
  /// Sorts the scene's triangles into the rows of each of `views`, size^2 texels each, around `origin`; `near` as for
  /// binCube.
  void binPerspective(const Scene& scene, glm::vec3 origin, const std::vector<Perspective>& views, int size,
                      int threads, float near = 0.0f);
  /// Sorts them into the rows of one orthographic map of size^2 texels: texel (i, j) is the ray along `direction`
  /// through centre + radius (x s + y t), x = 2 (i + 0.5) / size - 1 (y from j likewise), (s, t, direction) the Frame
  /// of renderer/core/sampling.h; distances are measured from the plane `radius` behind the centre (the sphere of
  /// `radius` around the centre is to hold the scene: nothing is clipped).
  void binPlane(const Scene& scene, glm::vec3 direction, glm::vec3 centre, float radius, int size, int threads);
  /// Draws map `view` of the last binning (a face, or 0 for the plane) into out[j size + i] (row 0 first, GL's texture
  /// row 0): the distance d to the nearest triangle along the texel's ray plus min(|dd/di| + |dd/dj|, maxSlopeBias d)
  /// for a cube face (maxSlopeBias for the plane), the change of the triangle's distance to the neighbouring texels
  /// (GL's fwidth), bounded where the triangle grazes the ray; kNoOccluder where no triangle lies.
  /// bandDone(rowBegin, rowEnd), if given, is called on the thread that drew rows [rowBegin, rowEnd) once they are
  /// final, so that what is made of them (quantized copies) is made on every core too.
  void draw(int view, float maxSlopeBias, int threads, float* out,
            const std::function<void(int rowBegin, int rowEnd)>& bandDone = {}) const;
  int views() const { return static_cast<int>(views_.size()); }
  int size() const { return size_; }

 private:
  // A map's rays in its local coordinates (d.s, d.t, d.axis) of an offset d from origin_: a perspective view's through
  // the origin along (x, y, 1); the plane's (s and t divided by its radius) from (x, y, 0) along (0, 0, 1). A GL cube
  // face's s, t and axis are signed unit axes (signedAxes): its local coordinates are sign[c] d[index[c]].
  struct View {
    glm::vec3 s, t, axis;
    glm::ivec3 index{0};
    glm::vec3 sign{0.0f};
    bool signedAxes = false;
    int firstRow = 0;
  };
  glm::vec3 local(const View& v, glm::vec3 d) const {
    if (v.signedAxes) return {v.sign.x * d[v.index.x], v.sign.y * d[v.index.y], v.sign.z * d[v.index.z]};
    return {glm::dot(d, v.s), glm::dot(d, v.t), glm::dot(d, v.axis)};
  }
  // A triangle of one view's band, with the texels its bounding box covers there.
  struct Entry {
    uint32_t triangle;
    uint16_t i0, i1, j0, j1;
  };
  void bin(const Scene& scene, int threads);
  std::vector<Entry>& bucket(int chunk, int view, int band) {
    return buckets_[(static_cast<std::size_t>(chunk) * views_.size() + static_cast<std::size_t>(view)) *
                        static_cast<std::size_t>(bands_) +
                    static_cast<std::size_t>(band)];
  }
  const std::vector<Entry>& bucket(int chunk, int view, int band) const {
    return const_cast<DistanceRasterizer*>(this)->bucket(chunk, view, band);
  }

  const Scene* scene_ = nullptr;
  bool perspective_ = true;
  glm::vec3 origin_{0.0f};
  float radius_ = 1.0f;
  float near_ = 0.0f;  // of a perspective view
  int size_ = 0, chunks_ = 0, bands_ = 0;
  std::vector<View> views_;
  // Per vertex, 4 bits per view: which side of the view's four edges (x, y = -1 or +1) it lies beyond.
  std::vector<uint32_t> outside_;
  // [chunk][view][band]: the triangles of each chunk of the scene's triangles that reach each band of rows.
  std::vector<std::vector<Entry>> buckets_;
};

}  // namespace vplab
