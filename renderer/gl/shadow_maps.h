#pragma once
// One shadow map per point caster (VPL, area-light sample, punctual light), as cube maps (6 layers of a 2D array).
//
// Why cubes and not paraboloids or octahedral maps: a cube face is an ordinary perspective projection, so the
// rasteriser's straight edges are exact. Paraboloid and octahedral maps are non-linear: a triangle's edges must curve
// and only come out right for finely tessellated geometry, while vplab's scenes are mostly a few large quads (the
// Cornell box walls are two triangles each) whose paraboloid images would be badly wrong near the caster, which is
// exactly where VPL shadows matter. Cubes also cover the whole sphere that punctual lights need and sample with
// hardware PCF. The faces are stored as layers 6 c + f of a 2D texture array (not a cube-map array) and the lookup
// picks the face itself: on llvmpipe a 2D-array PCF fetch is several times cheaper than seamless cube filtering, at
// the price of clamping the 2x2 filter at face edges. The cost is six faces per caster, so each face is
// shadowMapSize / 2 texels wide: 6 (S/2)^2 = 1.5 S^2 texels per caster, close to one S x S paraboloid. All casters of
// one chunk render in a single instanced draw (a geometry shader fans each triangle out to the six faces); under a
// time budget they render a caster per draw instead, so that an update can be spread over several calls.
// Depth stores the radial distance / far, so one comparison works on every face.

#include <functional>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/gl/resources.h"
#include "renderer/gl/shader.h"

namespace vplab {

class GlScene;

class CubeShadowMaps {
 public:
  CubeShadowMaps() = default;
  /// Renders one cube per caster position from caster `first` on; faces are faceSize texels wide. far: largest
  /// distance stored. With outOfTime, draws a caster at a time and stops after one once it says so: returns the first
  /// caster not rendered (the next call's `first`, with the same casters), or -1 when every cube is rendered. The maps
  /// do not depend on where it stopped.
  int render(const GlScene& scene, const std::vector<glm::vec3>& casters, int faceSize, float far, int first = 0,
             const std::function<bool()>& outOfTime = {});
  /// Renders again only the cubes of the casters `moved` names (indices into `casters`, which holds as many casters as
  /// the last render, with the same face size and far): the others keep their maps. A caster per draw; with outOfTime
  /// it stops after one once it says so and returns the first entry of `moved` not rendered, else -1.
  int renderMoved(const GlScene& scene, const std::vector<glm::vec3>& casters, const std::vector<int>& moved,
                  int first = 0, const std::function<bool()>& outOfTime = {});

  /// Casters are split into chunks of at most casterCapacity() cubes (GL_MAX_ARRAY_TEXTURE_LAYERS / 6).
  int chunkCount() const { return static_cast<int>(chunks_.size()); }
  int chunkBegin(int chunk) const { return chunk * capacity_; }
  int chunkEnd(int chunk) const { return std::min(count_, (chunk + 1) * capacity_); }
  const GlTexture& chunkTexture(int chunk) const { return chunks_[static_cast<std::size_t>(chunk)]; }
  int casterCount() const { return count_; }
  float far() const { return far_; }

 private:
  /// Uploads the casters' positions and sets the program's uniforms and the GL state every draw of a cube needs.
  void beginDraws(const GlScene& scene, const std::vector<glm::vec3>& casters, float far);

  std::vector<GlTexture> chunks_;
  GlBuffer casterBuffer_;
  GlFramebuffer framebuffer_;
  GlVertexArray vao_;
  ShaderProgram program_;
  int capacity_ = 1;
  int count_ = 0;
  int faceSize_ = 0;
  float far_ = 1.0f;
};

}  // namespace vplab
