#include "renderer/offline/light_tree.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <stdexcept>

#include "renderer/core/sampling.h"

namespace vplab {

glm::vec3 vplBrdfMax(const BrdfParams& brdf, const glm::vec3& normal, const glm::vec3& incoming) {
  const float cosIn = glm::dot(normal, incoming);
  // Both cosines are clamped at zero (brdf.h): light that arrived from below reflects nothing.
  if (!(cosIn > 0.0f)) return glm::vec3(0.0f);
  if (brdf.metallic == 0.0f && brdf.specular == 0.0f) return brdf.baseColor * kInvPi;
  // Diffuse lobe: the two Fresnel transmissions are at most 1.
  const glm::vec3 diffuse = (1.0f - brdf.metallic) * brdf.baseColor * kInvPi;
  // Specular lobe: D <= 1 / (pi alpha^2) (D's peak at n.h = 1 for alpha <= 1); the height-correlated Smith term
  // V = 0.5 / (cos_out sqrt(cos_in^2 (1 - a^2) + a^2) + cos_in sqrt(cos_out^2 (1 - a^2) + a^2)) <= 0.5 / (cos_in a);
  // both Fresnel factors are at most 1.
  const float alpha = brdf.alpha();
  const float dMax = alpha < 1.0f ? 1.0f / (kPi * alpha * alpha) : brdf_detail::ggxD(0.0f, alpha);
  const float fresnelMax = std::max(0.0f, (1.0f - brdf.metallic) * brdf.specular) + brdf.metallic;
  return diffuse + glm::vec3(dMax * fresnelMax * 0.5f / (cosIn * alpha));
}

namespace {

/// Orientation cone: unit axis and half-angle in radians (pi = every direction).
struct Cone {
  glm::vec3 axis{0.0f, 0.0f, 1.0f};
  float angle = 0.0f;
};

/// The smallest cone (of this construction) holding both cones: the union of pbrt-v4's DirectionCone, written from
/// its description (Pharr et al., "Physically Based Rendering" 4th ed., §3.8.4).
Cone coneUnion(const Cone& a, const Cone& b) {
  if (a.angle >= kPi || b.angle >= kPi) return {a.axis, kPi};
  const float between = std::acos(std::clamp(glm::dot(a.axis, b.axis), -1.0f, 1.0f));
  if (std::min(between + b.angle, kPi) <= a.angle) return a;
  if (std::min(between + a.angle, kPi) <= b.angle) return b;
  // Half of the angle spanned from a's far edge to b's far edge.
  const float angle = 0.5f * (a.angle + between + b.angle);
  if (angle >= kPi) return {a.axis, kPi};
  // Rotate a's axis toward b's by angle - a.angle.
  const glm::vec3 ortho = b.axis - a.axis * glm::dot(a.axis, b.axis);
  const float orthoLength = glm::length(ortho);
  if (!(orthoLength > 1e-7f)) return {a.axis, kPi};
  const float turn = angle - a.angle;
  const glm::vec3 axis = glm::normalize(a.axis * std::cos(turn) + ortho * (std::sin(turn) / orthoLength));
  // The float rotation may land a hair off: widen by a small margin so both cones stay inside.
  return {axis, std::min(kPi, angle + 1e-5f)};
}

/// What the build reads of each VPL, packed for the passes over it.
struct BuildItem {
  glm::vec3 position;
  glm::vec3 normal;
  float weight;  ///< luminance of the intensity
};

constexpr int kBins = 16;
/// Tree depth from which nodes split at the median instead of the binned cost (a balanced tree of 2^31 VPLs is 31
/// deep).
constexpr int kBinnedDepth = 48;

struct Bin {
  glm::vec3 pMin{std::numeric_limits<float>::max()}, pMax{-std::numeric_limits<float>::max()};
  glm::vec3 nMin{std::numeric_limits<float>::max()}, nMax{-std::numeric_limits<float>::max()};
  double weight = 0.0;
  uint32_t count = 0;
  void add(const BuildItem& it) {
    pMin = glm::min(pMin, it.position), pMax = glm::max(pMax, it.position);
    nMin = glm::min(nMin, it.normal), nMax = glm::max(nMax, it.normal);
    weight += it.weight;
    ++count;
  }
  void add(const Bin& o) {
    if (o.count == 0) return;
    pMin = glm::min(pMin, o.pMin), pMax = glm::max(pMax, o.pMax);
    nMin = glm::min(nMin, o.nMin), nMax = glm::max(nMax, o.nMax);
    weight += o.weight;
    count += o.count;
  }
  /// I * (box diagonal^2 + scale^2 normal-box diagonal^2): Walter et al.'s cluster size metric with the box of the
  /// normals for the cone.
  double cost(float normalScale) const {
    if (count == 0) return 0.0;
    const glm::vec3 dp = pMax - pMin, dn = (nMax - nMin) * normalScale;
    // A tiny floor keeps clusters of zero intensity from being free, so they still split by size.
    return (weight + 1e-30) * (glm::dot(dp, dp) + glm::dot(dn, dn));
  }
};

class Builder {
 public:
  Builder(const std::vector<Vpl>& vpls, const std::vector<glm::vec3>& intensities, uint32_t seed,
          std::vector<LightTreeNode>& nodes)
      : vpls_(vpls), intensities_(intensities), seed_(seed), nodes_(nodes) {
    items_.resize(vpls.size());
    order_.resize(vpls.size());
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::size_t i = 0; i < vpls.size(); ++i) {
      items_[i] = {vpls[i].position, vpls[i].normal, luminance(intensities[i])};
      order_[i] = static_cast<uint32_t>(i);
      lo = glm::min(lo, vpls[i].position), hi = glm::max(hi, vpls[i].position);
    }
    normalScale_ = vpls.empty() ? 1.0f : 0.5f * glm::length(hi - lo);
  }

  /// Builds the subtree over order_[begin, end) into nodes_[node ...] at tree depth `depth`, the top `parallelDepth`
  /// levels' first children on threads of their own.
  void build(uint32_t begin, uint32_t end, uint32_t node, int parallelDepth, int depth = 0) {
    const uint32_t count = end - begin;
    if (count == 1) {
      makeLeaf(node, order_[begin]);
      return;
    }
    // Below kBinnedDepth levels the median halves the range: the binned split may peel a few far VPLs off at a time,
    // and the median keeps the depth (and so the build) O(log N) whatever the positions.
    const uint32_t mid = split(begin, end, depth >= kBinnedDepth);
    const uint32_t first = node + 1;
    const uint32_t second = node + 2 * (mid - begin);  // the first subtree holds 2 n - 1 nodes
    if (parallelDepth > 0 && count > (1u << 14)) {
      auto left = std::async(std::launch::async, [&] { build(begin, mid, first, parallelDepth - 1, depth + 1); });
      build(mid, end, second, parallelDepth - 1, depth + 1);
      left.get();
    } else {
      build(begin, mid, first, 0, depth + 1);
      build(mid, end, second, 0, depth + 1);
    }
    merge(node, first, second, begin);
  }

 private:
  void makeLeaf(uint32_t node, uint32_t vpl) {
    LightTreeNode& n = nodes_[node];
    n.boundsMin = n.boundsMax = vpls_[vpl].position;
    n.coneAxis = vpls_[vpl].normal;
    n.coneCos = 1.0f;
    n.intensity = intensities_[vpl];
    n.representative = vpl;
    n.secondChild = 0;
    n.count = 1;
  }

  void merge(uint32_t node, uint32_t first, uint32_t second, uint32_t begin) {
    const LightTreeNode& a = nodes_[first];
    const LightTreeNode& b = nodes_[second];
    LightTreeNode& n = nodes_[node];
    n.boundsMin = glm::min(a.boundsMin, b.boundsMin);
    n.boundsMax = glm::max(a.boundsMax, b.boundsMax);
    const Cone cone = coneUnion({a.coneAxis, std::acos(std::clamp(a.coneCos, -1.0f, 1.0f))},
                                {b.coneAxis, std::acos(std::clamp(b.coneCos, -1.0f, 1.0f))});
    n.coneAxis = cone.axis;
    n.coneCos = cone.angle >= kPi ? -1.0f : std::cos(cone.angle);
    n.intensity = a.intensity + b.intensity;
    // Representative: a child's, with probability proportional to the children's intensity (luminance); the random
    // number is a hash of the seed and the node's first VPL slot and size, so the tree is the same at any thread
    // count.
    const float wa = luminance(a.intensity), wb = luminance(b.intensity);
    const float u = static_cast<float>(hashKey(seed_, begin, a.count + b.count) >> 40) * 0x1p-24f;
    n.representative = (wa + wb > 0.0f && u * (wa + wb) >= wa) ? b.representative : a.representative;
    n.secondChild = second;
    n.count = a.count + b.count;
  }

  /// Partitions order_[begin, end) in two non-empty parts (halves at the median when `median`); returns where the
  /// second starts.
  uint32_t split(uint32_t begin, uint32_t end, bool median) {
    // Step 1: the extents of the positions and (scaled) normals; the widest of the six dimensions is split.
    Bin all;
    for (uint32_t i = begin; i < end; ++i) all.add(items_[order_[i]]);
    std::array<float, 6> extent{};
    for (int k = 0; k < 3; ++k) {
      extent[k] = all.pMax[k] - all.pMin[k];
      extent[k + 3] = normalScale_ * (all.nMax[k] - all.nMin[k]);
    }
    const int dim = static_cast<int>(std::max_element(extent.begin(), extent.end()) - extent.begin());
    const float lo = dim < 3 ? all.pMin[dim] : all.nMin[dim - 3];
    const float width = dim < 3 ? extent[dim] : all.nMax[dim - 3] - all.nMin[dim - 3];
    const uint32_t mid = begin + (end - begin) / 2;
    auto key = [&](uint32_t v) { return dim < 3 ? items_[v].position[dim] : items_[v].normal[dim - 3]; };
    if (!(width > 0.0f)) return mid;  // every VPL at one place facing one way: any halving will do
    auto halve = [&] {
      std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                       [&](uint32_t a, uint32_t b) { return key(a) < key(b) || (key(a) == key(b) && a < b); });
      return mid;
    };
    if (median) return halve();
    // Step 2: bin along it and take the split of least cost.
    auto binOf = [&](uint32_t v) { return std::clamp(static_cast<int>(kBins * (key(v) - lo) / width), 0, kBins - 1); };
    std::array<Bin, kBins> bins;
    for (uint32_t i = begin; i < end; ++i) bins[binOf(order_[i])].add(items_[order_[i]]);
    std::array<double, kBins> leftCost{};
    Bin acc;
    for (int k = 0; k < kBins - 1; ++k) {
      acc.add(bins[k]);
      leftCost[k] = acc.count > 0 ? acc.cost(normalScale_) : -1.0;
    }
    acc = Bin{};
    double best = std::numeric_limits<double>::max();
    int bestSplit = -1;
    for (int k = kBins - 1; k >= 1; --k) {
      acc.add(bins[k]);
      const uint32_t leftCount = (end - begin) - acc.count;
      if (leftCount == 0 || acc.count == 0) continue;
      const double c = leftCost[k - 1] + acc.cost(normalScale_);
      if (c < best) best = c, bestSplit = k;
    }
    // Step 3: partition; if every VPL fell in one bin (a few far outliers), halve at the median instead.
    if (bestSplit > 0) {
      uint32_t* at =
          std::partition(order_.data() + begin, order_.data() + end, [&](uint32_t v) { return binOf(v) < bestSplit; });
      const uint32_t m = static_cast<uint32_t>(at - order_.data());
      if (m > begin && m < end) return m;
    }
    return halve();
  }

  const std::vector<Vpl>& vpls_;
  const std::vector<glm::vec3>& intensities_;
  uint32_t seed_;
  std::vector<LightTreeNode>& nodes_;
  std::vector<BuildItem> items_;
  std::vector<uint32_t> order_;
  float normalScale_ = 1.0f;
};

}  // namespace

LightTree::LightTree(const std::vector<Vpl>& vpls, const std::vector<BrdfParams>& brdfs, uint32_t seed, int threads) {
  const auto start = std::chrono::steady_clock::now();
  if (vpls.size() >= (1u << 31)) throw std::invalid_argument("lightcuts: more than 2^31 VPLs");
  intensities_.resize(vpls.size());
  for (std::size_t i = 0; i < vpls.size(); ++i) {
    if (vpls[i].inMedium)
      throw std::invalid_argument(
          "lightcuts bounds surface VPLs only: a medium VPL has no orientation cone (use vpl, vpl-kk or vpl-abc)");
    intensities_[i] = vpls[i].flux * vplBrdfMax(brdfs[i], vpls[i].normal, vpls[i].incoming);
  }
  if (!vpls.empty()) {
    nodes_.resize(2 * vpls.size() - 1);
    Builder builder(vpls, intensities_, seed, nodes_);
    int parallelDepth = 0;
    while ((2 << parallelDepth) <= std::max(1, threads) && parallelDepth < 8) ++parallelDepth;
    builder.build(0, static_cast<uint32_t>(vpls.size()), 0, parallelDepth);
  }
  buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace vplab
