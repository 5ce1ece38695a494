#pragma once
// The seam between the VPL gather and the technique that answers V(x1, x2) for each VPL (docs/methods.md "VPL
// visibility"). A technique is one class here and one GLSL file, shaders/common/visibility_<name>.glsl, which defines
//   float vplVisibility(int caster, vec3 casterPos, vec3 casterNormal, vec3 x, float distance, vec3 geoNormal)
// over the sampler bound to TextureUnit::VplVisibility; the gather is compiled once per technique with the define
// the class names. Adding a technique: a class deriving from VplVisibility, its shader, and an entry in
// makeVplVisibility() and in the VisibilityMethod enum (renderer/settings.h).
//
//   cube  one cube shadow map per VPL, a hemicube for a surface VPL (shadow_maps.h): exact up to the map resolution;
//         costs VPLs x triangles.
//   ism   imperfect shadow maps (ism.h): a paraboloid tile per VPL from a fixed point set; costs the point budget plus
//         VPLs x tile texels, independent of the triangle count, at the price of light leaks and over-darkening.

#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "renderer/gl/gl_limits.h"
#include "renderer/gl/ism.h"
#include "renderer/gl/resources.h"
#include "renderer/gl/shader.h"
#include "renderer/gl/shadow_maps.h"
#include "renderer/settings.h"

namespace vplab {

class GlScene;

class VplVisibility {
 public:
  virtual ~VplVisibility() = default;
  /// The define the gather is compiled with to include this technique's shader.
  virtual std::string shaderDefine() const = 0;
  /// Whether the maps built for `casters` under `settings` must be rebuilt for these (also true before the first
  /// update and after a new scene).
  virtual bool stale(const std::vector<VplCaster>& casters, const Settings& settings) const = 0;
  /// Rebuilds the maps; far: the largest distance stored (the same value the lookup divides by). A technique may
  /// build them a slice at a time: given outOfTime (empty: no budget), it stops after a slice once outOfTime() says
  /// so and returns false, and the next
  /// call with the same casters and settings goes on where it stopped (other casters start over). Returns true when
  /// every map is built; the maps are the same however the work was sliced.
  virtual bool update(const GlScene& glScene, const Scene& scene, const std::vector<VplCaster>& casters,
                      const Settings& settings, float far, const std::function<bool()>& outOfTime) = 0;
  /// The scene's geometry changed: everything derived from it is dropped.
  virtual void resetScene() = 0;

  /// Casters are drawn in chunks, each bound as one texture (a chunk is what one texture can hold).
  virtual int chunkCount() const = 0;
  virtual int chunkBegin(int chunk) const = 0;
  virtual int chunkEnd(int chunk) const = 0;
  /// Binds a chunk's texture to TextureUnit::VplVisibility and sets the technique's uniforms on `program`.
  virtual void bindChunk(int chunk, ShaderProgram& program) const = 0;
};

/// The texels per side of a VPL's cube or hemicube faces under Settings::shadowMapSize S: S / 2 rounded down to an
/// even number, at least 8 (shadow_maps.h), so that a hemicube's two half faces fill the halves of their layer.
inline int vplCubeFaceSize(int shadowMapSize) { return std::max(8, shadowMapSize / 4 * 2); }

/// The technique a VisibilityMethod names.
std::unique_ptr<VplVisibility> makeVplVisibility(VisibilityMethod method);

/// The maps a technique would allocate for `casters` VPLs under `settings`.
struct VisibilityFootprint {
  double bytes = 0;
  /// What the bytes are for ("256 VPLs with ISM tiles of 64^2"), for a message about the total.
  std::string what;
  /// One sentence naming a GL limit the maps exceed and what to change; empty when none is.
  std::string problem;
};
VisibilityFootprint visibilityFootprint(VisibilityMethod method, int casters, const Settings& settings,
                                        const GlLimits& limits);

class CubeVisibility final : public VplVisibility {
 public:
  std::string shaderDefine() const override { return "VISIBILITY_CUBE 1"; }
  bool stale(const std::vector<VplCaster>& casters, const Settings& settings) const override;
  bool update(const GlScene& glScene, const Scene& scene, const std::vector<VplCaster>& casters,
              const Settings& settings, float far, const std::function<bool()>& outOfTime) override;
  void resetScene() override {
    valid_ = false;
    nextCaster_ = nextMoved_ = -1;
  }
  int chunkCount() const override { return maps_.chunkCount(); }
  int chunkBegin(int chunk) const override { return maps_.chunkBegin(chunk); }
  int chunkEnd(int chunk) const override { return maps_.chunkEnd(chunk); }
  void bindChunk(int chunk, ShaderProgram& program) const override;

 private:
  CubeShadowMaps maps_;
  std::vector<VplCaster> casters_;
  int mapSize_ = 0;
  bool valid_ = false;
  // The update under way (its casters, map size and far distance) and the first caster not yet rendered; or, for an
  // update of the casters that moved only, those casters and the first of them not yet rendered.
  std::vector<VplCaster> updateCasters_;
  int updateMapSize_ = 0;
  float updateFar_ = 0.0f;
  int nextCaster_ = -1;
  std::vector<int> moved_;
  int nextMoved_ = -1;
};

class IsmVisibility final : public VplVisibility {
 public:
  std::string shaderDefine() const override { return "VISIBILITY_ISM 1"; }
  bool stale(const std::vector<VplCaster>& casters, const Settings& settings) const override;
  bool update(const GlScene& glScene, const Scene& scene, const std::vector<VplCaster>& casters,
              const Settings& settings, float far, const std::function<bool()>& outOfTime) override;
  void resetScene() override;
  int chunkCount() const override { return count_ > 0 ? 1 : 0; }
  int chunkBegin(int) const override { return 0; }
  int chunkEnd(int) const override { return count_; }
  void bindChunk(int chunk, ShaderProgram& program) const override;

 private:
  const Scene* scene_ = nullptr;
  IsmPoints points_;
  IsmLayout layout_;
  GlTexture atlas_;
  std::vector<VplCaster> casters_;
  int pointBudget_ = 0, tileSize_ = 0, count_ = 0;
  bool valid_ = false;
  // The update under way: its casters, tile size and far distance, the tiles splatted so far on the CPU and the first
  // caster not yet splatted.
  std::vector<VplCaster> updateCasters_;
  int updateTileSize_ = 0;
  float updateFar_ = 0.0f;
  std::vector<uint16_t> updateTiles_;
  int nextCaster_ = -1;
};

}  // namespace vplab
