#include "renderer/offline/lightcuts_renderer.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>

#include "renderer/offline/camera_sample.h"
#include "renderer/offline/lightcut_bound.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/scene/gltf_loader.h"

namespace vplab {

LightcutGather::LightcutGather(const EmbreeScene& embree, const std::vector<Vpl>& vpls,
                               const std::vector<BrdfParams>& brdfs, const LightTree& tree, float clampBound,
                               float relativeError, int maxCut)
    : embree_(embree),
      vpls_(vpls),
      brdfs_(brdfs),
      tree_(tree),
      clampBound_(clampBound),
      relativeError_(relativeError),
      maxCut_(static_cast<uint32_t>(std::max(1, maxCut))) {}

namespace {

/// A node of the cut being refined.
struct CutNode {
  float bound;  ///< B_C luminance(I_C)
  uint32_t node;
  glm::vec3 estimate;   ///< E_C with visibility
  glm::vec3 unclamped;  ///< E_C with G instead of G_b
  bool visible;         ///< V of the representative (when a shadow ray was traced)
  bool traced;          ///< whether it was
  bool operator<(const CutNode& o) const { return bound < o.bound; }  ///< max-heap on the bound
};

}  // namespace

Lightcut LightcutGather::gather(const ShadingPoint& sp) const {
  Lightcut cut;
  const std::vector<LightTreeNode>& nodes = tree_.nodes();
  if (nodes.empty()) return cut;
  const std::vector<glm::vec3>& intensities = tree_.intensities();
  // Reused per thread: the cut's heap holds up to lightcutMax nodes.
  static thread_local std::vector<CutNode> heap;
  heap.clear();
  glm::vec3 total(0.0f);    // running estimate, for the threshold
  glm::vec3 settled(0.0f);  // single VPLs and nodes of bound 0: final
  glm::vec3 settledUnclamped(0.0f);

  // E_C (without V) of a node at sp; a single VPL's exact contribution.
  auto estimate = [&](const LightTreeNode& node, glm::vec3& unclamped) -> glm::vec3 {
    const Vpl& vpl = vpls_[node.representative];
    const BrdfParams& vplBrdf = brdfs_[node.representative];
    if (node.leaf()) return vplUnoccludedContribution(sp, vpl, vplBrdf, clampBound_, &unclamped);
    unclamped = glm::vec3(0.0f);
    VplPairGeometry pair;
    if (!vplPairGeometry(sp.hit, vpl, pair)) return glm::vec3(0.0f);
    const float repIntensity = luminance(intensities[node.representative]);
    if (!(repIntensity > 0.0f)) return glm::vec3(0.0f);
    const glm::vec3 f1 = evaluateBrdfForVpl(sp.brdf, sp.hit.shadingNormal, sp.wo, pair.w);
    const glm::vec3 f2 = evaluateBrdfForVpl(vplBrdf, vpl.normal, vpl.incoming, -pair.w);
    // s_r: the representative's own BRDF relative to its bound (1 for Lambert VPLs), times the cluster's intensity.
    const glm::vec3 base = f1 * node.intensity * (luminance(f2 * vpl.flux) / repIntensity);
    unclamped = base * pair.g;
    return base * std::min(pair.g, clampBound_);
  };
  auto visibleFrom = [&](uint32_t vplIndex) {
    const Vpl& vpl = vpls_[vplIndex];
    const ShadowRay ray =
        embree_.shadowRayBetween(sp.hit.position, sp.hit.geometricNormal, vpl.position, vpl.geometricNormal);
    ++cut.shadowRays;
    return !embree_.occluded(ray.origin, ray.direction, ray.tMax);
  };
  // Adds a node to the cut; `parent` (when given) lends its representative's visibility.
  auto add = [&](uint32_t index, const CutNode* parent) {
    const LightTreeNode& node = nodes[index];
    ++cut.nodes;
    glm::vec3 unclamped;
    glm::vec3 e = estimate(node, unclamped);
    const bool lit = e.r > 0.0f || e.g > 0.0f || e.b > 0.0f;
    bool traced = false, visible = false;
    if (lit) {
      if (parent && parent->traced && nodes[parent->node].representative == node.representative) {
        visible = parent->visible;
      } else {
        visible = visibleFrom(node.representative);
      }
      traced = true;
      if (!visible) e = unclamped = glm::vec3(0.0f);
    }
    const float bound = node.leaf() ? 0.0f : lightcutBound(sp, node, clampBound_) * luminance(node.intensity);
    total += e;
    if (bound > 0.0f) {
      heap.push_back({bound, index, e, unclamped, visible, traced});
      std::push_heap(heap.begin(), heap.end());
    } else {
      settled += e;
      settledUnclamped += unclamped;
    }
  };

  // Step 1: the root. Step 2: refine the node of largest bound until the threshold or the cut size stops it.
  add(0, nullptr);
  while (!heap.empty()) {
    const CutNode& top = heap.front();
    if (top.bound <= relativeError_ * luminance(total)) break;
    if (cut.nodes >= maxCut_) {
      cut.maxReached = true;
      break;
    }
    std::pop_heap(heap.begin(), heap.end());
    const CutNode parent = heap.back();
    heap.pop_back();
    total -= parent.estimate;
    --cut.nodes;
    add(parent.node + 1, &parent);
    add(nodes[parent.node].secondChild, &parent);
  }
  // Step 3: the estimate, summed afresh (the running total only steered the refinement).
  cut.radiance = settled;
  cut.unclamped = settledUnclamped;
  for (const CutNode& c : heap) {
    cut.radiance += c.estimate;
    cut.unclamped += c.unclamped;
    cut.errorBound += c.bound;
  }
  return cut;
}

CutSizeSummary summarizeCutSizes(const Image& cutSize, int maxCut) {
  CutSizeSummary summary;
  std::vector<float> sizes;
  for (const glm::vec3& p : cutSize.pixels)
    if (p.r > 0.0f) sizes.push_back(p.r);
  summary.pixels = sizes.size();
  if (sizes.empty()) return summary;
  std::sort(sizes.begin(), sizes.end());
  double sum = 0.0, atMax = 0.0;
  for (float v : sizes) {
    sum += v;
    atMax += v >= static_cast<float>(maxCut) ? 1.0 : 0.0;
  }
  summary.mean = sum / static_cast<double>(sizes.size());
  summary.p95 = sizes[std::min(sizes.size() - 1, static_cast<std::size_t>(0.95 * static_cast<double>(sizes.size())))];
  summary.max = sizes.back();
  summary.atMax = atMax / static_cast<double>(sizes.size());
  return summary;
}

void requireLightcutsApply(const Scene& scene, const Settings& settings, Method method) {
  const std::string name = toString(method);
  if (scene.hasMedia())
    throw SceneError(name +
                     " renders surfaces only and this scene has participating media: medium VPLs have no orientation "
                     "cone and medium receivers no bound here (use vpl, vpl-kk or vpl-abc)");
  if (settings.vslRadius > 0.0f || settings.vslRadiusFromDensity)
    throw std::invalid_argument(name +
                                " lights point VPLs: a VSL's sphere integral is not bounded by 1 / d_min^2 (set the "
                                "VSL radius to 0, or use the vsl method)");
}

namespace {

/// Per-pixel counters (a pixel is touched by one thread at a time).
struct CutTally {
  uint64_t cuts = 0, nodes = 0, rays = 0, atMax = 0;
};

}  // namespace

LightcutsRenderResult renderLightcuts(const OfflineScene& offline, const VplSet& vplSet, Method method,
                                      const Settings& settings, RenderControl* control, OnPass onPass) {
  const auto start = std::chrono::steady_clock::now();
  const Scene& scene = offline.scene();
  const EmbreeScene& embree = offline.embree();
  requireLightcutsApply(scene, settings, method);
  std::vector<BrdfParams> brdfs;
  brdfs.reserve(vplSet.vpls.size());
  for (const Vpl& v : vplSet.vpls) brdfs.push_back(brdfParamsAt(scene, v.material, v.uv));
  const LightTree tree(vplSet.vpls, brdfs, settings.seed, resolveThreadCount(settings.threads));
  const LightcutGather cuts(embree, vplSet.vpls, brdfs, tree, settings.clampBound, settings.lightcutError,
                            settings.lightcutMax);
  // Kollig & Keller's compensation, computed as vpl-kk does (every VPL at its vertices).
  std::optional<VplTransport> compensation;
  if (method == Method::LightcutsKK) compensation.emplace(offline, vplSet, Method::VplKK, settings);

  const std::size_t pixels = static_cast<std::size_t>(std::max(0, settings.width)) * std::max(0, settings.height);
  std::vector<GatherTally> tallies(pixels);
  std::vector<CutTally> cutTallies(pixels);
  ProgressiveOptions options = progressiveOptions(settings, 1, std::move(onPass));
  PixelEstimator estimator = [&](int x, int y, uint32_t, Rng& rng) -> glm::vec3 {
    const std::size_t pixel = static_cast<std::size_t>(y) * settings.width + x;
    GatherTally& tally = tallies[pixel];
    CutTally& cutTally = cutTallies[pixel];
    return manyLightCameraSample(
        embree, offline.lights(), settings, x, y, rng,
        [&](const glm::vec3&, const std::vector<MediumInterval>&, float) { return glm::vec3(0.0f); },
        [&](const Interaction& sp) {
          // The bounded VPL sum through the cut, then (LightcutsKK) the residual's compensation.
          const Lightcut cut = cuts.gather({sp.hit, sp.wo, sp.brdf});
          ++cutTally.cuts;
          cutTally.nodes += cut.nodes;
          cutTally.rays += cut.shadowRays;
          cutTally.atMax += cut.maxReached ? 1 : 0;
          tally.shadowRays += cut.shadowRays;
          tally.evaluations += cut.nodes;
          tally.clampedLum += luminance(cut.radiance);
          tally.unclampedLum += luminance(cut.unclamped);
          glm::vec3 l = cut.radiance;
          if (compensation) l += compensation->methodCompensation(sp, rng, tally);
          return l;
        });
  };
  LightcutsRenderResult result;
  static_cast<ProgressiveResult&>(result) = renderProgressive(options, estimator, control);
  addTallies(tallies, result);
  CutTally total;
  result.cutSize = Image(settings.width, settings.height);
  for (std::size_t i = 0; i < cutTallies.size(); ++i) {
    const CutTally& t = cutTallies[i];
    total.cuts += t.cuts, total.nodes += t.nodes, total.rays += t.rays, total.atMax += t.atMax;
    result.cutSize.pixels[i] = glm::vec3(t.cuts ? static_cast<float>(t.nodes) / static_cast<float>(t.cuts) : 0.0f);
  }
  result.treeSeconds = tree.buildSeconds();
  result.treeNodes = tree.nodes().size();
  result.treeBytes = tree.nodes().size() * sizeof(LightTreeNode);
  result.cuts = total.cuts;
  result.cutsAtMax = total.atMax;
  result.meanCut = total.cuts ? static_cast<double>(total.nodes) / static_cast<double>(total.cuts) : 0.0;
  result.meanShadowRays = total.cuts ? static_cast<double>(total.rays) / static_cast<double>(total.cuts) : 0.0;
  // The tree's build is part of the render's time.
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace vplab
