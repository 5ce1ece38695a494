#include "renderer/gl/light_shadows.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <numeric>

#include "renderer/core/parallel.h"
#include "renderer/core/sampling.h"
#include "renderer/gl/gl_scene.h"
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
    g.radius = 0.0f;
    for (uint32_t t : g.triangles)
      for (int c = 0; c < 3; ++c)
        g.radius = std::max(g.radius, glm::length(scene.positions[scene.triangles[t][c]] - g.centre));
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

CubeFaceTriangles cubeFaceTriangles(const Scene& scene, glm::vec3 origin) {
  // Per vertex, 4 bits per face: which side planes of the face's frustum it lies outside. Face f looks along axis
  // a = f / 2 with sign s; its planes are s d_a >= +-d_b and s d_a >= +-d_c for the other two axes (d = vertex -
  // origin). The planes are widened by a millionth of the distance, so that rounding never drops a triangle on a face's
  // edge.
  constexpr int64_t kBlock = 1 << 16;
  std::vector<uint32_t> outside(scene.positions.size());
  const int64_t vertexBlocks = (static_cast<int64_t>(outside.size()) + kBlock - 1) / kBlock;
  parallelFor(vertexBlocks, 0, [&](int64_t block, int) {
    const std::size_t end = std::min(outside.size(), static_cast<std::size_t>((block + 1) * kBlock));
    for (std::size_t v = static_cast<std::size_t>(block * kBlock); v < end; ++v) {
      const glm::vec3 d = scene.positions[v] - origin;
      const float slack = 1e-6f * (std::abs(d.x) + std::abs(d.y) + std::abs(d.z));
      uint32_t bits = 0;
      for (int f = 0; f < 6; ++f) {
        const int a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
        const float u = (f % 2 ? -d[a] : d[a]) + slack;
        bits |= ((u < d[b] ? 1u : 0u) | (u < -d[b] ? 2u : 0u) | (u < d[c] ? 4u : 0u) | (u < -d[c] ? 8u : 0u))
                << (4 * f);
      }
      outside[v] = bits;
    }
  });
  // Blocks of triangles in parallel, each block's lists in the scene's order, joined block by block.
  const int64_t triangleBlocks = (static_cast<int64_t>(scene.triangles.size()) + kBlock - 1) / kBlock;
  std::vector<std::array<std::vector<uint32_t>, 6>> blockLists(static_cast<std::size_t>(triangleBlocks));
  parallelFor(triangleBlocks, 0, [&](int64_t block, int) {
    std::array<std::vector<uint32_t>, 6>& lists = blockLists[static_cast<std::size_t>(block)];
    const std::size_t end = std::min(scene.triangles.size(), static_cast<std::size_t>((block + 1) * kBlock));
    for (std::size_t i = static_cast<std::size_t>(block * kBlock); i < end; ++i) {
      const glm::uvec3& t = scene.triangles[i];
      const uint32_t common = outside[t.x] & outside[t.y] & outside[t.z];
      for (std::size_t f = 0; f < 6; ++f)
        if (((common >> (4 * f)) & 15u) == 0) {
          lists[f].push_back(t.x);
          lists[f].push_back(t.y);
          lists[f].push_back(t.z);
        }
    }
  });
  CubeFaceTriangles out;
  for (std::size_t f = 0; f < 6; ++f) {
    out.begin[f] = out.indices.size();
    for (const auto& lists : blockLists) out.indices.insert(out.indices.end(), lists[f].begin(), lists[f].end());
  }
  out.begin[6] = out.indices.size();
  return out;
}

int LightShadowMaps::render(const GlScene& scene, const std::vector<LightShadowCaster>& casters, int faceSize,
                            float far, int first, const std::function<bool()>& outOfTime) {
  if (!program_.valid()) program_ = ShaderProgram({"preview/light_shadow.vert.glsl", "preview/light_shadow.frag.glsl"});
  count_ = static_cast<int>(casters.size());
  // One cube at least, so that the direct pass's sampler is complete in a scene without such lights.
  const int cubes = std::max(count_, 1);
  if (!cubes_ || cubes_.layers() != 6 * cubes || faceSize_ != faceSize) {
    cubes_ = GlTexture::cubeArray(faceSize, cubes, TextureFormat::R32F);
    cubes_.setLinearFiltering(false);
    depth_ = GlTexture(faceSize, faceSize, TextureFormat::Depth32F);
    faceSize_ = faceSize;
  }
  // Cube face orientations of the GL specification (table 8.19), so that a samplerCubeArray lookup with the offset
  // from the light finds the texel rendered for it.
  static const glm::vec3 kTargets[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  static const glm::vec3 kUps[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  const glm::mat4 projection = glm::perspective(glm::radians(90.0f), 1.0f, far * 1e-5f, far);
  // Slope bias of the stored distance, at most this many texels' worth of distance (grazing triangles).
  if (count_ == 0) return -1;
  program_.set("uMaxSlopeBias", 4.0f * 2.0f / static_cast<float>(faceSize));
  program_.use();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  const int faces = 6 * count_;
  int next = -1;
  for (int face = first; face < faces; ++face) {
    const int c = face / 6, f = face % 6;
    framebuffer_.attachColor(0, cubes_, 0, face);
    framebuffer_.attachDepth(depth_);
    framebuffer_.finalize(1);
    framebuffer_.bind(faceSize, faceSize);
    framebuffer_.clearColor(0, glm::vec4(3.0e38f));
    framebuffer_.clearDepth(1.0f);
    const glm::vec3& origin = casters[static_cast<std::size_t>(c)].position;
    program_.set("uViewProjection", projection * glm::lookAt(origin, origin + kTargets[f], kUps[f]));
    program_.set("uLightPosition", origin);
    if (faceScene_ != scene.serial() || faceOrigin_ != origin) {
      const CubeFaceTriangles lists = cubeFaceTriangles(*scene.source(), origin);
      faceIndices_.assign(lists.indices.data(), std::max<std::size_t>(lists.indices.size(), 1) * sizeof(uint32_t));
      scene.attachPositions(faceVertices_, faceIndices_);
      faceBegin_ = lists.begin;
      faceScene_ = scene.serial();
      faceOrigin_ = origin;
    }
    faceVertices_.bind();
    const std::size_t begin = faceBegin_[static_cast<std::size_t>(f)],
                      end = faceBegin_[static_cast<std::size_t>(f) + 1];
    if (end > begin)
      glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(end - begin), GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(begin * sizeof(uint32_t)));
    if (outOfTime && face + 1 < faces && outOfTime()) {
      next = face + 1;
      break;
    }
  }
  glDisable(GL_DEPTH_TEST);
  return next;
}

int LightShadowMaps::renderDirectional(const GlScene& scene, const std::vector<glm::vec3>& directions, glm::vec3 centre,
                                       float radius, int size, int first, const std::function<bool()>& outOfTime) {
  if (!program_.valid()) program_ = ShaderProgram({"preview/light_shadow.vert.glsl", "preview/light_shadow.frag.glsl"});
  directionalCount_ = static_cast<int>(directions.size());
  // A 1-layer placeholder keeps the sampler complete when there is no directional light.
  const int layers = std::max(1, directionalCount_);
  if (!planes_ || planes_.layers() != layers || planes_.width() != size) {
    planes_ = GlTexture(size, size, TextureFormat::R32F, 1, layers);
    planes_.setLinearFiltering(false);
    planeDepth_ = GlTexture(size, size, TextureFormat::Depth32F);
  }
  program_.set("uAlongDirection", 1);
  program_.set("uMaxSlopeBias", 4.0f * 2.0f * radius / static_cast<float>(size));
  program_.use();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  int next = -1;
  for (int i = first; i < layers; ++i) {
    framebuffer_.attachColor(0, planes_, 0, i);
    framebuffer_.attachDepth(planeDepth_);
    framebuffer_.finalize(1);
    framebuffer_.bind(size, size);
    framebuffer_.clearColor(0, glm::vec4(3.0e38f));
    framebuffer_.clearDepth(1.0f);
    if (i >= directionalCount_) continue;
    // The frame of shaders/common/math.glsl orthonormalFrame around the direction: map u along s, v along t.
    const glm::vec3 dir = directions[static_cast<std::size_t>(i)];
    const Frame frame(dir);
    const glm::vec3 origin = centre - dir * radius;
    glm::mat4 view(1.0f);
    view[0] = glm::vec4(frame.s.x, frame.t.x, frame.n.x, 0.0f);
    view[1] = glm::vec4(frame.s.y, frame.t.y, frame.n.y, 0.0f);
    view[2] = glm::vec4(frame.s.z, frame.t.z, frame.n.z, 0.0f);
    view[3] = glm::vec4(-glm::dot(frame.s, centre), -glm::dot(frame.t, centre), -glm::dot(frame.n, origin), 1.0f);
    // View space: x, y in [-radius, radius], z = distance along the direction in [0, 2 radius]; GL looks down -z.
    const glm::mat4 flip = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, 1.0f, -1.0f));
    const glm::mat4 projection = glm::ortho(-radius, radius, -radius, radius, -1e-3f * radius, 2.001f * radius);
    program_.set("uViewProjection", projection * flip * view);
    program_.set("uLightPosition", origin);
    program_.set("uDirection", dir);
    scene.drawIndexed();
    if (outOfTime && i + 1 < layers && outOfTime()) {
      next = i + 1;
      break;
    }
  }
  program_.set("uAlongDirection", 0);
  glDisable(GL_DEPTH_TEST);
  return next;
}

void LightShadowMaps::bind() const {
  if (cubes_) cubes_.bind(unit(TextureUnit::LightShadows));
  if (planes_) planes_.bind(unit(TextureUnit::DirectionalShadows));
}

}  // namespace vplab
