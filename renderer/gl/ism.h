#pragma once
// Imperfect shadow maps (Ritschel et al. 2008; docs/methods.md "VPL visibility"): the CPU half. A fixed set of surface
// points stands in for the triangles; every VPL splats its own subset of them into a small paraboloid depth tile, and
// a pull-push pass fills the holes between splats. The cost is the point budget plus N x tile texels, whatever the
// triangle count. Nothing here needs GL: the tiles are uploaded by IsmVisibility (vpl_visibility.h) and tested
// against exact visibility on the CPU.
//
// Why the splatting runs on the CPU: measured on llvmpipe (docs/benchmarks.md "Imperfect shadow maps"), C++ splats
// several times faster than GL_POINTS or a compute shader with imageAtomicMin, is deterministic (each tile is written
// by one thread, no atomics) and gives the same tiles on every GL driver; on a GPU the upload of N 64^2 16-bit tiles
// costs less than a millisecond.

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/core/sampling.h"
#include "renderer/scene/scene.h"

namespace vplab {

/// Surface points sampled with probability proportional to area, stratified along the triangles' area CDF: the point
/// of stratum j lies at the position (j + xi_j) / count of the total area, so every triangle gets its share up to one
/// point, and inside its triangle at the same fraction of the triangle's own area, mapped to 2D by the triangle's
/// recursive subdivision into four (a stratified 1D position stays stratified in 2D).
/// The points are stored in van der Corput order of their strata (point k holds stratum bitreverse(k), skipping
/// strata past the count), so that every contiguous run of them is itself stratified along the CDF: each caster takes
/// one run (casterRange), and a change of the caster count changes nothing but where the runs begin. The same scene
/// and count give the same points.
struct IsmPoints {
  std::vector<glm::vec3> positions;
  /// Geometric normal of each point's triangle (its splat is sized by the projected area).
  std::vector<glm::vec3> normals;
  std::vector<uint32_t> triangles;
  /// Total surface area of the scene, m^2.
  double totalArea = 0.0;
  std::size_t size() const { return positions.size(); }
  /// The run [first, second) of points of caster i of n.
  std::pair<std::size_t, std::size_t> casterRange(int i, int n) const {
    const auto at = [&](int c) { return static_cast<std::size_t>(static_cast<uint64_t>(size()) * c / n); };
    return {at(i), at(i + 1)};
  }
};

IsmPoints sampleIsmPoints(const Scene& scene, int count);

/// Paraboloid parameterisation of the hemisphere around a VPL's normal n: a unit direction w with n.w >= 0 maps to
/// uv = (s.w, t.w) / (1 + n.w) in the unit disc, (s, t, n) the orthonormal Frame of renderer/core/sampling.h (the
/// shader builds the same frame). A texel of a tile of T x T texels covers the solid angle 4 / (1 + |uv|^2)^2 (2/T)^2.

/// Layout and parameters of one set of tiles: tile i covers texels [tx, tx + tileSize) x [ty, ty + tileSize) of layer
/// i / tilesPerLayer, with (tx, ty) = tileSize x (c % tilesPerRow, c / tilesPerRow), c = i % tilesPerLayer.
struct IsmLayout {
  int tileSize = 64;
  int tilesPerRow = 1;
  int tilesPerLayer = 1;
  int layers = 1;
  int atlasSize() const { return tileSize * tilesPerRow; }
  /// Index of tile `tile`'s texel (0, 0) in the layers x atlasSize^2 texels of splatIsmTiles' result.
  std::size_t tileOrigin(int tile) const {
    const int inLayer = tile % tilesPerLayer, layer = tile / tilesPerLayer;
    const std::size_t side = static_cast<std::size_t>(atlasSize());
    return static_cast<std::size_t>(layer) * side * side +
           static_cast<std::size_t>((inLayer / tilesPerRow) * tileSize) * side +
           static_cast<std::size_t>((inLayer % tilesPerRow) * tileSize);
  }
};

/// Chooses the smallest square atlas (a power-of-two number of tiles per row, at most maxTextureSize texels wide)
/// that holds `tiles` tiles, in as many layers as needed.
IsmLayout ismLayout(int tiles, int tileSize, int maxTextureSize);

/// A VPL as the visibility techniques see it (vpl_visibility.h): where its maps are drawn from and which way they face.
struct VplCaster {
  glm::vec3 position;
  /// A surface VPL's geometric normal: it lights only the half-space this points into. A medium VPL's direction of
  /// travel of its light, which a paraboloid tile faces.
  glm::vec3 normal;
  /// A medium VPL lights every direction.
  bool inMedium = false;
  bool operator==(const VplCaster&) const = default;
};

/// Splats each caster's run of points (IsmPoints::casterRange over the casters) into its 16-bit depth tile (depth =
/// distance / far, 65535 = nothing there), each point as a disc of the solid angle its share of the surface area
/// subtends, then fills holes by pull-push over at most `fillLevels` levels of the tile's pyramid (holes up to about
/// 2^fillLevels texels wide: larger empty regions are directions where no surface lies and stay empty). Returns layers
/// x atlasSize^2 texels, row 0 first (GL's texture row 0), tile by tile in parallel on `threads`.
std::vector<uint16_t> splatIsmTiles(const IsmPoints& points, const std::vector<VplCaster>& casters,
                                    const IsmLayout& layout, float far, int fillLevels, int threads);
/// The same for casters [firstCaster, endCaster) only, into their tiles of `atlas` (layers x atlasSize^2 texels): an
/// update can be spread over several calls, and gives the same tiles.
void splatIsmTileRange(const IsmPoints& points, const std::vector<VplCaster>& casters, const IsmLayout& layout,
                       float far, int fillLevels, int threads, int firstCaster, int endCaster,
                       std::vector<uint16_t>& atlas);

/// Visibility of x (geometric normal geoNormal) from caster i through its tile: the lookup of
/// shaders/common/visibility_ism.glsl without its 2x2 filter, the same normal offset and texel-footprint bias on top of
/// `bias`. For tests against exact visibility.
float ismVisibility(const std::vector<uint16_t>& tiles, const IsmLayout& layout, int caster, const VplCaster& c,
                    glm::vec3 x, glm::vec3 geoNormal, float far, float bias);

}  // namespace vplab
