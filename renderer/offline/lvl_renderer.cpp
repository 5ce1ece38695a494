#include "renderer/offline/lvl_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "renderer/core/sampling.h"
#include "renderer/offline/camera_sample.h"
#include "renderer/offline/direct_light.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/vpl/vpl_contribution.h"
#include "renderer/vpl/vsl_integral.h"

namespace vplab {

namespace {

/// Shading normals closer than about 25 degrees to a group's first pixel join the group.
constexpr float kGroupNormalCos = 0.9f;
/// VPL samples a glossy local light keeps for the pixels other than the one it was evaluated toward.
constexpr int kGlossyIncidentSamples = 16;
/// Shadow rays per occludedBatch call (as the VPL renderer's batches).
constexpr std::size_t kShadowBatch = 64;
/// Keys the tiles' streams apart from the pixels' (hashKey(seed, pixel, sample)).
constexpr uint64_t kTileStream = 0x6c766c74696c65ull;

/// A pixel of the tile whose camera ray found a surface that scatters.
struct TilePixel {
  std::size_t local = 0;  ///< row-major index in the tile
  Interaction x;
  int group = -1;
};

/// The exchange between one pixel x_m and one local light y.
struct Pair {
  float areaPdf = 0.0f;     ///< p_brdf(x_m -> y) |cos theta_y| / d^2 (0 when x_m cannot draw y)
  glm::vec3 weight{0.0f};   ///< f(x_m) cos_x (1 - b/G)+ |cos theta_y| / d^2: times L_r / p_G gives the estimate
  glm::vec3 toPixel{0.0f};  ///< unit, from y toward x_m
  bool visible = false;
  bool residual() const { return visible && (weight.r > 0.0f || weight.g > 0.0f || weight.b > 0.0f); }
};

struct LocalLight {
  std::size_t pixel = 0;  ///< index in the group of the pixel that drew it
  Interaction::Sample sample;
  std::optional<Interaction> y;  ///< the first hit, when it scatters toward the drawing pixel
  std::vector<Pair> pairs;       ///< one per pixel of the group
  float mixturePdf = 0.0f;       ///< p_G(y)
};

/// L_r(y -> x) for the pixels of a group: the evaluated estimate and, for a glossy y, its incident samples.
struct LocalRadiance {
  std::size_t evaluatedFor = 0;  ///< group index of the pixel `toEvaluated` was computed toward
  glm::vec3 toEvaluated{0.0f};
  bool directional = false;  ///< glossy y with other pixels to serve: re-evaluate `incident` toward them
  std::vector<IncidentSample> incident;
  /// sum f(y; wo, wi) weight over the kept samples.
  glm::vec3 toward(const Interaction& y, const glm::vec3& wo) const {
    glm::vec3 sum(0.0f);
    for (const IncidentSample& s : incident) sum += evaluateBrdf(y.brdf, y.hit.shadingNormal, wo, s.wi) * s.weight;
    return sum;
  }
};

class LvlTile {
 public:
  LvlTile(const OfflineScene& offline, const VplTransport& transport, const Settings& settings)
      : scene_(offline.scene()),
        embree_(offline.embree()),
        lights_(offline.lights()),
        transport_(transport),
        settings_(settings),
        bound_(settings.clampBound),
        residual_(std::isfinite(settings.clampBound) && settings.components != Components::Direct) {}

  /// One camera sample for every pixel of the tile (see lvl_renderer.h).
  void render(const PixelTile& tile, uint32_t sampleIndex, Rng* rngs, glm::vec3* out, GatherTally* tallies) {
    // Step 1: each pixel's camera sample with the global (bounded) VPLs, keeping its surface point.
    pixels_.clear();
    for (int py = tile.y0; py < tile.y1; ++py)
      for (int px = tile.x0; px < tile.x1; ++px) {
        const std::size_t i = tile.local(px, py);
        GatherTally& tally = tallies[i];
        out[i] = manyLightCameraSample(
            embree_, lights_, settings_, px, py, rngs[i],
            [](const glm::vec3&, const std::vector<MediumInterval>&, float) { return glm::vec3(0.0f); },
            [&](const Interaction& sp) {
              pixels_.push_back({i, sp, -1});
              return transport_.gather(sp, rngs[i], tally, true);
            });
      }
    if (!residual_ || pixels_.empty()) return;

    // Step 2: groups of pixels with one material and similar normals, in row-major order.
    std::vector<std::vector<std::size_t>> groups;
    for (std::size_t p = 0; p < pixels_.size(); ++p) {
      TilePixel& px = pixels_[p];
      for (std::size_t g = 0; g < groups.size() && px.group < 0; ++g) {
        const Interaction& first = pixels_[groups[g].front()].x;
        if (first.hit.material == px.x.hit.material &&
            glm::dot(first.hit.shadingNormal, px.x.hit.shadingNormal) >= kGroupNormalCos)
          px.group = static_cast<int>(g);
      }
      if (px.group < 0) {
        px.group = static_cast<int>(groups.size());
        groups.emplace_back();
      }
      groups[px.group].push_back(p);
    }

    // Steps 3-5 per group, each with its share of the tile's local lights.
    Rng tileRng(hashKey(hashKey(settings_.seed, kTileStream), tile.index, sampleIndex));
    const int lightsPerTile = std::max(1, settings_.lvlLightsPerTile);
    for (const std::vector<std::size_t>& group : groups) {
      const long share = std::lround(static_cast<double>(lightsPerTile) * group.size() / pixels_.size());
      renderGroup(group, static_cast<int>(std::max(1L, share)), tileRng, rngs, out, tallies);
    }
  }

 private:
  void renderGroup(const std::vector<std::size_t>& group, int lightCount, Rng& tileRng, Rng* rngs, glm::vec3* out,
                   GatherTally* tallies) {
    const std::size_t m = group.size();
    // Step 3: local lights, each drawn from one pixel's BRDF (stratified over the group), traced to its first hit.
    lights_k_.assign(static_cast<std::size_t>(lightCount), LocalLight{});
    for (int k = 0; k < lightCount; ++k) {
      LocalLight& light = lights_k_[k];
      if (m > 1) {
        const float u = tileRng.next1D();
        light.pixel = std::min(m - 1, static_cast<std::size_t>((static_cast<float>(k) + u) * m / lightCount));
      }
      const TilePixel& from = pixels_[group[light.pixel]];
      Rng& rng = rngs[from.local];
      light.sample = from.x.sample(rng);
      if (!light.sample.valid()) continue;
      const glm::vec3 origin = from.x.rayOrigin(embree_, light.sample.wi);
      Segment next = embree_.traceSegment(origin, light.sample.wi, kInfinity, [&rng]() { return rng.next2D(); });
      if (next.end == Segment::End::Escape) continue;
      Interaction y = Interaction::atSegmentEnd(scene_, next, -light.sample.wi);
      // Points seen from their back reflect nothing toward the drawing pixel (as in Kollig-Keller); the density of
      // such a y still counts in the mixture below.
      light.y = y;
    }

    // Step 4: every pixel against every local light: the pdf of drawing it, the residual weight, a shadow ray.
    for (LocalLight& light : lights_k_) pairsFor(light, group);
    traceShadowRays(group, tallies);
    for (LocalLight& light : lights_k_) {
      float sum = 0.0f;
      for (const Pair& p : light.pairs) sum += p.visible ? p.areaPdf : 0.0f;
      light.mixturePdf = sum / static_cast<float>(m);
    }

    // Step 5: L_r at each light some pixel needs, then the estimate at every pixel.
    const float invLights = 1.0f / static_cast<float>(lightCount);
    for (LocalLight& light : lights_k_) {
      if (!light.y || !(light.mixturePdf > 0.0f)) continue;
      std::optional<std::size_t> evaluate;
      std::size_t needing = 0;
      for (std::size_t p = 0; p < m; ++p)
        if (light.pairs[p].residual()) {
          ++needing;
          if (!evaluate || p == light.pixel) evaluate = p;
        }
      if (!evaluate) continue;
      GatherTally& tally = tallies[pixels_[group[light.pixel]].local];
      Rng& rng = rngs[pixels_[group[light.pixel]].local];
      const LocalRadiance radiance = localRadiance(light, *evaluate, needing > 1, rng, tally);
      for (std::size_t p = 0; p < m; ++p) {
        const Pair& pair = light.pairs[p];
        if (!pair.residual()) continue;
        glm::vec3 l = p == radiance.evaluatedFor || !radiance.directional ? radiance.toEvaluated
                                                                          : radiance.toward(*light.y, pair.toPixel);
        out[pixels_[group[p]].local] += pair.weight * l * (invLights / light.mixturePdf);
      }
    }
  }

  /// Pair terms of one light against every pixel of the group (visibility still to trace, except the drawing pixel's,
  /// for which y is the first hit).
  void pairsFor(LocalLight& light, const std::vector<std::size_t>& group) {
    light.pairs.assign(group.size(), Pair{});
    // An invalid sample or an escaped ray leaves no point (and no density): nothing to pair.
    if (!light.y) return;
    const Interaction& y = *light.y;
    for (std::size_t p = 0; p < group.size(); ++p) {
      const Interaction& x = pixels_[group[p]].x;
      Pair& pair = light.pairs[p];
      const bool drawing = p == light.pixel;
      const glm::vec3 d = y.position - x.position;
      const float dist2 = glm::dot(d, d);
      if (!(dist2 > 0.0f)) continue;
      const glm::vec3 w = drawing ? light.sample.wi : d * (1.0f / std::sqrt(dist2));
      const float areaFactor = std::abs(glm::dot(y.hit.geometricNormal, w)) / dist2;
      // The density with which x draws y: its BRDF sample along w (zero where Interaction::sample refuses).
      const float cosX = glm::dot(x.hit.shadingNormal, w);
      const bool drawable = x.accepts(w) && cosX > 0.0f;
      const float pdf = drawing ? light.sample.pdf : (drawable ? x.pdf(w) : 0.0f);
      pair.areaPdf = pdf * areaFactor;
      pair.toPixel = -w;
      pair.visible = drawing;
      // The residual (1 - b/G)+ with G from the shading normals, as the bound's G_b (docs/theory.md §4, §5); y must
      // reflect toward x (one-sided surfaces).
      if (!drawable || glm::dot(y.hit.geometricNormal, w) >= 0.0f) continue;
      const float cosY = std::max(0.0f, -glm::dot(y.hit.shadingNormal, w));
      const float g = cosX * cosY / dist2;
      if (!(g > bound_)) continue;
      const glm::vec3 f = drawing ? light.sample.f : evaluateBrdf(x.brdf, x.hit.shadingNormal, x.wo, w);
      pair.weight = f * ((1.0f - bound_ / g) * cosX * areaFactor);
    }
  }

  /// V(x_m, y_k) for every pair that matters (a density or a residual) of the lights some pixel could take a residual
  /// from, batched.
  void traceShadowRays(const std::vector<std::size_t>& group, GatherTally* tallies) {
    std::array<ShadowRay, kShadowBatch> rays;
    std::array<Pair*, kShadowBatch> targets;
    std::array<uint8_t, kShadowBatch> blocked;
    std::size_t n = 0;
    auto flush = [&]() {
      embree_.occludedBatch(rays.data(), blocked.data(), n);
      for (std::size_t i = 0; i < n; ++i) targets[i]->visible = !blocked[i];
      n = 0;
    };
    for (LocalLight& light : lights_k_) {
      // A light no pixel of the group could take a residual from contributes nothing, whatever its density.
      const bool anyResidual = std::any_of(light.pairs.begin(), light.pairs.end(), [](const Pair& p) {
        return p.weight.r > 0.0f || p.weight.g > 0.0f || p.weight.b > 0.0f;
      });
      if (!light.y || !anyResidual) continue;
      for (std::size_t p = 0; p < group.size(); ++p) {
        Pair& pair = light.pairs[p];
        if (p == light.pixel ||
            !(pair.areaPdf > 0.0f || pair.weight.r > 0.0f || pair.weight.g > 0.0f || pair.weight.b > 0.0f))
          continue;
        const TilePixel& px = pixels_[group[p]];
        rays[n] = embree_.shadowRayBetween(px.x.position, px.x.hit.geometricNormal, light.y->position,
                                           light.y->hit.geometricNormal);
        targets[n] = &pair;
        ++tallies[px.local].shadowRays;
        if (++n == kShadowBatch) flush();
      }
    }
    if (n > 0) flush();
  }

  /// L_r(y -> x) toward the group's pixel `evaluate`; with `shared` and a glossy y, also its incident samples for
  /// the other pixels (see lvl_renderer.h).
  LocalRadiance localRadiance(const LocalLight& light, std::size_t evaluate, bool shared, Rng& rng,
                              GatherTally& tally) {
    LocalRadiance r;
    r.evaluatedFor = evaluate;
    Interaction y = *light.y;
    if (evaluate != light.pixel) y.wo = light.pairs[evaluate].toPixel;
    const bool recurse = transport_.maxDepth() > 1;
    GatherTally inner;
    if (!shared || isPureLambert(y.brdf)) {
      // Kollig-Keller's L(y -> x) without Le(y): direct light + bounded gather + the compensation at y.
      r.toEvaluated = estimateDirectLight(embree_, lights_, y, rng);
      r.toEvaluated += transport_.gather(y, rng, inner, false);
      if (recurse) r.toEvaluated += transport_.compensation(y, rng, 1, tally);
    } else {
      r.directional = true;
      std::array<IncidentSample, 2> direct;
      r.toEvaluated = estimateDirectLight(embree_, lights_, y.hit, y.wo, y.brdf, rng, &direct);
      r.incident.assign(direct.begin(), direct.end());
      r.toEvaluated += gatherIncident(y, rng, inner, r.incident);
      if (recurse) {
        IncidentSample deeper;
        r.toEvaluated += transport_.compensation(y, rng, 1, tally, &deeper);
        r.incident.push_back(deeper);
      }
    }
    tally.shadowRays += inner.shadowRays;
    tally.evaluations += inner.evaluations;
    return r;
  }

  /// The bounded VPL gather at a glossy y toward y.wo, keeping the VPLs' incident samples: all of them for y.wo,
  /// kGlossyIncidentSamples of them resampled (systematically, in proportion to their weight's channel sum) in
  /// `kept` for the other pixels.
  glm::vec3 gatherIncident(const Interaction& y, Rng& rng, GatherTally& tally, std::vector<IncidentSample>& kept) {
    const std::vector<Vpl>& vpls = transport_.vpls();
    const std::vector<BrdfParams>& vplBrdfs = transport_.vplBrdfs();
    visible_.clear();
    std::array<ShadowRay, kShadowBatch> rays;
    std::array<IncidentSample, kShadowBatch> pending;
    std::array<uint8_t, kShadowBatch> blocked;
    std::size_t n = 0;
    auto flush = [&]() {
      embree_.occludedBatch(rays.data(), blocked.data(), n);
      tally.shadowRays += n;
      for (std::size_t i = 0; i < n; ++i)
        if (!blocked[i]) visible_.push_back(pending[i]);
      n = 0;
    };
    for (std::size_t i = 0; i < vpls.size(); ++i) {
      ++tally.evaluations;
      if (!vplIncident(y.hit, vpls[i], vplBrdfs[i], bound_, pending[n])) continue;
      rays[n] = embree_.shadowRayBetween(y.position, y.hit.geometricNormal, vpls[i].position, vpls[i].geometricNormal);
      if (++n == kShadowBatch) flush();
    }
    if (n > 0) flush();
    glm::vec3 toWo(0.0f);
    double total = 0.0;
    for (const IncidentSample& s : visible_) {
      toWo += evaluateBrdf(y.brdf, y.hit.shadingNormal, y.wo, s.wi) * s.weight;
      total += static_cast<double>(s.weight.r) + s.weight.g + s.weight.b;
    }
    if (visible_.size() <= static_cast<std::size_t>(kGlossyIncidentSamples)) {
      kept.insert(kept.end(), visible_.begin(), visible_.end());
      return toWo;
    }
    // Systematic resampling: sample j picks the VPL whose cumulative share holds (j + u) / S; a VPL's expected count
    // is S times its share, so weight * total / (S * share) keeps the sum unbiased.
    const double step = total / kGlossyIncidentSamples;
    double target = rng.next1D() * step, cumulative = 0.0;
    std::size_t i = 0;
    for (int j = 0; j < kGlossyIncidentSamples; ++j, target += step) {
      for (;;) {
        const IncidentSample& s = visible_[i];
        const double share = static_cast<double>(s.weight.r) + s.weight.g + s.weight.b;
        if (cumulative + share > target || i + 1 == visible_.size()) break;
        cumulative += share;
        ++i;
      }
      const IncidentSample& s = visible_[i];
      const double share = static_cast<double>(s.weight.r) + s.weight.g + s.weight.b;
      kept.push_back({s.wi, s.weight * static_cast<float>(step / share)});
    }
    return toWo;
  }

  const Scene& scene_;
  const EmbreeScene& embree_;
  const LightSampler& lights_;
  const VplTransport& transport_;
  const Settings& settings_;
  const float bound_;
  const bool residual_;
  // Scratch, reused from tile to tile by the thread that owns this LvlTile.
  std::vector<TilePixel> pixels_;
  std::vector<LocalLight> lights_k_;
  std::vector<IncidentSample> visible_;
};

}  // namespace

VplRenderResult renderLvl(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                          RenderControl* control, std::function<void(const Image& mean, int samplesSoFar)> onPass) {
  if (offline.scene().hasMedia())
    throw SceneError("lvl renders surfaces only and this scene has participating media (use vpl-kk or vpl-abc)");
  // The global part and the compensation at local lights are the VPL renderer's (G_b gather, Kollig-Keller).
  const VplTransport transport(offline, vpls, Method::VplKK, settings);
  const std::size_t pixelCount =
      static_cast<std::size_t>(std::max(0, settings.width)) * static_cast<std::size_t>(std::max(0, settings.height));
  // Per-pixel tallies: a tile's pixels are only touched by the thread rendering that tile.
  std::vector<GatherTally> tallies(pixelCount);
  ProgressiveOptions options = progressiveOptions(settings, 1, std::move(onPass));
  TileEstimator estimator = [&](const PixelTile& tile, uint32_t sampleIndex, Rng* rngs, glm::vec3* out) {
    thread_local std::vector<GatherTally> tileTallies;
    tileTallies.assign(tile.pixelCount(), GatherTally{});
    LvlTile(offline, transport, settings).render(tile, sampleIndex, rngs, out, tileTallies.data());
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) {
        tallies[static_cast<std::size_t>(y) * settings.width + x].add(tileTallies[tile.local(x, y)]);
      }
  };
  VplRenderResult result;
  static_cast<ProgressiveResult&>(result) =
      renderProgressiveTiles(options, std::max(1, settings.lvlTileSize), estimator, control);
  addTallies(tallies, result);
  return result;
}

}  // namespace vplab
