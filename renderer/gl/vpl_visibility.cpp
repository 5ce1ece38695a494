#include "renderer/gl/vpl_visibility.h"

#include <glad/gl.h>

#include <sstream>

#include "renderer/core/parallel.h"
#include "renderer/gl/gl_scene.h"
#include "renderer/gl/texture_units.h"

namespace vplab {

namespace {

int glInteger(GLenum name) {
  GLint value = 0;
  glGetIntegerv(name, &value);
  return value;
}

// Pull-push fills holes up to an eighth of the tile wide (8 texels of a 64^2 tile): the gaps between splats of one
// surface; a wider empty region is a direction in which no surface lies, and filling it would invent an occluder.
int ismFillLevels(int tileSize) {
  int levels = 0;
  while ((8 << levels) < tileSize) ++levels;
  return std::max(1, levels);
}

}  // namespace

std::unique_ptr<VplVisibility> makeVplVisibility(VisibilityMethod method) {
  switch (method) {
    case VisibilityMethod::Ism: return std::make_unique<IsmVisibility>();
    case VisibilityMethod::Cube:
    case VisibilityMethod::Auto: break;  // resolved by the caller (resolveVisibility)
  }
  return std::make_unique<CubeVisibility>();
}

VisibilityFootprint visibilityFootprint(VisibilityMethod method, int casters, const Settings& settings,
                                        const GlLimits& limits) {
  VisibilityFootprint fit;
  std::ostringstream why;
  if (method == VisibilityMethod::Ism) {
    if (settings.ismTileSize > limits.maxTextureSize) {
      why << "ismTileSize " << settings.ismTileSize << " exceeds this GL context's texture size "
          << limits.maxTextureSize << ": lower --ism-tile-size";
      fit.problem = why.str();
      return fit;
    }
    IsmLayout layout = ismLayout(casters, settings.ismTileSize, limits.maxTextureSize);
    fit.bytes = 2.0 * layout.atlasSize() * layout.atlasSize() * layout.layers;
    fit.what = std::to_string(casters) + " VPLs with ISM tiles of " + std::to_string(settings.ismTileSize) + "^2";
    if (layout.layers > limits.maxArrayLayers) {
      why << fit.what << " need " << layout.layers << " atlas layers, over the " << limits.maxArrayLayers
          << " this GL context allows: lower --vpl-count or --ism-tile-size";
      fit.problem = why.str();
    }
    return fit;
  }
  const int face = vplCubeFaceSize(settings.shadowMapSize);
  if (face > limits.maxTextureSize) {
    why << "shadowMapSize " << settings.shadowMapSize << " exceeds this GL context's texture size "
        << limits.maxTextureSize << ": lower --shadow-map-size";
    fit.problem = why.str();
    return fit;
  }
  // Whole cubes: an upper bound, as surface VPLs have hemicubes of half the size (shadow_maps.h).
  fit.bytes = 2.0 * 6.0 * face * face * static_cast<double>(casters);
  fit.what =
      std::to_string(casters) + " VPLs with cube shadow maps of " + std::to_string(settings.shadowMapSize) + " texels";
  return fit;
}

// --- cube shadow maps -------------------------------------------------------------------------------------------

namespace {
// A cube map depends on its caster's position, a hemicube also on its normal: flux or material edits keep them.
bool sameMap(const VplCaster& a, const VplCaster& b) {
  return a.inMedium == b.inMedium && a.position == b.position && (a.inMedium || a.normal == b.normal);
}
}  // namespace

bool CubeVisibility::stale(const std::vector<VplCaster>& casters, const Settings& settings) const {
  if (!valid_ || settings.shadowMapSize != mapSize_ || casters.size() != casters_.size()) return true;
  for (std::size_t i = 0; i < casters.size(); ++i)
    if (!sameMap(casters[i], casters_[i])) return true;
  return false;
}

bool CubeVisibility::update(const GlScene&, const Scene& scene, const std::vector<VplCaster>& casters,
                            const Settings& settings, float far, const std::function<bool()>& outOfTime) {
  const int threads = resolveThreadCount(settings.threads);
  const bool same = updateCasters_ == casters && updateMapSize_ == settings.shadowMapSize && updateFar_ == far;
  if (!(same && (nextCaster_ >= 0 || nextMoved_ >= 0))) {
    // A set as large as the last whose casters mostly stayed (the preview's representatives after a camera move,
    // representative_lights.h): only the maps of the casters that moved are drawn again, unless one changed between a
    // cube and a hemicube (which moves the others' layers).
    moved_.clear();
    bool comparable =
        valid_ && mapSize_ == settings.shadowMapSize && maps_.far() == far && casters.size() == casters_.size();
    for (std::size_t i = 0; comparable && i < casters.size(); ++i) {
      comparable = casters[i].inMedium == casters_[i].inMedium;
      if (!sameMap(casters[i], casters_[i])) moved_.push_back(static_cast<int>(i));
    }
    const bool partial = comparable && 2 * moved_.size() <= casters.size();
    updateCasters_ = casters;
    updateMapSize_ = settings.shadowMapSize;
    updateFar_ = far;
    nextCaster_ = partial ? -1 : 0;
    nextMoved_ = partial ? 0 : -1;
    valid_ = false;
  }
  if (nextMoved_ >= 0) {
    nextMoved_ = maps_.renderMoved(scene, updateCasters_, moved_, threads, nextMoved_, outOfTime);
    if (nextMoved_ >= 0) return false;
  } else {
    nextCaster_ =
        maps_.render(scene, updateCasters_, vplCubeFaceSize(updateMapSize_), far, threads, nextCaster_, outOfTime);
    if (nextCaster_ >= 0) return false;
  }
  casters_ = updateCasters_;
  mapSize_ = updateMapSize_;
  valid_ = true;
  return true;
}

void CubeVisibility::bindChunk(int chunk, ShaderProgram& program) const {
  maps_.chunkTexture(chunk).bind(unit(TextureUnit::Visibility));
  program.set("uWholeCubes", maps_.chunkWholeCubes(chunk));
}

// --- imperfect shadow maps --------------------------------------------------------------------------------------

void IsmVisibility::resetScene() {
  valid_ = false;
  nextCaster_ = -1;
  scene_ = nullptr;
  points_ = {};
}

bool IsmVisibility::stale(const std::vector<VplCaster>& casters, const Settings& settings) const {
  if (!valid_ || settings.ismTileSize != tileSize_ || settings.ismPointBudget != pointBudget_ ||
      casters.size() != casters_.size())
    return true;
  // A tile depends on its caster's position and orientation.
  for (std::size_t i = 0; i < casters.size(); ++i)
    if (casters[i].position != casters_[i].position || casters[i].normal != casters_[i].normal) return true;
  return false;
}

bool IsmVisibility::update(const GlScene&, const Scene& scene, const std::vector<VplCaster>& casters,
                           const Settings& settings, float far, const std::function<bool()>& outOfTime) {
  const int n = static_cast<int>(casters.size());
  const bool resume = nextCaster_ >= 0 && updateCasters_ == casters && updateTileSize_ == settings.ismTileSize &&
                      updateFar_ == far && pointBudget_ == settings.ismPointBudget && scene_ == &scene;
  if (!resume) {
    // The point set depends on the geometry and the budget only: the same points every frame, for any VPL count.
    if (scene_ != &scene || pointBudget_ != settings.ismPointBudget || points_.size() == 0) {
      points_ = sampleIsmPoints(scene, settings.ismPointBudget);
      scene_ = &scene;
      pointBudget_ = settings.ismPointBudget;
    }
    layout_ = ismLayout(n, settings.ismTileSize, glInteger(GL_MAX_TEXTURE_SIZE));
    updateTiles_.assign(static_cast<std::size_t>(layout_.atlasSize()) * layout_.atlasSize() * layout_.layers, 65535);
    updateCasters_ = casters;
    updateTileSize_ = settings.ismTileSize;
    updateFar_ = far;
    nextCaster_ = 0;
  }
  // Slices of a few tiles per thread: small enough to stop within a frame's budget, large enough to keep the
  // threads busy.
  const int slice = 8 * std::max(1, resolveThreadCount(settings.threads));
  do {
    const int end = std::min(n, nextCaster_ + slice);
    splatIsmTileRange(points_, casters, layout_, far, ismFillLevels(settings.ismTileSize), settings.threads,
                      nextCaster_, end, updateTiles_);
    nextCaster_ = end;
  } while (nextCaster_ < n && !(outOfTime && outOfTime()));
  if (nextCaster_ < n) return false;

  if (!atlas_ || atlas_.width() != layout_.atlasSize() || atlas_.layers() != layout_.layers) {
    atlas_ = GlTexture(layout_.atlasSize(), layout_.atlasSize(), TextureFormat::Depth16, 1, layout_.layers, true);
    atlas_.setDepthCompare(true);
  }
  atlas_.uploadDepth16(updateTiles_);

  casters_ = casters;
  tileSize_ = settings.ismTileSize;
  count_ = n;
  valid_ = true;
  nextCaster_ = -1;
  return true;
}

void IsmVisibility::bindChunk(int, ShaderProgram& program) const {
  atlas_.bind(unit(TextureUnit::Visibility));
  program.set("uIsmTileSize", layout_.tileSize);
  program.set("uIsmTilesPerRow", layout_.tilesPerRow);
  program.set("uIsmTilesPerLayer", layout_.tilesPerLayer);
}

}  // namespace vplab
