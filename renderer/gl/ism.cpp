#include "renderer/gl/ism.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "renderer/core/parallel.h"

namespace vplab {

namespace {

// The barycentric coordinates (of the first two corners) of the point at fraction u of a triangle's area: u's base-4
// digits pick one of the four half-size sub-triangles (three corners and the inverted middle one) at each level, so
// points at evenly spread fractions fall into distinct sub-triangles of every level that has fewer of them.
glm::vec2 trianglePointAtAreaFraction(double u) {
  // The current sub-triangle's corners, in barycentric coordinates (b0, b1).
  glm::dvec2 a(1.0, 0.0), b(0.0, 1.0), c(0.0, 0.0);
  for (int level = 0; level < 16; ++level) {
    u *= 4.0;
    const int digit = std::min(3, static_cast<int>(u));
    u -= digit;
    const glm::dvec2 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
    if (digit == 0) {
      b = ab, c = ca;
    } else if (digit == 1) {
      a = ab, c = bc;
    } else if (digit == 2) {
      a = ca, b = bc;
    } else {
      a = bc, b = ca, c = ab;
    }
  }
  return glm::vec2((a + b + c) / 3.0);
}

uint64_t reverseBits(uint64_t k, int bits) {
  uint64_t r = 0;
  for (int i = 0; i < bits; ++i, k >>= 1) r = (r << 1) | (k & 1u);
  return r;
}

}  // namespace

IsmPoints sampleIsmPoints(const Scene& scene, int count) {
  IsmPoints points;
  const std::size_t triangles = scene.triangles.size();
  if (count <= 0 || triangles == 0) return points;
  // Area CDF in double: a million small triangles would lose their strata in float.
  std::vector<double> cdf(triangles);
  double total = 0.0;
  for (std::size_t t = 0; t < triangles; ++t) {
    total += static_cast<double>(scene.triangleArea(static_cast<uint32_t>(t)));
    cdf[t] = total;
  }
  points.totalArea = total;
  if (!(total > 0.0)) return points;
  // Stratum j's point lies at (j + xi_j) / count of the total area, jittered; the strata are in increasing order, so
  // one sweep over the CDF finds every point's triangle and its fraction of that triangle's area.
  const std::size_t n = static_cast<std::size_t>(count);
  std::vector<glm::vec3> positions(n), normals(n);
  std::vector<uint32_t> stratumTriangles(n);
  std::size_t t = 0;
  for (std::size_t j = 0; j < n; ++j) {
    Rng rng(hashKey(0x49534d, static_cast<uint64_t>(j)));
    const double u = (static_cast<double>(j) + static_cast<double>(rng.next1D())) / static_cast<double>(n) * total;
    while (t + 1 < triangles && cdf[t] <= u) ++t;
    const double below = t > 0 ? cdf[t - 1] : 0.0, area = cdf[t] - below;
    const double fraction = area > 0.0 ? std::clamp((u - below) / area, 0.0, 1.0 - 1e-12) : 0.5;
    const glm::vec2 bary = trianglePointAtAreaFraction(fraction);
    const uint32_t tri = static_cast<uint32_t>(t);
    const glm::uvec3& v = scene.triangles[tri];
    positions[j] =
        bary.x * scene.positions[v.x] + bary.y * scene.positions[v.y] + (1.0f - bary.x - bary.y) * scene.positions[v.z];
    normals[j] = scene.geometricNormal(tri);
    stratumTriangles[j] = tri;
  }
  // Van der Corput order of the strata: any run of k consecutive points then has at most about one point in each run
  // of count / k strata (Niederreiter 1992), so each caster's run is spread over the surface like the whole set.
  int bits = 0;
  while ((uint64_t{1} << bits) < n) ++bits;
  points.positions.reserve(n);
  points.normals.reserve(n);
  points.triangles.reserve(n);
  for (uint64_t k = 0; k < (uint64_t{1} << bits); ++k) {
    const uint64_t j = reverseBits(k, bits);
    if (j >= n) continue;
    points.positions.push_back(positions[j]);
    points.normals.push_back(normals[j]);
    points.triangles.push_back(stratumTriangles[j]);
  }
  return points;
}

IsmLayout ismLayout(int tiles, int tileSize, int maxTextureSize) {
  IsmLayout layout;
  layout.tileSize = tileSize;
  const int maxPerRow = std::max(1, maxTextureSize / tileSize);
  int perRow = 1;
  while (perRow < maxPerRow && perRow * perRow < tiles) perRow *= 2;
  layout.tilesPerRow = std::min(perRow, maxPerRow);
  layout.tilesPerLayer = layout.tilesPerRow * layout.tilesPerRow;
  layout.layers = std::max(1, (tiles + layout.tilesPerLayer - 1) / layout.tilesPerLayer);
  return layout;
}

namespace {

constexpr float kEmpty = std::numeric_limits<float>::infinity();

// Splat radius over the radius of the disc whose area is the point's projected share of the surface. Larger discs close
// more gaps between stratified points but widen every shadow (measured: 1.6 darkens the Cornell box's indirect light by
// 4 %, docs/methods.md "VPL visibility"); the gaps left are filled by pull-push.
constexpr float kSplatScale = 1.0f;

// Fills holes of one tile (row-major depths, kEmpty = no splat) by pull-push (Grossman & Dally 1998; Marroquim et al.
// 2007): pull averages the filled texels of each 2x2 block into the next level, push copies a level's value into the
// empty texels below it. Only `levels` levels are built, so a hole wider than about 2^levels texels stays empty.
void pullPush(std::vector<float>& tile, int size, int levels) {
  std::vector<std::vector<float>> pyramid;
  pyramid.push_back(tile);
  for (int l = 0, s = size; l < levels && s > 1; ++l, s /= 2) {
    const std::vector<float>& fine = pyramid.back();
    const int half = s / 2;
    std::vector<float> coarse(static_cast<std::size_t>(half) * half, kEmpty);
    for (int y = 0; y < half; ++y)
      for (int x = 0; x < half; ++x) {
        float sum = 0.0f;
        int filled = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            float d = fine[static_cast<std::size_t>(2 * y + dy) * s + (2 * x + dx)];
            if (d != kEmpty) {
              sum += d;
              ++filled;
            }
          }
        if (filled) coarse[static_cast<std::size_t>(y) * half + x] = sum / static_cast<float>(filled);
      }
    pyramid.push_back(std::move(coarse));
  }
  for (std::size_t l = pyramid.size() - 1; l > 0; --l) {
    std::vector<float>& fine = pyramid[l - 1];
    const std::vector<float>& coarse = pyramid[l];
    const int s = size >> (l - 1), half = s / 2;
    for (int y = 0; y < s; ++y)
      for (int x = 0; x < s; ++x) {
        float& d = fine[static_cast<std::size_t>(y) * s + x];
        if (d == kEmpty)
          d = coarse[static_cast<std::size_t>(std::min(y / 2, half - 1)) * half + std::min(x / 2, half - 1)];
      }
  }
  tile = std::move(pyramid[0]);
}

// One point's disc in a tile: centre (fx, fy) and squared radius in texels; the texel the point falls in is always
// covered. Each covered texel stores the distance along its direction to the point's tangent plane (normal, offset
// from the caster), kept within [r / 2, 2 r] of the point's own distance r, over far.
struct SplatDisc {
  float fx, fy, radius2;
  int pointX, pointY;
  glm::vec3 normal;
  float planeOffset, r, invFar;
};

// Texels [x0, x1] of row y (per-row arrays of the texel directions, the disc mask and the tile's depths): branch-free,
// so that it runs on SIMD lanes (the file is built without floating-point traps).
void splatRow(const SplatDisc& d, int y, int x0, int x1, const float* dirX, const float* dirY, const float* dirZ,
              const float* inDisc, float* depths) {
  const float cy = static_cast<float>(y) + 0.5f - d.fy, cy2 = cy * cy;
  const bool pointRow = y == d.pointY;
  for (int x = x0; x <= x1; ++x) {
    const float cx = static_cast<float>(x) + 0.5f - d.fx;
    const bool covered = ((cx * cx + cy2 <= d.radius2) | (pointRow & (x == d.pointX))) & (inDisc[x] != 0.0f);
    const float along = dirX[x] * d.normal.x + dirY[x] * d.normal.y + dirZ[x] * d.normal.z;
    float dist = std::abs(along) > 1e-6f ? d.planeOffset / along : d.r;
    dist = dist < 0.5f * d.r ? 0.5f * d.r : (2.0f * d.r < dist ? 2.0f * d.r : dist);
    const float depth = dist * d.invFar;
    depths[x] = covered && depth < depths[x] ? depth : depths[x];
  }
}

}  // namespace

std::vector<uint16_t> splatIsmTiles(const IsmPoints& points, const std::vector<VplCaster>& casters,
                                    const IsmLayout& layout, float far, int fillLevels, int threads) {
  std::vector<uint16_t> atlas(static_cast<std::size_t>(layout.atlasSize()) * layout.atlasSize() * layout.layers, 65535);
  splatIsmTileRange(points, casters, layout, far, fillLevels, threads, 0, static_cast<int>(casters.size()), atlas);
  return atlas;
}

void splatIsmTileRange(const IsmPoints& points, const std::vector<VplCaster>& casters, const IsmLayout& layout,
                       float far, int fillLevels, int threads, int firstCaster, int endCaster,
                       std::vector<uint16_t>& atlas) {
  const int side = layout.atlasSize();
  const int tileSize = layout.tileSize;
  const int casterCount = static_cast<int>(casters.size());
  endCaster = std::min(endCaster, casterCount);
  if (firstCaster >= endCaster) return;
  const float invFar = 1.0f / far;
  const float halfSize = 0.5f * static_cast<float>(tileSize);
  // Splats larger than this radius (texels) are cut: they come from points almost touching the caster.
  const float maxRadius = 0.125f * static_cast<float>(tileSize);
  // The unit direction of every texel centre in the caster's frame (the paraboloid's inverse map), shared by all
  // tiles, one array per component (the splat's rows run on SIMD lanes); inDisc = 0 outside the unit disc, where no
  // direction maps.
  const std::size_t texels = static_cast<std::size_t>(tileSize) * tileSize;
  std::vector<float> directionX(texels, 0.0f), directionY(texels, 0.0f), directionZ(texels, 0.0f), inDisc(texels, 0.0f);
  for (int y = 0; y < tileSize; ++y)
    for (int x = 0; x < tileSize; ++x) {
      const float tu = (static_cast<float>(x) + 0.5f) / halfSize - 1.0f,
                  tv = (static_cast<float>(y) + 0.5f) / halfSize - 1.0f;
      const float q = tu * tu + tv * tv;
      if (q > 1.0f) continue;
      const glm::vec3 w = glm::vec3(2.0f * tu, 2.0f * tv, 1.0f - q) / (1.0f + q);
      const std::size_t i = static_cast<std::size_t>(y) * tileSize + x;
      directionX[i] = w.x, directionY[i] = w.y, directionZ[i] = w.z;
      inDisc[i] = 1.0f;
    }
  parallelFor(endCaster - firstCaster, threads, [&](int64_t index, int) {
    const int i = firstCaster + static_cast<int>(index);
    const VplCaster& c = casters[static_cast<std::size_t>(i)];
    const Frame frame(c.normal);
    const auto [begin, end] = points.casterRange(i, casterCount);
    if (end == begin) return;
    // Each point of the caster's run stands for this much surface.
    const float pointArea = static_cast<float>(points.totalArea / static_cast<double>(end - begin));
    // Solid angle -> texels: a texel spans (2 / T)^2 of the uv square, and d omega = 4 / (1 + |uv|^2)^2 d uv.
    const float texelsPerSteradian = static_cast<float>(tileSize) * static_cast<float>(tileSize) / 16.0f;
    std::vector<float> tile(static_cast<std::size_t>(tileSize) * tileSize, kEmpty);
    const float rimSkip = 0.5f * 4.0f / static_cast<float>(tileSize);
    for (std::size_t j = begin; j < end; ++j) {
      const glm::vec3 d = points.positions[j] - c.position;
      const glm::vec3 local = frame.toLocal(d);
      const float r2 = glm::dot(d, d);
      const float r = std::sqrt(r2);
      // Behind the caster it sends no light. Points within half a rim texel of its plane (its own surface, mostly)
      // would share the rim texels with receivers just above that plane, and shadow the corners where the caster's
      // light is strongest; an occluder that flat to the caster cannot be resolved by the tile anyway.
      if (local.z <= rimSkip * r) continue;
      const float s = 1.0f / (r + local.z);  // uv = (x, y) / (r (1 + z / r))
      const float u = local.x * s, v = local.y * s;
      const float rho2 = u * u + v * v;
      const float fx = (u + 1.0f) * halfSize, fy = (v + 1.0f) * halfSize;
      // The disc covers the solid angle of the point's share of the area, foreshortened (two-sided occluders).
      const glm::vec3& np = points.normals[j];
      const float cosP = std::abs(glm::dot(np, d)) / r;
      const float texels = pointArea * cosP / r2 * (1.0f + rho2) * (1.0f + rho2) * texelsPerSteradian;
      const float radius = kSplatScale * std::sqrt(texels / kPi);
      // Each texel of the disc (at least the one the point falls in) stores the distance along the texel's centre
      // direction to the point's tangent plane, not the point's own distance: a receiver on the same surface then
      // meets its own depth up to half a texel's slope, instead of the depth of wherever the point fell in the texel
      // (which needed a bias of several texels' footprint, and that let light through thin walls).
      const float rad = std::clamp(radius, 0.5f, maxRadius);
      const glm::vec3 localNormal = frame.toLocal(np);
      const float planeOffset = glm::dot(local, localNormal);
      // floor by truncating a positive number (fx, fy >= 0, rad <= tileSize / 8): SSE2 has no rounding instruction.
      const int x0 = std::max(0, static_cast<int>(fx - rad + halfSize) - tileSize / 2),
                x1 = std::min(tileSize - 1, static_cast<int>(fx + rad));
      const int y0 = std::max(0, static_cast<int>(fy - rad + halfSize) - tileSize / 2),
                y1 = std::min(tileSize - 1, static_cast<int>(fy + rad));
      const SplatDisc disc{fx,          fy, rad * rad, static_cast<int>(fx), static_cast<int>(fy), localNormal,
                           planeOffset, r,  invFar};
      for (int y = y0; y <= y1; ++y) {
        const std::size_t row = static_cast<std::size_t>(y) * tileSize;
        splatRow(disc, y, x0, x1, directionX.data() + row, directionY.data() + row, directionZ.data() + row,
                 inDisc.data() + row, tile.data() + row);
      }
    }
    pullPush(tile, tileSize, fillLevels);
    uint16_t* out = atlas.data() + layout.tileOrigin(i);
    for (int y = 0; y < tileSize; ++y)
      for (int x = 0; x < tileSize; ++x) {
        float t = tile[static_cast<std::size_t>(y) * tileSize + x];
        out[static_cast<std::size_t>(y) * side + x] =
            t == kEmpty ? uint16_t(65535) : static_cast<uint16_t>(std::min(65534.0f, std::round(t * 65535.0f)));
      }
  });
}

float ismVisibility(const std::vector<uint16_t>& tiles, const IsmLayout& layout, int caster, const VplCaster& c,
                    glm::vec3 x, glm::vec3 geoNormal, float far, float bias) {
  const Frame frame(c.normal);
  const float texelAngle = 4.0f / static_cast<float>(layout.tileSize);
  const glm::vec3 d = x + geoNormal * (0.5f * texelAngle * glm::length(x - c.position)) - c.position;
  const glm::vec3 local = frame.toLocal(d);
  const float r = glm::length(d);
  if (local.z <= 0.0f || !(r > 0.0f)) return 1.0f;
  const float s = 1.0f / (r + local.z);
  const int tileSize = layout.tileSize, side = layout.atlasSize();
  const int px = std::clamp(static_cast<int>((local.x * s + 1.0f) * 0.5f * tileSize), 0, tileSize - 1);
  const int py = std::clamp(static_cast<int>((local.y * s + 1.0f) * 0.5f * tileSize), 0, tileSize - 1);
  const uint16_t stored = tiles[layout.tileOrigin(caster) + static_cast<std::size_t>(py) * side + px];
  return static_cast<float>(stored) / 65535.0f >= (r - bias - texelAngle * r) / far ? 1.0f : 0.0f;
}

}  // namespace vplab
