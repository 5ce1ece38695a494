#include "renderer/gl/direct_pass.h"

#include <algorithm>
#include <limits>
#include <string>
#include <unordered_map>

#include "renderer/core/sampling.h"

namespace vplab {

namespace {
// std140 layout of the light table of shaders/preview/direct.frag.glsl.
struct DirectLightGpu {
  glm::vec4 position, axis, weight, shadow, centre;
};
}  // namespace

namespace {
// Splits an emitter's samples [begin, end) into `cells` cells of nearby samples (median splits across the longest
// extent, recursively), each behind a new caster at its samples' centroid with faces of faceSize^2: shadow.x is its
// map, centre its position (shadow.y, the emitter, stays).
void splitIntoCells(std::vector<DirectLightGpu>& samples, std::size_t begin, std::size_t end, int cells, int faceSize,
                    std::vector<LightShadowCaster>& casters) {
  if (cells > 1 && end - begin >= 2) {
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::size_t i = begin; i < end; ++i) {
      lo = glm::min(lo, glm::vec3(samples[i].position));
      hi = glm::max(hi, glm::vec3(samples[i].position));
    }
    const glm::vec3 extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const std::size_t middle = begin + (end - begin) / 2;
    std::nth_element(
        samples.begin() + static_cast<std::ptrdiff_t>(begin), samples.begin() + static_cast<std::ptrdiff_t>(middle),
        samples.begin() + static_cast<std::ptrdiff_t>(end),
        [axis](const DirectLightGpu& a, const DirectLightGpu& b) { return a.position[axis] < b.position[axis]; });
    splitIntoCells(samples, begin, middle, cells / 2, faceSize, casters);
    splitIntoCells(samples, middle, end, cells - cells / 2, faceSize, casters);
    return;
  }
  glm::vec3 centre(0.0f), normal(0.0f);
  for (std::size_t i = begin; i < end; ++i) {
    centre += glm::vec3(samples[i].position);
    normal += glm::vec3(samples[i].axis);
  }
  centre /= static_cast<float>(end - begin);
  float radius = 0.0f;
  for (std::size_t i = begin; i < end; ++i)
    radius = std::max(radius, glm::distance(centre, glm::vec3(samples[i].position)));
  // The map's origin a little in front of the emitter: from a point in its plane the emitter's own triangles are seen
  // edge-on, and rounding can make one cover half the map at distance ~0 (every receiver shadowed).
  const float normalLength = glm::length(normal);
  if (normalLength > 0.5f * static_cast<float>(end - begin))
    centre += normal / normalLength * (1e-3f * radius + 1e-5f * glm::length(centre));
  const float map = static_cast<float>(casters.size());
  casters.push_back({centre, faceSize});
  for (std::size_t i = begin; i < end; ++i) {
    samples[i].shadow.x = map;
    samples[i].centre = glm::vec4(centre, 0.0f);
  }
}

// The blocker-search taps of the area run [begin, end) of `lights`: tap j takes sample begin + j (end - begin) / taps,
// so the taps cover every cell in proportion to its samples.
BlockerSearchTaps searchTapsOf(const std::vector<DirectLightGpu>& lights, int begin, int end) {
  BlockerSearchTaps taps;
  for (int j = 0; j < kBlockerSearchTaps; ++j) {
    const DirectLightGpu& l = lights[static_cast<std::size_t>(begin + j * (end - begin) / kBlockerSearchTaps)];
    taps.sample[static_cast<std::size_t>(j)] = glm::vec4(glm::vec3(l.position), l.shadow.x);
    taps.normal[static_cast<std::size_t>(j)] = glm::vec3(l.axis);
    taps.centre[static_cast<std::size_t>(j)] = glm::vec3(l.centre);
  }
  return taps;
}

// The pixel of a k x k block each blocker-search tap searches from: tap j from pixel j mod k^2 (row by row).
std::array<glm::vec2, kBlockerSearchTaps> searchTapPixels(int k) {
  std::array<glm::vec2, kBlockerSearchTaps> pixels;
  for (int j = 0; j < kBlockerSearchTaps; ++j) {
    const int q = j % (k * k);
    pixels[static_cast<std::size_t>(j)] = glm::vec2(q % k, q / k);
  }
  return pixels;
}

BrdfVariants directProgram(const UniformTableLayout& layout, int mapKind, const MediaShaderLayout& media = {}) {
  std::vector<std::string> defines = {uniformTableDefine("DIRECT_UBO_LIGHTS", layout),
                                      "DIRECT_MAP_KIND " + std::to_string(mapKind)};
  for (std::string& d : media.defines()) defines.push_back(std::move(d));
  return BrdfVariants("preview/direct.frag.glsl", defines);
}
}  // namespace

DirectLightPass::DirectLightPass()
    : tableLayout_(uniformTableLayout(sizeof(DirectLightGpu))),
      programs_{directProgram(tableLayout_, AreaMap), directProgram(tableLayout_, PunctualMap),
                directProgram(tableLayout_, DirectionalMap)},
      searchProgram_({"preview/fullscreen.vert.glsl", "preview/blocker_search.frag.glsl"},
                     {"BLOCKER_SEARCH_TAPS " + std::to_string(kBlockerSearchTaps)}) {}

void DirectLightPass::useMedia(const MediaShaderLayout& media) {
  if (media == media_) return;
  media_ = media;
  programs_ = {directProgram(tableLayout_, AreaMap, media), directProgram(tableLayout_, PunctualMap, media),
               directProgram(tableLayout_, DirectionalMap, media)};
}

DirectLightPass::TableView DirectLightPass::bindTable() const {
  shadows_.bind();
  TableView view{&table_, tableLayout_, 0, 0, runs_.empty() ? 0 : runs_.back().end, sizes_};
  for (const MapRun& run : runs_) {
    if (run.kind == AreaMap) view.areaEnd = run.end;
    if (run.kind != DirectionalMap) view.punctualEnd = run.end;
  }
  return view;
}

bool DirectLightPass::renderMaps(const Scene& scene, const Settings& settings, float sceneRadius,
                                 const std::function<bool()>& outOfTime) {
  if (!mapsStarted_) {
    uploadLights(scene, settings);
    mapsStarted_ = true;
    nextFace_ = nextDirectional_ = 0;
  }
  if (nextFace_ >= 0) {
    nextFace_ = shadows_.render(scene, casters_, settings.threads, nextFace_, outOfTime);
    if (nextFace_ >= 0) return false;
    // The last face was a slice of its own too.
    if (!casters_.empty() && !directionalDirections_.empty() && outOfTime && outOfTime()) return false;
  }
  nextDirectional_ = shadows_.renderDirectional(scene, directionalDirections_, scene.bounds.center(), sceneRadius,
                                                sizes_.directional, settings.threads, nextDirectional_, outOfTime);
  if (nextDirectional_ >= 0) return false;
  mapsStarted_ = false;
  return true;
}

bool DirectLightPass::draw(bool lambertOnly, const Camera& camera, glm::vec3 sceneCentre, float sceneRadius,
                           Target& raw, const InterleavedLayout& layout, Target* punctual, const GlVertexArray& vao,
                           const std::function<bool()>& outOfTime) {
  // The programs of the kinds of map the scene has: a program is compiled when first asked for (BrdfVariants).
  for (int kind = 0; kind < MapKinds; ++kind) {
    if (std::none_of(runs_.begin(), runs_.end(), [kind](const MapRun& run) { return run.kind == kind; })) continue;
    ShaderProgram& direct = programs_[static_cast<std::size_t>(kind)][lambertOnly];
    direct.set("uCameraPosition", camera.position);
    direct.set("uLightShadowTexel", 2.0f / static_cast<float>(sizes_.punctualFace));
    direct.set("uAreaShadowTexel", 2.0f / static_cast<float>(sizes_.areaFace));
    direct.set("uSceneCentre", sceneCentre);
    direct.set("uSceneRadius", sceneRadius);
    direct.set("uDirectionalShadowTexel", 2.0f * sceneRadius / static_cast<float>(sizes_.directional));
  }
  // Every map is a layer of one cube-map array or of one 2D array, all bound at once; a chunk per run of lights behind
  // one map, drawn by the program of the map's kind. An area run's chunk reads its emitter's blocker search, the
  // layer of searches_ named by the chunk's `maps`.
  shadows_.bind();
  LightTable area{&table_, BufferBinding::DirectLights, tableLayout_, {}, {}};
  LightTable exact = area;
  area.bindChunk = [](int emitter, ShaderProgram& program) { program.set("uSearchLayer", emitter); };
  for (const MapRun& run : runs_) {
    LightTable& table = run.kind == AreaMap ? area : exact;
    const int emitter = run.kind == AreaMap ? static_cast<int>(area.chunks.size()) : 0;
    table.chunks.push_back({run.begin, run.end, emitter, 0, &programs_[run.kind][lambertOnly]});
  }
  // Every chunk names its program, so the tables' own is never drawn with: one the scene uses stands in for it.
  ShaderProgram& standIn = programs_[runs_.empty() ? AreaMap : runs_.front().kind][lambertOnly];
  drawSlices_.begin(outOfTime);
  drawBlockerSearches(layout, vao);
  drawInterleavedLightTable(standIn, raw, layout, area, vao, drawSlices_);
  const InterleavedLayout everyPixel{layout.width, layout.height, 1, layout.width, layout.height};
  if (punctual) drawInterleavedLightTable(standIn, *punctual, everyPixel, exact, vao, drawSlices_);
  return drawSlices_.end();
}

void DirectLightPass::drawBlockerSearches(const InterleavedLayout& layout, const GlVertexArray& vao) {
  const int emitters = static_cast<int>(searchTaps_.size());
  if (emitters == 0) return;
  if (!searches_ || searches_.width() != layout.blockWidth || searches_.height() != layout.blockHeight ||
      searches_.layers() != emitters)
    searches_ = GlTexture(layout.blockWidth, layout.blockHeight, TextureFormat::Rgba32F, 1, emitters);
  ShaderProgram& search = searchProgram_.get();
  search.set("uInterleave", layout.k);
  search.set("uImageSize", glm::ivec2(layout.width, layout.height));
  search.set("uAreaShadowTexel", 2.0f / static_cast<float>(sizes_.areaFace));
  const std::array<glm::vec2, kBlockerSearchTaps> pixels = searchTapPixels(layout.k);
  search.setArray("uTapPixel", pixels.data(), kBlockerSearchTaps);
  for (int e = 0; e < emitters; ++e)
    drawSlices_.step([&, e] {
      const BlockerSearchTaps& taps = searchTaps_[static_cast<std::size_t>(e)];
      searchTarget_.attachColor(0, searches_, 0, e);
      searchTarget_.finalize(1);
      searchTarget_.bind(layout.blockWidth, layout.blockHeight);
      search.setArray("uTapSample", taps.sample.data(), kBlockerSearchTaps);
      search.setArray("uTapNormal", taps.normal.data(), kBlockerSearchTaps);
      search.setArray("uTapCentre", taps.centre.data(), kBlockerSearchTaps);
      drawFullscreen(search, vao);
    });
  searches_.bind(unit(TextureUnit::BlockerSearch));
}

void DirectLightPass::uploadLights(const Scene& scene, const Settings& settings) {
  std::vector<DirectLightGpu> lights;
  runs_.clear();
  // Appends a light behind a map of `kind`: a run goes on while the kind stays the same, and for area-light samples
  // while the emitter does (the shader's blocker search runs once per run, over the maps of the emitter's cells).
  auto add = [&](const DirectLightGpu& light, MapKind kind) {
    const int index = static_cast<int>(lights.size());
    if (runs_.empty() || runs_.back().kind != kind || (kind == AreaMap && lights.back().shadow.y != light.shadow.y))
      runs_.push_back({index, index, kind});
    lights.push_back(light);
    runs_.back().end = index + 1;
  };
  casters_.clear();
  sizes_ = LightMapSizes::of(settings);
  // Shadow maps: a few per area emitter, one per cell of its samples (below), and one per punctual light.
  std::vector<AreaLightGroup> groups = groupAreaLights(scene);
  std::unordered_map<uint32_t, int> groupOf;
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (uint32_t t : groups[g].triangles) groupOf[t] = static_cast<int>(g);
  // Area lights: K points y_k chosen with p(triangle) proportional to its power (luminance of its mean textured Le
  // x area, as the offline light sampler chooses) and uniform on the triangle, so p_A(y) = p_t / A_t; each carries
  // Le(y) / (K p_A), Le looked up at y, making the sum an unbiased estimate of the unshadowed T Le; the visibility
  // comes from the sample's emitter map.
  std::vector<float> cdf;
  std::vector<uint32_t> emitters;  // triangles with power > 0 (a black part of a textured emitter is never chosen)
  float total = 0.0f;
  for (uint32_t t : scene.emissiveTriangles) {
    float power = luminance(scene.meanEmission(t)) * scene.triangleArea(t);
    if (!(power > 0.0f)) continue;
    total += power;
    cdf.push_back(total);
    emitters.push_back(t);
  }
  if (total > 0.0f) {
    std::vector<DirectLightGpu> samples;
    int k = settings.directLightSamples;
    // Sample s is Halton point s in bases 2 (the light choice) and 3, 5 (the point on the triangle), rotated by the
    // seed: deterministic (the same settings give the same samples, hence a stable preview) and stratified, so the
    // K samples cover the emitters evenly (independent random samples left errors of +-20 % at K = 64 where an
    // emitter is seen at grazing angles; these give +-3 %).
    Rng rotation(hashKey(settings.seed, 0x646972656374ull));
    const float offsetLight = rotation.next1D();
    const glm::vec2 offsetPoint = rotation.next2D();
    for (int s = 0; s < k; ++s) {
      const auto index = static_cast<uint64_t>(s);
      float u = rotateUnit(radicalInverse(2, index), offsetLight) * total;
      std::size_t i = static_cast<std::size_t>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
      i = std::min(i, cdf.size() - 1);
      uint32_t tri = emitters[i];
      float pTri = (cdf[i] - (i ? cdf[i - 1] : 0.0f)) / total;
      glm::vec2 b = sampleUniformTriangle(
          {rotateUnit(radicalInverse(3, index), offsetPoint.x), rotateUnit(radicalInverse(5, index), offsetPoint.y)});
      const glm::uvec3& v = scene.triangles[tri];
      glm::vec3 y = b.x * scene.positions[v.x] + b.y * scene.positions[v.y] + (1.0f - b.x - b.y) * scene.positions[v.z];
      float pdfA = pTri / scene.triangleArea(tri);
      glm::vec3 weight =
          scene.emissionAt(scene.triangleMaterials[tri], scene.uvAt(tri, b)) / (static_cast<float>(k) * pdfA);
      samples.push_back({glm::vec4(y, 0.0f), glm::vec4(scene.geometricNormal(tri), 0.0f), glm::vec4(weight, 0.0f),
                         glm::vec4(glm::vec2(static_cast<float>(groupOf.at(tri))), 0.0f, 0.0f), glm::vec4(0.0f)});
    }
    // Samples of one emitter next to each other, then split into cells, each behind its own map: up to
    // kAreaShadowCells per emitter while the emitters' maps stay within kMaxAreaGroups in all (what previewFitProblem
    // budgets), and with at least 4 samples per cell. Not by the interleaving: a change of k redraws no map (a cell
    // with fewer samples than k^2 leaves some subsets without one, which the merge averages over).
    std::stable_sort(samples.begin(), samples.end(),
                     [](const DirectLightGpu& a, const DirectLightGpu& b) { return a.shadow.y < b.shadow.y; });
    for (std::size_t begin = 0; begin < samples.size();) {
      std::size_t end = begin;
      while (end < samples.size() && samples[end].shadow.y == samples[begin].shadow.y) ++end;
      const int cells = std::max(1, std::min({kAreaShadowCells, kMaxAreaGroups / static_cast<int>(groups.size()),
                                              static_cast<int>(end - begin) / 4}));
      splitIntoCells(samples, begin, end, cells, sizes_.areaFace, casters_);
      begin = end;
    }
    for (const DirectLightGpu& sample : samples) add(sample, AreaMap);
  }
  // The point and spot lights, then the directional ones: one run each.
  for (const PunctualLight& l : scene.punctualLights) {
    if (l.isDirectional()) continue;
    bool spot = l.type == PunctualLight::Type::Spot;
    const float cube = static_cast<float>(casters_.size());
    casters_.push_back({l.position, sizes_.punctualFace});
    add({glm::vec4(l.position, spot ? 2.0f : 1.0f), glm::vec4(l.direction, std::cos(l.outerConeAngle)),
         glm::vec4(l.intensity, std::cos(l.innerConeAngle)), glm::vec4(cube, 0.0f, 0.0f, 0.0f),
         glm::vec4(l.position, 0.0f)},
        PunctualMap);
  }
  directionalDirections_.clear();
  for (const PunctualLight& l : scene.punctualLights) {
    if (!l.isDirectional()) continue;
    const float map = static_cast<float>(directionalDirections_.size());
    directionalDirections_.push_back(l.direction);
    add({glm::vec4(0.0f, 0.0f, 0.0f, 3.0f), glm::vec4(l.direction, 0.0f), glm::vec4(l.intensity, 0.0f),
         glm::vec4(map, 0.0f, 0.0f, 0.0f), glm::vec4(0.0f)},
        DirectionalMap);
  }
  searchTaps_.clear();
  for (const MapRun& run : runs_)
    if (run.kind == AreaMap) searchTaps_.push_back(searchTapsOf(lights, run.begin, run.end));
  table_.assign(lights.data(), lights.size() * sizeof(DirectLightGpu));
}

}  // namespace vplab
