#include "renderer/gl/gather_pass.h"

#include <algorithm>

#include "renderer/core/sampling.h"

namespace vplab {

namespace {
// std140 layout of the VPL table of shaders/common/gather.glsl.
struct VplGpu {
  glm::vec4 position, normal, incoming, flux, baseColor, geoNormal, lambertPower;
};
}  // namespace

VplGatherPass::VplGatherPass() : tableLayout_(uniformTableLayout(sizeof(VplGpu))) {}

void VplGatherPass::useVisibility(const VplVisibility& visibility) {
  const std::vector<std::string> defines = {uniformTableDefine("GATHER_UBO_VPLS", sizeof(VplGpu)),
                                            visibility.shaderDefine()};
  point_ = std::make_unique<BrdfVariants>("preview/gather.frag.glsl", defines);
  sphere_ = std::make_unique<BrdfVariants>("preview/gather_vsl.frag.glsl", defines);
}

void VplGatherPass::upload(const Scene& scene, const VplSet& set) {
  std::vector<VplGpu> gpu(set.vpls.size());
  haveRadius_ = false;
  for (std::size_t i = 0; i < gpu.size(); ++i) {
    const Vpl& v = set.vpls[i];
    haveRadius_ = haveRadius_ || v.radius > 0.0f;
    const Material& m = scene.materials[v.material];
    gpu[i] = {glm::vec4(v.position, v.radius),
              glm::vec4(v.normal, m.metallic),
              glm::vec4(v.incoming, m.roughness),
              glm::vec4(v.flux, m.specular),
              glm::vec4(scene.baseColorAt(v.material, v.uv), 0.0f),
              glm::vec4(v.geometricNormal, 0.0f),
              glm::vec4(0.0f)};
    // The pure-Lambert gather's whole VPL factor f(x2) Phi = albedo / pi Phi, 0 where the light arrived from behind
    // the shading normal (common/gather.glsl).
    if (glm::dot(v.normal, v.incoming) > 0.0f)
      gpu[i].lambertPower = glm::vec4(glm::vec3(gpu[i].baseColor) * v.flux * kInvPi, 0.0f);
  }
  table_.assign(gpu.data(), gpu.size() * sizeof(VplGpu));
}

bool VplGatherPass::draw(bool lambertOnly, const Camera& camera, const Settings& settings, float far, float bias,
                         const VplVisibility& visibility, Target& raw, const InterleavedLayout& layout,
                         const GlVertexArray& vao, const std::function<bool()>& outOfTime) {
  // A set without VSLs uses the variant without the cone integral (common/gather.glsl).
  ShaderProgram& gather = (haveRadius_ ? *sphere_ : *point_)[lambertOnly];
  gather.set("uCameraPosition", camera.position);
  gather.set("uClampBound", settings.clampBound);
  gather.set("uShadowFar", far);
  gather.set("uShadowBias", bias);
  // At most kGatherVplsPerDraw VPLs per pixel and draw, so that a budget can stop between draws; the same split with
  // or without a budget, so that both sum in the same order and give the same image.
  LightTable table{&table_, BufferBinding::Vpls, tableLayout_, {}, [&](int c) { visibility.bindChunk(c, gather); }};
  const int k = layout.k;
  table.layout.capacity = std::max(table.layout.alignment, std::min(table.layout.capacity, kGatherVplsPerDraw * k * k));
  for (int c = 0; c < visibility.chunkCount(); ++c)
    table.chunks.push_back({visibility.chunkBegin(c), visibility.chunkEnd(c)});
  return drawInterleavedLightTable(gather, raw, layout, table, vao, &nextDraw_, outOfTime);
}

}  // namespace vplab
