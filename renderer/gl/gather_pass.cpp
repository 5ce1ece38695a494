#include "renderer/gl/gather_pass.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

#include "renderer/core/sampling.h"

namespace vplab {

namespace {
// std140 layout of the VPL table of shaders/common/gather.glsl.
struct VplGpu {
  glm::vec4 position, normal, incoming, flux, baseColor, geoNormal, lambertPower;
};
}  // namespace

VplGatherPass::VplGatherPass() : tableLayout_(uniformTableLayout(sizeof(VplGpu))) {}

void VplGatherPass::useVisibility(const VplVisibility& visibility, const MediaShaderLayout& media) {
  std::vector<std::string> defines = {uniformTableDefine("GATHER_UBO_VPLS", tableLayout_), visibility.shaderDefine()};
  for (std::string& d : media.defines()) defines.push_back(std::move(d));
  point_ = std::make_unique<BrdfVariants>("preview/gather.frag.glsl", defines);
  sphere_ = std::make_unique<BrdfVariants>("preview/gather_vsl.frag.glsl", defines);
  sphereLambertVpls_.reset();
  defines_ = defines;
}

std::vector<uint32_t> gatherOrder(const Scene& scene, const VplSet& vpls, int* lambertCount) {
  std::vector<uint32_t> order(vpls.vpls.size());
  std::iota(order.begin(), order.end(), 0u);
  // The same test as evaluateBrdf's Lambert fast path.
  // A medium VPL's factor is precomputed like a Lambert one's (lambertPower: its flux), its phase function applied in
  // the loop.
  auto lambert = [&](uint32_t i) {
    if (vpls.vpls[i].inMedium) return true;
    const Material& m = scene.materials[vpls.vpls[i].material];
    return m.metallic <= 0.0f && m.specular <= 0.0f;
  };
  auto glossy = std::stable_partition(order.begin(), order.end(), lambert);
  *lambertCount = static_cast<int>(glossy - order.begin());
  // Medium VPLs before surface ones: cube visibility gives them whole cubes and surface VPLs hemicubes, and finds a
  // VPL's maps from how many whole cubes come before it (shadow_maps.h).
  std::stable_partition(order.begin(), glossy, [&](uint32_t i) { return vpls.vpls[i].inMedium; });
  return order;
}

void VplGatherPass::upload(const Scene& scene, const VplSet& set, const std::vector<uint32_t>& order,
                           int lambertCount) {
  lambertCount_ = lambertCount;
  std::vector<VplGpu> gpu(set.vpls.size());
  haveRadius_ = false;
  for (std::size_t i = 0; i < gpu.size(); ++i) {
    const Vpl& v = set.vpls[order[i]];
    haveRadius_ = haveRadius_ || v.radius > 0.0f;
    if (v.inMedium ? v.medium >= scene.media.size() : v.material >= scene.materials.size())
      throw std::invalid_argument("VPL " + std::to_string(order[i]) + " names a " +
                                  (v.inMedium ? "medium" : "material") +
                                  " the scene does not have: the VPLs were made for another scene");
    if (v.inMedium) {
      // A medium VPL (common/vpl_table.glsl): flagged in geoNormal.w, its phase function's g in baseColor.w, the
      // direction its light travelled on in geoNormal.xyz; no surface, so no shading normal and no BRDF.
      const float g = scene.media[v.medium].g;
      gpu[i] = {glm::vec4(v.position, 0.0f), glm::vec4(0.0f),           glm::vec4(v.incoming, 0.0f),
                glm::vec4(v.flux, 0.0f),     glm::vec4(0.0f, 0.0f, 0.0f, g), glm::vec4(-v.incoming, 1.0f),
                glm::vec4(v.flux, 0.0f)};
      continue;
    }
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

void VplGatherPass::drawTable(ShaderProgram& program, const VplVisibility& visibility, Target& raw,
                              const InterleavedLayout& layout, const GlVertexArray& vao, PassSlices& slices) const {
  LightTable table{&table_, BufferBinding::Vpls, tableLayout_, {},
                   [&](int maps, ShaderProgram& p) { visibility.bindChunk(maps, p); }};
  for (int c = 0; c < visibility.chunkCount(); ++c)
    table.chunks.push_back({visibility.chunkBegin(c), visibility.chunkEnd(c), c, visibility.chunkBegin(c), nullptr});
  drawInterleavedLightTable(program, raw, layout, table, vao, slices);
}

bool VplGatherPass::draw(bool lambertOnly, const Camera& camera, const Settings& settings, float far, float bias,
                         const VplVisibility& visibility, Target& raw, const InterleavedLayout& layout,
                         const GlVertexArray& vao, const std::function<bool()>& outOfTime) {
  // A set without VSLs uses the variant without the cone integral (common/gather.glsl).
  ShaderProgram& gather = (haveRadius_ ? *sphere_ : *point_)[lambertOnly];
  auto setUniforms = [&](ShaderProgram& program) {
    program.set("uCameraPosition", camera.position);
    program.set("uClampBound", settings.clampBound);
    program.set("uShadowFar", far);
    program.set("uShadowBias", bias);
  };
  setUniforms(gather);
  // At most kGatherVplsPerDraw VPLs per pixel and draw, so that a budget can stop between draws; the same split with
  // or without a budget, so that both sum in the same order and give the same image.
  LightTable table{&table_, BufferBinding::Vpls, tableLayout_, {},
                   [&](int maps, ShaderProgram& program) { visibility.bindChunk(maps, program); }};
  table.drawEmptySubsets = !lambertOnly;
  const int k = layout.k;
  table.layout.capacity =
      std::max(table.layout.alignment, std::min(table.layout.capacity, kGatherVplsPerDraw * k * k));
  // With VSLs on a scene with glossy materials, the VPLs on Lambert materials (first in the table) skip the lobe at
  // their end.
  const int lambertEnd = haveRadius_ && !lambertOnly ? lambertCount_ : 0;
  if (lambertEnd > 0 && !sphereLambertVpls_) {
    std::vector<std::string> defines = defines_;
    defines.push_back("VSL_LAMBERT_VPLS 1");
    sphereLambertVpls_ = std::make_unique<ShaderProgram>(
        std::vector<std::string>{"preview/fullscreen.vert.glsl", "preview/gather_vsl.frag.glsl"}, defines);
  }
  if (lambertEnd > 0) setUniforms(*sphereLambertVpls_);
  for (int c = 0; c < visibility.chunkCount(); ++c) {
    const int begin = visibility.chunkBegin(c), end = visibility.chunkEnd(c);
    const int split = std::clamp(lambertEnd, begin, end);
    if (split > begin) table.chunks.push_back({begin, split, c, begin, sphereLambertVpls_.get()});
    if (end > split) table.chunks.push_back({split, end, c, begin, nullptr});
  }
  slices_.begin(outOfTime);
  drawInterleavedLightTable(gather, raw, layout, table, vao, slices_);
  return slices_.end();
}

}  // namespace vplab
