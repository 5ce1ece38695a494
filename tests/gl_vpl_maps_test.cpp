// The VPLs' cube and hemicube maps (renderer/gl/shadow_maps.h), read back from their texture and checked texel by texel
// against rays cast the way shaders/common/shadow.glsl reads them: each layer's texel (i, j) maps to the direction the
// lookup sends there, and holds the nearest triangle's distance / far as a 16-bit depth (1 where nothing lies). Then:
// the maps do not depend on the thread count, on a budget that stops after each batch, nor on drawing only the
// casters that moved.

#include <cmath>
#include <string>

#include "renderer/gl/gl_limits.h"
#include "renderer/gl/shadow_maps.h"
#include "renderer/vpl/vpl_generation.h"
#include "tests/gl_test_util.h"
#include "tests/nearest_hit.h"
#include "tests/test_scenes.h"

namespace vplab {
namespace {

using GlVplMaps = test::GlBackendTest;

using test::Nearest;
using test::nearestHit;

// The frame shaders/common/math.glsl orthonormalFrame builds around n (its sign copysign(1, n.z), as Frame's).
void glslFrame(glm::dvec3 n, glm::dvec3& s, glm::dvec3& t) {
  const double sgn = std::copysign(1.0, n.z), a = -1.0 / (sgn + n.z), b = n.x * n.y * a;
  s = glm::dvec3(1.0 + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
  t = glm::dvec3(b, sgn + n.y * n.y * a, -n.y);
}

// The direction whose lookup lands on texel (i, j) of a caster's layer (shaders/common/shadow.glsl): a whole cube's
// face `layer` in GL's cube-map orientation; a hemicube's front face along n (x = s, y = t), and its side layers, whose
// upper half is the upper half of the face along +s (+t) and whose lower half is that of the face along -s (-t), x
// across and the normal up.
glm::dvec3 lookupDirection(bool whole, glm::dvec3 n, int layer, int i, int j, int size) {
  const double x = 2.0 * (i + 0.5) / size - 1.0;
  if (whole) {
    const double y = 2.0 * (j + 0.5) / size - 1.0;
    const glm::dvec3 d[6] = {{1, -y, -x}, {-1, -y, x}, {x, 1, y}, {x, -1, -y}, {x, -y, 1}, {-x, -y, -1}};
    return glm::normalize(d[layer]);
  }
  glm::dvec3 s, t;
  glslFrame(n, s, t);
  if (layer == 0) return glm::normalize(n + x * s + (2.0 * (j + 0.5) / size - 1.0) * t);
  const bool upper = j >= size / 2;
  const int row = upper ? j : j + size / 2;  // the face's own row
  const double y = 2.0 * (row + 0.5) / size - 1.0;
  const glm::dvec3 along = (layer == 1 ? s : t) * (upper ? 1.0 : -1.0), across = layer == 1 ? t : s;
  return glm::normalize(along + x * across + y * n);
}

std::vector<uint16_t> readLayers(const GlTexture& texture) {
  return texture.readDepth16();
}

// Casters in the Cornell box: a medium VPL (a whole cube) first, then surface VPLs a little off the floor, a wall, the
// ceiling beside the light and a box with a tilted normal, then VPLs as the generator places them, on their surfaces.
std::vector<VplCaster> cornellCasters(const OfflineScene& offline) {
  const Scene& scene = offline.scene();
  const glm::vec3 lo = scene.bounds.lower, hi = scene.bounds.upper, size = hi - lo, c = 0.5f * (lo + hi);
  std::vector<VplCaster> casters = {
      {c + glm::vec3(0.05f, 0.1f, -0.03f) * size, glm::vec3(0, 1, 0), true},
      {glm::vec3(c.x + 0.1f * size.x, lo.y + 1e-4f * size.y, c.z), glm::vec3(0, 1, 0), false},
      {glm::vec3(lo.x + 1e-4f * size.x, c.y, c.z - 0.2f * size.z), glm::vec3(1, 0, 0), false},
      {glm::vec3(c.x + 0.3f * size.x, hi.y - 1e-4f * size.y, c.z), glm::vec3(0, -1, 0), false},
      {c + glm::vec3(-0.2f, -0.3f, 0.1f) * size, glm::normalize(glm::vec3(0.3f, 0.8f, -0.5f)), false}};
  const VplSet vpls = generateVpls(offline, test::smallVplSettings(16, 64));
  for (std::size_t i = 0; i < vpls.vpls.size() && i < 40; ++i)
    casters.push_back({vpls.vpls[i].position, vpls.vpls[i].geometricNormal, false});
  return casters;
}

// Checks every texel of every chunk of `maps` (drawn for `casters` with faces of size^2 and `far`) against the nearest
// hit along the direction the lookup reads there; returns how many texels were compared (those on no triangle edge).
int expectNearestHits(const Scene& scene, const std::vector<VplCaster>& casters, const CubeShadowMaps& maps, int size,
                      float far) {
  int compared = 0, failures = 0;
  for (int chunk = 0; chunk < maps.chunkCount(); ++chunk) {
    const std::vector<uint16_t> texels = maps.chunkTexture(chunk).readDepth16();
    int layer = 0;
    for (int c = maps.chunkBegin(chunk); c < maps.chunkEnd(chunk); ++c) {
      const VplCaster& caster = casters[static_cast<std::size_t>(c)];
      for (int l = 0; l < (caster.inMedium ? 6 : 3); ++l, ++layer)
        for (int j = 0; j < size; ++j)
          for (int i = 0; i < size; ++i) {
            const glm::dvec3 dir = lookupDirection(caster.inMedium, glm::dvec3(caster.normal), l, i, j, size);
            // The caster's own surface, which a generated VPL lies on up to rounding, is not an occluder.
            const Nearest n = nearestHit(scene, glm::dvec3(caster.position), dir, 1e-4 * far);
            if (n.ambiguous) continue;
            ++compared;
            const double expected = std::isfinite(n.t) ? std::min(n.t / far, 1.0) : 1.0;
            const double stored =
                texels[(static_cast<std::size_t>(layer) * size + static_cast<std::size_t>(j)) * size + i] / 65535.0;
            if (std::abs(stored - expected) > 1.0 / 65535.0 + 1e-5 * expected && ++failures <= 8)
              ADD_FAILURE() << "caster " << c << " layer " << l << " texel " << i << "," << j << ": expected "
                            << expected * far << ", stored " << stored * far;
          }
    }
  }
  EXPECT_EQ(failures, 0);
  return compared;
}

TEST_P(GlVplMaps, EveryTexelHoldsTheNearestTriangleWhereTheLookupReadsIt) {
  auto offline = test::loadAssetScene("cornell-box");
  const Scene& scene = offline->scene();
  const std::vector<VplCaster> casters = cornellCasters(*offline);
  ASSERT_GT(casters.size(), 30u);
  const int size = 32;
  const float far = 2.0f * scene.bounds.diagonal();
  CubeShadowMaps maps;
  EXPECT_EQ(maps.render(scene, casters, size, far, 2), -1);
  ASSERT_EQ(maps.chunkCount(), 1);
  EXPECT_EQ(maps.chunkWholeCubes(0), 1);
  const int compared = expectNearestHits(scene, casters, maps, size, far);
  // Few texels lie on an edge.
  EXPECT_GT(compared, (6 + 3 * (static_cast<int>(casters.size()) - 1)) * size * size * 95 / 100);
}

// More casters than one texture array holds layers for (GL_MAX_ARRAY_TEXTURE_LAYERS, 2048 on llvmpipe): each chunk
// holds its own casters' maps.
TEST_P(GlVplMaps, CastersBeyondOneArraySpillIntoFurtherChunks) {
  auto offline = test::loadAssetScene("cornell-box");
  const Scene& scene = offline->scene();
  const std::vector<VplCaster> some = cornellCasters(*offline);
  std::vector<VplCaster> casters(some.begin(), some.begin() + 1);  // the whole cube first
  const int maxLayers = queryGlLimits().maxArrayLayers;
  ASSERT_GT(maxLayers, 0);
  int layers = 6;
  while (layers <= maxLayers + 6) {
    VplCaster c = some[1 + casters.size() % (some.size() - 1)];
    c.position += 1e-3f * static_cast<float>(casters.size() % 7) * c.normal;
    casters.push_back(c);
    layers += 3;
  }
  const int size = 8;
  const float far = 2.0f * scene.bounds.diagonal();
  CubeShadowMaps maps;
  EXPECT_EQ(maps.render(scene, casters, size, far, 2), -1);
  EXPECT_GE(maps.chunkCount(), 2);
  EXPECT_EQ(maps.chunkEnd(maps.chunkCount() - 1), static_cast<int>(casters.size()));
  expectNearestHits(scene, casters, maps, size, far);
}

TEST_P(GlVplMaps, TheSameMapsAtAnyThreadCountUnderABudgetAndForTheCastersThatMoved) {
  auto offline = test::loadAssetScene("cornell-box");
  const Scene& scene = offline->scene();
  const std::vector<VplCaster> casters = cornellCasters(*offline);
  const int size = 16;
  const float far = 2.0f * scene.bounds.diagonal();
  CubeShadowMaps one;
  ASSERT_EQ(one.render(scene, casters, size, far, 1), -1);
  const std::vector<uint16_t> expected = readLayers(one.chunkTexture(0));

  CubeShadowMaps many;
  ASSERT_EQ(many.render(scene, casters, size, far, 3), -1);
  EXPECT_EQ(readLayers(many.chunkTexture(0)), expected);

  // A budget that is always spent: a batch per call, resumed where it stopped.
  CubeShadowMaps sliced;
  int calls = 0;
  for (int next = 0; next >= 0; ++calls) next = sliced.render(scene, casters, size, far, 2, next, [] { return true; });
  EXPECT_GT(calls, 1);
  EXPECT_EQ(readLayers(sliced.chunkTexture(0)), expected);

  // Two casters move and are drawn again alone: the maps are those of a full render of the moved set.
  std::vector<VplCaster> moved = casters;
  moved[2].position.y += 0.05f;
  moved[7].normal = glm::normalize(moved[7].normal + glm::vec3(0.2f, 0.0f, 0.0f));
  ASSERT_EQ(sliced.renderMoved(scene, moved, {2, 7}, 2), -1);
  CubeShadowMaps full;
  ASSERT_EQ(full.render(scene, moved, size, far, 2), -1);
  EXPECT_EQ(readLayers(sliced.chunkTexture(0)), readLayers(full.chunkTexture(0)));
}

}  // namespace

VPLAB_GL_BACKENDS(GlVplMaps);

}  // namespace vplab
