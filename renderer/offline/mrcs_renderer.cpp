#include "renderer/offline/mrcs_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>

#include "renderer/core/sampling.h"
#include "renderer/offline/lightcuts_renderer.h"
#include "renderer/offline/progressive.h"
#include "renderer/scene/brdf_params.h"
#include "renderer/vpl/vpl_contribution.h"

namespace vplab {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Step 1: the reduced columns, stored column by column: rho[j * rows + r] = luminance of A_{p_r, j}.
std::vector<float> sampleRows(const OfflineScene& offline, const VplSet& vplSet, const Settings& settings,
                              std::size_t rows, std::size_t& rowsHit) {
  const Scene& scene = offline.scene();
  const EmbreeScene& embree = offline.embree();
  const std::vector<Vpl>& vpls = vplSet.vpls;
  std::vector<BrdfParams> brdfs;
  brdfs.reserve(vpls.size());
  for (const Vpl& v : vpls) brdfs.push_back(brdfParamsAt(scene, v.material, v.uv));
  std::vector<float> rho(vpls.size() * rows, 0.0f);
  std::vector<uint8_t> hit(rows, 0);
  const int64_t pixels = static_cast<int64_t>(settings.width) * settings.height;
  parallelFor(static_cast<int64_t>(rows), resolveThreadCount(settings.threads), [&](int64_t r, int) {
    // The row's pixel: stratified over the raster order, jittered by a hash of the seed and the row.
    const double u = static_cast<double>(hashKey(settings.seed, 0x6d726373u, static_cast<uint64_t>(r)) >> 11) * 0x1p-53;
    const int64_t pixel = std::min<int64_t>(
        pixels - 1,
        static_cast<int64_t>((static_cast<double>(r) + u) * static_cast<double>(pixels) / static_cast<double>(rows)));
    const int x = static_cast<int>(pixel % settings.width), y = static_cast<int>(pixel / settings.width);
    const glm::vec3 dir = cameraRayDirection(scene.camera, x + 0.5f, y + 0.5f, settings.width, settings.height);
    const std::optional<SurfaceHit> h = embree.intersect(scene.camera.position, dir);
    if (!h) return;
    const Interaction x1 = Interaction::onSurface(scene, *h, -dir);
    if (!x1.scatters()) return;
    hit[static_cast<std::size_t>(r)] = 1;
    const ShadingPoint sp{x1.hit, x1.wo, x1.brdf};
    // Every VPL's term with an exact shadow ray (one ray at a time: rows x VPLs rays, a small part of the time).
    for (std::size_t j = 0; j < vpls.size(); ++j) {
      const float c = luminance(vplUnoccludedContribution(sp, vpls[j], brdfs[j], settings.clampBound));
      if (c > 0.0f &&
          embree.visible(sp.hit.position, sp.hit.geometricNormal, vpls[j].position, vpls[j].geometricNormal))
        rho[j * rows + static_cast<std::size_t>(r)] = c;
    }
  });
  rowsHit = static_cast<std::size_t>(std::count(hit.begin(), hit.end(), 1));
  return rho;
}

/// Step 2: top-down splitting of the non-zero columns into at most `clusters` clusters.
class ColumnClustering {
 public:
  ColumnClustering(const std::vector<float>& rho, std::size_t rows, const std::vector<uint32_t>& columns,
                   const std::vector<double>& norms, uint32_t seed)
      : rho_(rho), rows_(rows), norms_(norms), seed_(seed) {
    push(columns);
  }

  std::vector<std::vector<uint32_t>> run(std::size_t clusters) {
    while (clusters_.size() < clusters && !queue_.empty()) {
      const auto [cost, index] = queue_.top();
      if (!(cost > 0.0)) break;  // the rest are single columns or parallel ones: nothing to gain
      queue_.pop();
      std::vector<uint32_t> members = std::move(clusters_[index]);
      clusters_[index].clear();
      free_.push_back(index);
      split(members);
    }
    std::vector<std::vector<uint32_t>> out;
    for (auto& c : clusters_)
      if (!c.empty()) out.push_back(std::move(c));
    return out;
  }

 private:
  const float* column(uint32_t j) const { return rho_.data() + static_cast<std::size_t>(j) * rows_; }

  /// A cluster's sum of columns, its |sum|^2 and W = sum of the columns' norms.
  struct Sums {
    std::vector<double> sum;
    double sumSq = 0.0;
    double w = 0.0;
  };
  Sums sums(const std::vector<uint32_t>& members) const {
    Sums s;
    s.sum.assign(rows_, 0.0);
    for (uint32_t j : members) {
      const float* c = column(j);
      for (std::size_t r = 0; r < rows_; ++r) s.sum[r] += c[r];
      s.w += norms_[j];
    }
    for (double v : s.sum) s.sumSq += v * v;
    return s;
  }

  /// cost(C) = 2 (W^2 - |sum rho|^2) (the pairwise sum of the header, expanded with |rho_j / |rho_j|| = 1).
  double cost(const std::vector<uint32_t>& members) const {
    const Sums s = sums(members);
    return std::max(0.0, 2.0 * (s.w * s.w - s.sumSq));
  }

  void push(std::vector<uint32_t> members) {
    const double c = members.size() > 1 ? cost(members) : 0.0;
    std::size_t index;
    if (!free_.empty()) {
      index = free_.back();
      free_.pop_back();
      clusters_[index] = std::move(members);
    } else {
      index = clusters_.size();
      clusters_.push_back(std::move(members));
    }
    queue_.push({c, index});
  }

  void split(std::vector<uint32_t>& members) {
    // A random direction of R^R, from a hash of the seed and the split's number.
    Rng rng(hashKey(seed_, 0x73706c6974u, splits_++));
    std::vector<double> direction(rows_);
    for (double& d : direction) {
      // Box-Muller: a Gaussian per coordinate makes the direction uniform on the sphere.
      const float u1 = std::max(rng.next1D(), 1e-7f), u2 = rng.next1D();
      d = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * kPi * u2);
    }
    // Order the normalised columns along it.
    std::vector<std::pair<double, uint32_t>> order;
    order.reserve(members.size());
    for (uint32_t j : members) {
      const float* c = column(j);
      double p = 0.0;
      for (std::size_t r = 0; r < rows_; ++r) p += c[r] * direction[r];
      order.push_back({p / norms_[j], j});
    }
    std::sort(order.begin(), order.end());
    // The cut of least cost(left) + cost(right), with running sums: |s_L + rho|^2 = |s_L|^2 + 2 s_L.rho + |rho|^2.
    const Sums all = sums(members);
    const std::vector<double>& total = all.sum;
    const double wTotal = all.w, totalSq = all.sumSq;
    std::vector<double> left(rows_, 0.0);
    double leftSq = 0.0, leftDotTotal = 0.0, wLeft = 0.0, best = std::numeric_limits<double>::max();
    std::size_t bestCut = order.size() / 2;
    for (std::size_t i = 0; i + 1 < order.size(); ++i) {
      const float* c = column(order[i].second);
      double dotLeft = 0.0, dotTotal = 0.0, self = 0.0;
      for (std::size_t r = 0; r < rows_; ++r) {
        dotLeft += left[r] * c[r];
        dotTotal += total[r] * c[r];
        self += static_cast<double>(c[r]) * c[r];
        left[r] += c[r];
      }
      leftSq += 2.0 * dotLeft + self;
      leftDotTotal += dotTotal;
      wLeft += norms_[order[i].second];
      const double wRight = wTotal - wLeft;
      const double rightSq = totalSq - 2.0 * leftDotTotal + leftSq;
      const double c2 = (wLeft * wLeft - leftSq) + (wRight * wRight - rightSq);
      if (c2 < best) best = c2, bestCut = i + 1;
    }
    std::vector<uint32_t> a, b;
    for (std::size_t i = 0; i < order.size(); ++i) (i < bestCut ? a : b).push_back(order[i].second);
    push(std::move(a));
    push(std::move(b));
  }

  const std::vector<float>& rho_;
  std::size_t rows_;
  const std::vector<double>& norms_;
  uint32_t seed_;
  uint64_t splits_ = 0;
  std::vector<std::vector<uint32_t>> clusters_;
  std::vector<std::size_t> free_;
  std::priority_queue<std::pair<double, std::size_t>> queue_;
};

}  // namespace

MrcsReduction reduceVplsByRowColumnSampling(const OfflineScene& offline, const VplSet& vpls, const Settings& settings) {
  requireLightcutsApply(offline.scene(), settings, Method::Mrcs);
  MrcsReduction out;
  out.reduced.stats = vpls.stats;
  const std::size_t rows = static_cast<std::size_t>(std::max(1, settings.mrcsRows));
  // Step 1: the rows.
  auto start = Clock::now();
  const std::vector<float> rho = sampleRows(offline, vpls, settings, rows, out.rows);
  out.rowSeconds = secondsSince(start);
  // Step 2: the columns' norms; the dark ones are left out.
  start = Clock::now();
  std::vector<double> norms(vpls.vpls.size(), 0.0);
  std::vector<uint32_t> columns;
  for (std::size_t j = 0; j < vpls.vpls.size(); ++j) {
    double s = 0.0;
    for (std::size_t r = 0; r < rows; ++r) s += static_cast<double>(rho[j * rows + r]) * rho[j * rows + r];
    norms[j] = std::sqrt(s);
    if (norms[j] > 0.0) columns.push_back(static_cast<uint32_t>(j));
  }
  out.darkColumns = vpls.vpls.size() - columns.size();
  const std::size_t clusterCount = static_cast<std::size_t>(std::max(1, settings.mrcsClusters));
  std::vector<std::vector<uint32_t>> clusters;
  if (columns.size() <= clusterCount) {
    for (uint32_t j : columns) clusters.push_back({j});
  } else {
    ColumnClustering clustering(rho, rows, columns, norms, settings.seed);
    clusters = clustering.run(clusterCount);
  }
  // Step 3: a representative per cluster, drawn by |rho|, its flux scaled by W_C / |rho_r|.
  for (std::vector<uint32_t>& c : clusters) {
    std::sort(c.begin(), c.end());
    double w = 0.0;
    for (uint32_t j : c) w += norms[j];
    const double u = static_cast<double>(hashKey(settings.seed, 0x726570u, c.front()) >> 11) * 0x1p-53 * w;
    uint32_t pick = c.back();
    double acc = 0.0;
    for (uint32_t j : c) {
      acc += norms[j];
      if (u < acc) {
        pick = j;
        break;
      }
    }
    Vpl rep = vpls.vpls[pick];
    if (c.size() > 1) rep.flux *= static_cast<float>(w / norms[pick]);
    out.reduced.vpls.push_back(rep);
    out.representatives.push_back(pick);
  }
  out.clusterSeconds = secondsSince(start);
  return out;
}

MrcsRenderResult renderMrcs(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                            RenderControl* control, OnPass onPass) {
  MrcsRenderResult result;
  result.reduction = reduceVplsByRowColumnSampling(offline, vpls, settings);
  static_cast<VplRenderResult&>(result) =
      renderVpl(offline, result.reduction.reduced, Method::Vpl, settings, control, std::move(onPass));
  result.seconds += result.reduction.rowSeconds + result.reduction.clusterSeconds;
  return result;
}

}  // namespace vplab
