#include "renderer/gl/light_shadows.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>

#include "renderer/core/sampling.h"
#include "renderer/gl/texture_units.h"

namespace vplab {

namespace {

int findRoot(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

}  // namespace

std::vector<AreaLightGroup> groupAreaLights(const Scene& scene) {
  const std::vector<uint32_t>& emissive = scene.emissiveTriangles;
  // Connected components over shared vertex indices, and over coincident vertex positions (quads written with their
  // own vertices per face still form one emitter).
  std::vector<int> parent(emissive.size());
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<std::pair<glm::vec3, int>> corners;
  for (std::size_t e = 0; e < emissive.size(); ++e) {
    const glm::uvec3& v = scene.triangles[emissive[e]];
    for (int c = 0; c < 3; ++c) corners.push_back({scene.positions[v[c]], static_cast<int>(e)});
  }
  auto less = [](const auto& a, const auto& b) {
    return a.first.x != b.first.x   ? a.first.x < b.first.x
           : a.first.y != b.first.y ? a.first.y < b.first.y
                                    : a.first.z < b.first.z;
  };
  std::sort(corners.begin(), corners.end(), less);
  for (std::size_t i = 1; i < corners.size(); ++i)
    if (corners[i].first == corners[i - 1].first)
      parent[static_cast<std::size_t>(findRoot(parent, corners[i].second))] = findRoot(parent, corners[i - 1].second);

  std::vector<AreaLightGroup> groups;
  std::vector<int> groupOf(emissive.size(), -1), rootGroup(emissive.size(), -1);
  for (std::size_t e = 0; e < emissive.size(); ++e) {
    int root = findRoot(parent, static_cast<int>(e));
    if (rootGroup[static_cast<std::size_t>(root)] < 0) {
      rootGroup[static_cast<std::size_t>(root)] = static_cast<int>(groups.size());
      groups.emplace_back();
    }
    groups[static_cast<std::size_t>(rootGroup[static_cast<std::size_t>(root)])].triangles.push_back(emissive[e]);
  }
  auto measure = [&](AreaLightGroup& g) {
    glm::dvec3 weighted(0.0);
    double power = 0.0;
    for (uint32_t t : g.triangles) {
      const glm::uvec3& v = scene.triangles[t];
      double p = luminance(scene.meanEmission(t)) * scene.triangleArea(t);
      weighted += p * glm::dvec3(scene.positions[v.x] + scene.positions[v.y] + scene.positions[v.z]) / 3.0;
      power += p;
    }
    g.power = static_cast<float>(power);
    if (power > 0.0) g.centre = glm::vec3(weighted / power);
  };
  for (AreaLightGroup& g : groups) measure(g);
  std::sort(groups.begin(), groups.end(),
            [](const AreaLightGroup& a, const AreaLightGroup& b) { return a.power > b.power; });
  if (groups.size() > static_cast<std::size_t>(kMaxAreaGroups)) {
    // Too many emitters for a map each: the weaker ones join the nearest of the strongest, whose centre and radius
    // then cover them.
    for (std::size_t i = kMaxAreaGroups; i < groups.size(); ++i) {
      std::size_t best = 0;
      for (std::size_t j = 1; j < static_cast<std::size_t>(kMaxAreaGroups); ++j)
        if (glm::length(groups[j].centre - groups[i].centre) < glm::length(groups[best].centre - groups[i].centre))
          best = j;
      groups[best].triangles.insert(groups[best].triangles.end(), groups[i].triangles.begin(),
                                    groups[i].triangles.end());
    }
    groups.resize(kMaxAreaGroups);
    for (AreaLightGroup& g : groups) measure(g);
  }
  return groups;
}

int LightShadowMaps::render(const Scene& scene, const std::vector<LightShadowCaster>& casters, int threads,
                            int first, const std::function<bool()>& outOfTime) {
  count_ = static_cast<int>(casters.size());
  // One cube at least, so that the direct pass's sampler is complete in a scene without such lights: of one texel
  // then, since llvmpipe zero-fills every texture it allocates (a 1024^2 placeholder cost 24 MB of page faults).
  const int cubes = std::max(count_, 1);
  int side = 1;
  for (const LightShadowCaster& c : casters) side = std::max(side, c.faceSize);
  if (!cubes_ || cubes_.layers() != 6 * cubes || cubes_.width() != side) {
    cubes_ = GlTexture::cubeArray(side, cubes, TextureFormat::R16);
    cubes_.setLinearFiltering(false);
  }
  // Each cube's scale: a little more than its caster's distance to the farthest corner of the triangles' bounds, so
  // that every occluder's distance is below it. Set when the maps start; a resumed render has the same casters.
  if (first == 0 || scales_.size() != casters.size()) {
    scales_.resize(casters.size());
    const Bounds& b = scene.geometryBounds;
    for (std::size_t c = 0; c < casters.size(); ++c) {
      const float farthest = b.valid() ? glm::length(glm::max(glm::abs(casters[c].position - b.lower),
                                                              glm::abs(casters[c].position - b.upper)))
                                       : 0.0f;
      scales_[c] = std::isfinite(farthest) && farthest > 0.0f ? 1.01f * farthest : 1.0f;
    }
    // One entry at least: the buffer is bound with the (placeholder) cubes.
    const float none = 1.0f;
    scalesBuffer_.assign(scales_.empty() ? &none : scales_.data(),
                         std::max<std::size_t>(scales_.size(), 1) * sizeof(float));
  }
  if (count_ == 0) return -1;
  const int faces = 6 * count_;
  for (int face = first; face < faces; ++face) {
    const LightShadowCaster& caster = casters[static_cast<std::size_t>(face / 6)];
    const int size = caster.faceSize;
    assert(size > 0 && side % size == 0);
    // A cube's six faces share one binning; a render resumed inside a cube goes on with it (a change of the scene or
    // the lights starts the maps over from face 0).
    if (face % 6 == 0 || binnedScene_ != &scene || binnedOrigin_ != caster.position || rasterizer_.size() != size) {
      rasterizer_.binCube(scene, caster.position, size, threads);
      binnedScene_ = &scene;
      binnedOrigin_ = caster.position;
    }
    texels_.resize(static_cast<std::size_t>(size) * size);
    quantized_.resize(texels_.size());
    // 65535 only where no triangle lies; quantized band by band as the bands are drawn, on every core.
    const float perScale = 65535.0f / scales_[static_cast<std::size_t>(face / 6)];
    auto quantize = [&](int rowBegin, int rowEnd) {
      for (std::size_t i = static_cast<std::size_t>(rowBegin) * size; i < static_cast<std::size_t>(rowEnd) * size; ++i)
        quantized_[i] = texels_[i] >= kNoOccluder
                            ? std::uint16_t{65535}
                            : static_cast<std::uint16_t>(std::min(texels_[i] * perScale + 0.5f, 65534.0f));
    };
    // Slope bias of the stored distance, at most this many texels' worth of distance (grazing triangles).
    rasterizer_.draw(face % 6, 4.0f * 2.0f / static_cast<float>(size), threads, texels_.data(), quantize);
    if (size == side) {
      cubes_.uploadLayerUnorm16(face, quantized_);
    } else {
      // Texel (i, j) of the array's face takes texel (i / r, j / r) of the drawn one: a lookup of the array reads
      // what nearest sampling of the drawn map would (floor(s side) / r = floor(s size)).
      const int r = side / size;
      repeated_.resize(static_cast<std::size_t>(side) * side);
      for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i)
          repeated_[static_cast<std::size_t>(j) * side + i] = quantized_[static_cast<std::size_t>(j / r) * size + i / r];
      cubes_.uploadLayerUnorm16(face, repeated_);
    }
    if (outOfTime && face + 1 < faces && outOfTime()) return face + 1;
  }
  return -1;
}

int LightShadowMaps::renderDirectional(const Scene& scene, const std::vector<glm::vec3>& directions, glm::vec3 centre,
                                       float radius, int size, int threads, int first,
                                       const std::function<bool()>& outOfTime) {
  directionalCount_ = static_cast<int>(directions.size());
  // A 1-layer placeholder of one texel keeps the sampler complete when there is no directional light (no shader
  // reads it then).
  const int layers = std::max(1, directionalCount_);
  const int side = directionalCount_ > 0 ? size : 1;
  if (!planes_ || planes_.layers() != layers || planes_.width() != side) {
    planes_ = GlTexture(side, side, TextureFormat::R32F, 1, layers);
    planes_.setLinearFiltering(false);
  }
  if (directionalCount_ == 0) return -1;
  texels_.resize(static_cast<std::size_t>(size) * size);
  for (int i = first; i < layers; ++i) {
    const glm::vec3 direction = directions[static_cast<std::size_t>(i)];
    rasterizer_.binPlane(scene, direction, centre, radius, size, threads);
    binnedScene_ = nullptr;
    rasterizer_.draw(0, 4.0f * 2.0f * radius / static_cast<float>(size), threads, texels_.data());
    planes_.uploadLayerFloat(i, texels_);
    if (outOfTime && i + 1 < layers && outOfTime()) return i + 1;
  }
  return -1;
}

void LightShadowMaps::bind() const {
  if (cubes_) cubes_.bind(unit(TextureUnit::LightShadows));
  if (scalesBuffer_.size() > 0) scalesBuffer_.bindStorage(binding(BufferBinding::LightShadowScales));
  if (planes_) planes_.bind(unit(TextureUnit::DirectionalShadows));
}

}  // namespace vplab
