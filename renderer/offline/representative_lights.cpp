#include "renderer/offline/representative_lights.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_map>

#include "renderer/core/parallel.h"
#include "renderer/offline/lightcut_bound.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/vpl/vpl_importance.h"

namespace vplab {

bool previewReducesVpls(const VplSet& vpls, const Settings& settings) {
  if (vpls.vpls.size() <= static_cast<std::size_t>(std::max(1, settings.previewRepresentatives))) return false;
  return std::none_of(vpls.vpls.begin(), vpls.vpls.end(), [](const Vpl& v) { return v.inMedium; });
}

RepresentativeLights::RepresentativeLights(const OfflineScene& offline, const VplSet& vpls, const Settings& settings)
    : offline_(offline), vpls_(vpls) {
  stats_.vpls = vpls.vpls.size();
  stats_.representatives = vpls.vpls.size();
  if (!previewReducesVpls(vpls, settings)) return;
  brdfs_.reserve(vpls.vpls.size());
  for (const Vpl& v : vpls.vpls) brdfs_.push_back(brdfParamsAt(offline.scene(), v.material, v.uv));
  tree_ = std::make_unique<LightTree>(vpls.vpls, brdfs_, settings.seed, resolveThreadCount(settings.threads));
  stats_.treeSeconds = tree_->buildSeconds();
}

namespace {

/// A node of the cut being refined: larger priority first, then larger luminance(I_C), then the lower index (so
/// that ties refine in one order).
struct CutEntry {
  double priority;
  float power;
  uint32_t node;
  bool operator<(const CutEntry& o) const {
    if (priority != o.priority) return priority < o.priority;
    if (power != o.power) return power < o.power;
    return node > o.node;
  }
};

/// Refines the root of `nodes` until `size` nodes (or every leaf): the node of largest priority(node) first. Leaves
/// are final. Returns the cut's nodes.
template <typename Priority>
std::vector<uint32_t> refineCut(const std::vector<LightTreeNode>& nodes, std::size_t size, Priority&& priority) {
  std::vector<uint32_t> cut;
  std::vector<CutEntry> heap;
  auto add = [&](uint32_t index) {
    const LightTreeNode& node = nodes[index];
    if (node.leaf()) {
      cut.push_back(index);
      return;
    }
    heap.push_back({priority(node), luminance(node.intensity), index});
    std::push_heap(heap.begin(), heap.end());
  };
  add(0);
  while (!heap.empty() && cut.size() + heap.size() < size) {
    std::pop_heap(heap.begin(), heap.end());
    const uint32_t parent = heap.back().node;
    heap.pop_back();
    add(parent + 1);
    add(nodes[parent].secondChild);
  }
  for (const CutEntry& e : heap) cut.push_back(e.node);
  return cut;
}

}  // namespace

const VplSet& RepresentativeLights::select(const Camera& camera, const Settings& settings) {
  if (!tree_) return vpls_;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<LightTreeNode>& nodes = tree_->nodes();
  const std::vector<glm::vec3>& intensities = tree_->intensities();
  const float diagonal = std::max(offline_.scene().bounds.diagonal(), 1e-6f);
  const float bound = 1.0f / (kImportanceDistanceFraction * diagonal * kImportanceDistanceFraction * diagonal);
  const std::vector<ShadingPoint> points =
      importancePoints(offline_, camera, kRepresentativePoints, settings.width, settings.height);

  // A node's representative lighting p unshadowed, scaled to the node's power: the cut's estimate at p.
  auto nodeEstimate = [&](const ShadingPoint& sp, const LightTreeNode& node) {
    const float repPower = luminance(intensities[node.representative]);
    if (!(repPower > 0.0f)) return 0.0;
    const glm::vec3 c =
        vplUnoccludedContribution(sp, vpls_.vpls[node.representative], brdfs_[node.representative], bound);
    return static_cast<double>(luminance(c)) * luminance(node.intensity) / repPower;
  };
  // Step 1: E_p through the kRepresentativeSeedCut most powerful clusters; each point's bounds count relative to it.
  const std::vector<uint32_t> seedCut =
      refineCut(nodes, kRepresentativeSeedCut, [](const LightTreeNode&) { return 0.0; });
  std::vector<double> weights(points.size(), 0.0);
  double largest = 0.0;
  for (std::size_t p = 0; p < points.size(); ++p) {
    for (uint32_t n : seedCut) weights[p] += nodeEstimate(points[p], nodes[n]);
    largest = std::max(largest, weights[p]);
  }
  // Points the seed cut leaves dark weigh as a thousandth of the brightest does.
  for (double& w : weights) w = largest > 0.0 ? 1.0 / std::max(w, 1e-3 * largest) : 1.0;
  // Step 2: the cut of previewRepresentatives nodes by the summed relative bounds.
  std::vector<uint32_t> cut =
      refineCut(nodes, static_cast<std::size_t>(settings.previewRepresentatives), [&](const LightTreeNode& node) {
        double sum = 0.0;
        const float power = luminance(node.intensity);
        if (!(power > 0.0f)) return 0.0;
        for (std::size_t p = 0; p < points.size(); ++p) sum += lightcutBound(points[p], node, bound) * weights[p];
        return std::isfinite(sum) ? sum * power : 0.0;
      });
  // Clusters without power light nothing.
  cut.erase(std::remove_if(cut.begin(), cut.end(), [&](uint32_t n) { return !(luminance(nodes[n].intensity) > 0.0f); }),
            cut.end());

  // Step 3: each representative keeps its place from the last cut; the new ones take the places left free.
  std::unordered_map<uint32_t, std::size_t> lastPlace;
  for (std::size_t i = 0; i < cut_.size(); ++i) lastPlace[nodes[cut_[i]].representative] = i;
  constexpr uint32_t kFree = 0xffffffffu;
  std::vector<uint32_t> placed(cut.size(), kFree);
  std::vector<uint32_t> newcomers;
  for (uint32_t n : cut) {
    const auto it = lastPlace.find(nodes[n].representative);
    if (it != lastPlace.end() && it->second < placed.size())
      placed[it->second] = n;
    else
      newcomers.push_back(n);
  }
  std::size_t next = 0;
  for (uint32_t& slot : placed)
    if (slot == kFree) slot = newcomers[next++];

  stats_.points = points.size();
  stats_.moved = 0;
  for (std::size_t i = 0; i < placed.size(); ++i)
    stats_.moved += i >= cut_.size() || nodes[placed[i]].representative != nodes[cut_[i]].representative;
  if (placed != cut_ || reduced_.vpls.empty()) {
    cut_ = std::move(placed);
    reduced_ = VplSet{};
    reduced_.stats = vpls_.stats;
    reduced_.vpls.reserve(cut_.size());
    for (uint32_t n : cut_) {
      const LightTreeNode& node = nodes[n];
      Vpl vpl = vpls_.vpls[node.representative];
      vpl.flux *= luminance(node.intensity) / luminance(intensities[node.representative]);
      reduced_.vpls.push_back(vpl);
    }
  }
  stats_.representatives = reduced_.vpls.size();
  stats_.selectSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return reduced_;
}

}  // namespace vplab
