#pragma once
// What the generation methods share (internal to renderer/vpl): the random numbers of a light path, one light path
// traced into VPL candidates, and the three generate functions the method list points to.

#include "renderer/core/sampling.h"
#include "renderer/vpl/generation_methods.h"

#include <array>
#include <string>
#include <vector>

namespace vplab {

/// A light path's random numbers, one at a time. Light tracing draws them from a Halton point and a PCG stream,
/// the Metropolis chains from the primary-sample vector they mutate.
class RandomSource {
 public:
  virtual ~RandomSource() = default;
  virtual float next() = 0;
};

/// Halton dimensions: light choice (1), point on the light (2), direction (2), first BRDF sample (3).
inline constexpr int kHaltonDims = 8;

/// Stream tag of plain light tracing's paths (tag 0 keeps the streams light tracing has always had).
inline constexpr uint64_t kTagMainPaths = 0;

/// The seed of the streams tagged `tag`: the seed itself for kTagMainPaths, a hash of both otherwise.
uint64_t streamSeed(uint32_t seed, uint64_t tag);

/// The Cranley-Patterson rotation of the Halton points for `seed` and a stream tag (main paths, pilot, ...).
std::array<float, kHaltonDims> haltonOffsets(uint32_t seed, uint64_t tag);

/// Halton point `index` (rotated by `offsets`) for the first kHaltonDims numbers, then a PCG stream keyed by
/// `streamKey`: stratified and coherent under small scene changes (a path keeps its numbers).
class HaltonPathSampler : public RandomSource {
 public:
  HaltonPathSampler(uint64_t index, const std::array<float, kHaltonDims>& offsets, uint64_t streamKey)
      : index_(index), offsets_(offsets), rng_(streamKey) {}
  float next() override;

 private:
  uint64_t index_;
  const std::array<float, kHaltonDims>& offsets_;
  Rng rng_;
  int dim_ = 0;
};

/// The start of a light path: light, point and direction from the first five numbers of `random`. The one place
/// that turns random numbers into emission, for every generation method.
EmissionSample sampleLightEmission(const LightSampler& lights, RandomSource& random);

/// One light path (docs/methods.md, "Light tracing"): a VPL candidate at every surface bounce 1..maxBounces, flux =
/// the raw path throughput alpha (not yet divided by the path count). emissionAreaPdf, when given, receives one
/// value per candidate: for bounce 1 the area density at the candidate with which the emission, given its point on
/// the light, lands there (pdf_dir cos / d^2; 0 for a delta direction), 0 for later bounces.
/// In a scene with media the path samples free flights: a medium VPL at every scattering event, surface VPLs
/// weighted by the free flight's transmittance, and (when vrls is given) every segment's media parts as virtual ray
/// lights with the raw throughput at the segment's start (docs/theory.md §17, §19).
void traceLightPath(const Scene& scene, const EmbreeScene& embree, const LightSampler& lights, int maxBounces,
                    RandomSource& random, std::vector<Vpl>& out, std::vector<float>* emissionAreaPdf = nullptr,
                    std::vector<Vrl>* vrls = nullptr);

/// `paths` light paths (Halton rotated by the seed and `tag`, then PCG), in parallel, candidates in path order.
/// pathCandidateCount, when given, receives each path's candidate count; emissionAreaPdf as traceLightPath's.
std::vector<Vpl> traceLightPaths(const GenerationContext& ctx, int64_t paths, uint64_t tag,
                                 std::vector<uint32_t>* pathCandidateCount = nullptr,
                                 std::vector<float>* emissionAreaPdf = nullptr, std::vector<Vrl>* vrls = nullptr);

/// Mean VPL candidates per light path, from kVplPilotPaths paths of a stream of their own.
double candidatesPerLightPath(const GenerationContext& ctx);

/// Russian roulette on a candidate: kept with probability p (when u < p) with its flux divided by p, otherwise
/// listed among the rejected (for display). Unbiased for every p > 0.
inline void keepWithProbability(Vpl v, double p, float u, VplSet& set) {
  if (p > 0.0 && u < p) {
    v.flux /= static_cast<float>(p);
    set.vpls.push_back(v);
  } else {
    set.rejected.push_back(v);
  }
}

VplSet generateLightTraced(const GenerationContext& ctx);
VplSet generateBidirectional(const GenerationContext& ctx);
/// Bidirectional resampling's inclusion probabilities: pi_i = min(1, c w_i) with sum pi_i = n (or every pi_i = 1 for
/// w_i > 0 when fewer than n are positive).
std::vector<double> inclusionProbabilities(const std::vector<double>& w, std::size_t n);
VplSet generateMetropolis(const GenerationContext& ctx);

/// Plain light tracing (no rejection) with `reason` as a warning: what an importance-driven method does when no
/// importance point sees anything.
VplSet fallBackToLightTracing(const GenerationContext& ctx, const std::string& reason);

}  // namespace vplab
