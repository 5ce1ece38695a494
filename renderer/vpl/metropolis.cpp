// Metropolis instant radiosity (Segovia et al. 2007; docs/methods.md, "Metropolis instant radiosity").
//
// A light path is a function of its random numbers u (primary sample space, Kelemen et al. 2002). Markov chains
// over u have the target
//   f(u) = I(u) / I_mean + epsilon F(u) / F_mean,   I = sum of the path's VPL importances, F = sum of their fluxes
// so paths are visited in proportion to what they bring to the camera (the epsilon term keeps every path that
// carries light reachable). b = E[f] over uniform u, I_mean and F_mean come from independent stratified bootstrap
// paths. Each chain starts from a bootstrap path drawn in proportion to f and records it (sampling-importance
// resampling of the bootstrap: b / f times the path's flux has the light-traced sum's expectation); every mutation
// then records the proposal with weight a = min(1, f(u') / f(u)) and the current state with 1 - a (Veach's
// expected-value recording). A VPL of a path with total recorded weight W carries
//   flux = alpha W b / (T f(u))          T = recorded states: one start per chain plus the mutations,
// and each recorded term has the light-traced sum's expectation, since the chains' moves keep the target
// distribution (the b of the start's draw cancels the b of the flux). The chain plan and the target's normalisation
// come from the same bootstrap, which makes the sum consistent rather than exactly unbiased (a bias of the order of
// 1/mirBootstrapPaths); where the chains record only their bootstrap starts (no burn-in, no mutations) it is exactly
// unbiased.
//
// Chains: as many as the VPL budget holds start paths, up to mirChains. A start path is independent of the other
// chains' and already distributed as the target, where a mutation's proposal is a perturbed copy of its chain's
// state, which at a small budget spends VPLs on near-duplicates of recorded paths; mutations take the budget beyond
// the starts. A few mutations before the start is recorded (mirBurnIn) move each chain off its bootstrap path, so
// that chains that drew the same one part (docs/methods.md measures all three).
//
// Temporal coherence with a fixed seed: each chain picks its start by an exponential race over the bootstrap paths
// (path j wins with the smallest E_cj / f(u_j), E_cj ~ Exp(1) from a stream keyed by (seed, chain, j), which picks j
// with probability f_j / sum f); a small light move changes the f_j a little and the winner only where two nearly
// tie, and another chain count only adds or drops chains. Each chain step draws its numbers (step kind,
// perturbation, acceptance) from a stream keyed by (seed, chain, step), and the bootstrap paths are Halton points. A
// small light move changes f a little, so a chain takes the same steps to slightly moved paths until an acceptance
// decision flips; from there on only that chain differs.

#include "renderer/vpl/generation_detail.h"
#include "renderer/vpl/vpl_importance.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vplab {

namespace {

constexpr uint64_t kTagMirBootstrap = 0x4d495242ull;
constexpr uint64_t kTagMirChain = 0x4d495243ull;
constexpr uint64_t kTagMirStep = 0x4d495253ull;
constexpr uint64_t kTagMirStart = 0x4d495250ull;

/// Kelemen's small-step perturbation: |du| from 1/1024 to 1/64, exponentially distributed in between.
constexpr float kSmallStepMin = 1.0f / 1024.0f;
constexpr float kSmallStepMax = 1.0f / 64.0f;

/// Draws from `base` and records every number, so that a path can be retraced and mutated.
class RecordingSource : public RandomSource {
 public:
  RecordingSource(RandomSource& base, std::vector<float>& record) : base_(base), record_(record) {}
  float next() override {
    float u = base_.next();
    record_.push_back(u);
    return u;
  }

 private:
  RandomSource& base_;
  std::vector<float>& record_;
};

/// Reads a primary-sample vector; past its end draws fresh numbers (lazy extension) and appends them.
class PrimarySampleSource : public RandomSource {
 public:
  PrimarySampleSource(std::vector<float>& u, Rng& fresh) : u_(u), fresh_(fresh) {}
  float next() override {
    if (i_ == u_.size()) u_.push_back(fresh_.next1D());
    return u_[i_++];
  }

 private:
  std::vector<float>& u_;
  Rng& fresh_;
  std::size_t i_ = 0;
};

/// One visited path: its numbers, VPLs (flux alpha), target value and recorded weight.
struct PathState {
  std::vector<float> u;
  std::vector<Vpl> vpls;
  double f = 0.0;
  double weight = 0.0;
};

struct Target {
  const ImportanceEstimator& importance;
  double meanImportance, meanFlux, epsilon;
  double operator()(const std::vector<Vpl>& vpls) const {
    double imp = 0.0, flux = 0.0;
    for (const Vpl& v : vpls) {
      imp += importance(v);
      flux += std::max(0.0f, luminance(v.flux));
    }
    return imp / meanImportance + (meanFlux > 0.0 ? epsilon * flux / meanFlux : 0.0);
  }
};

float perturb(float u, Rng& rng) {
  float du = kSmallStepMax * std::exp(-std::log(kSmallStepMax / kSmallStepMin) * rng.next1D());
  u += rng.next1D() < 0.5f ? du : -du;
  u -= std::floor(u);
  return std::min(u, kOneMinusEpsilon);
}

}  // namespace

VplSet generateMetropolis(const GenerationContext& ctx) {
  const Settings& s = ctx.settings;
  ImportanceEstimator importance(ctx.offline, s);
  if (importance.empty()) return fallBackToLightTracing(ctx, "metropolis: no importance point sees a surface");
  const int maxBounces = std::max(1, s.vplMaxBounces);

  // Bootstrap: independent stratified light paths, their numbers recorded.
  const int64_t nB = s.mirBootstrapPaths;
  const std::array<float, kHaltonDims> offsets = haltonOffsets(s.seed, kTagMirBootstrap);
  std::vector<PathState> boot(static_cast<std::size_t>(nB));
  std::vector<double> bootImp(boot.size()), bootFlux(boot.size());
  parallelFor(
      nB, s.threads,
      [&](int64_t j, int) {
        PathState& p = boot[static_cast<std::size_t>(j)];
        HaltonPathSampler halton(static_cast<uint64_t>(j), offsets,
                                 hashKey(hashKey(s.seed, kTagMirBootstrap), static_cast<uint64_t>(j)));
        RecordingSource source(halton, p.u);
        traceLightPath(ctx.scene, ctx.embree, ctx.lights, maxBounces, source, p.vpls);
        for (const Vpl& v : p.vpls) {
          bootImp[static_cast<std::size_t>(j)] += importance(v);
          bootFlux[static_cast<std::size_t>(j)] += std::max(0.0f, luminance(v.flux));
        }
      },
      ctx.control);
  double meanImp = 0.0, meanFlux = 0.0, meanCount = 0.0;
  for (std::size_t j = 0; j < boot.size(); ++j) {
    meanImp += bootImp[j];
    meanFlux += bootFlux[j];
    meanCount += static_cast<double>(boot[j].vpls.size());
  }
  meanImp /= static_cast<double>(nB);
  meanFlux /= static_cast<double>(nB);
  meanCount /= static_cast<double>(nB);
  VplSet set;
  if (!(meanCount > 0.0)) return set;  // no light path reaches a surface: there is no indirect light
  if (!(meanImp > 0.0)) return fallBackToLightTracing(ctx, "metropolis: no light path lights an importance point");
  const Target target{importance, meanImp, meanFlux, s.mirEpsilon};
  double b = 0.0, countUnderF = 0.0;
  for (std::size_t j = 0; j < boot.size(); ++j) {
    boot[j].f = bootImp[j] / meanImp + (meanFlux > 0.0 ? s.mirEpsilon * bootFlux[j] / meanFlux : 0.0);
    b += boot[j].f;
    countUnderF += boot[j].f * static_cast<double>(boot[j].vpls.size());
  }
  countUnderF /= b;
  b /= static_cast<double>(nB);

  // Plan: each chain's start path holds countUnderF VPLs on average, so the budget holds about vplCount /
  // countUnderF chains (at most mirChains). The rest of the budget goes to mutations: a proposal is a large step (a
  // path as light tracing draws it) or a small one (a path like the target's), recorded with its VPLs.
  const int chains = static_cast<int>(
      std::clamp<int64_t>(static_cast<int64_t>(std::floor(s.vplCount / std::max(countUnderF, 1.0))), 1, s.mirChains));
  const double perProposal = s.mirLargeStepProbability * meanCount + (1.0 - s.mirLargeStepProbability) * countUnderF;
  const int64_t totalSteps =
      std::max<int64_t>(0, std::llround((s.vplCount - chains * countUnderF) / std::max(perProposal, 1e-9)));
  auto stepsOf = [&](int64_t c) { return totalSteps / chains + (c < totalSteps % chains ? 1 : 0); };
  const double recorded = static_cast<double>(chains + totalSteps);

  struct ChainResult {
    std::vector<PathState> states;
    uint64_t accepted = 0;
  };
  std::vector<ChainResult> results(static_cast<std::size_t>(chains));
  parallelFor(
      chains, s.threads,
      [&](int64_t c, int) {
        ChainResult& out = results[static_cast<std::size_t>(c)];
        // The start: an exponential race over the bootstrap paths (see the header), O(mirBootstrapPaths) per chain.
        const uint64_t raceKey = hashKey(hashKey(s.seed, kTagMirStart), static_cast<uint64_t>(c));
        std::size_t j = 0;
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < boot.size(); ++k) {
          if (!(boot[k].f > 0.0)) continue;
          // A uniform number in (0, 1] from 53 bits of the key's hash.
          const double u = (static_cast<double>(hashKey(raceKey, k) >> 11) + 1.0) * 0x1p-53;
          const double e = -std::log(u) / boot[k].f;
          if (e < best) {
            best = e;
            j = k;
          }
        }
        std::vector<PathState>& states = out.states;
        states.push_back(boot[j]);
        states.back().weight = s.mirBurnIn == 0 ? 1.0 : 0.0;
        std::size_t current = 0;
        for (int64_t step = 0; step < s.mirBurnIn + stepsOf(c); ++step) {
          const bool record = step >= s.mirBurnIn;
          Rng rng(hashKey(hashKey(s.seed, kTagMirStep), static_cast<uint64_t>(c), static_cast<uint64_t>(step)));
          PathState proposal;
          if (rng.next1D() >= s.mirLargeStepProbability) {
            proposal.u = states[current].u;
            for (float& x : proposal.u) x = perturb(x, rng);
          }
          PrimarySampleSource source(proposal.u, rng);
          traceLightPath(ctx.scene, ctx.embree, ctx.lights, maxBounces, source, proposal.vpls);
          proposal.f = proposal.vpls.empty() ? 0.0 : target(proposal.vpls);
          const double a = std::min(1.0, proposal.f / states[current].f);
          if (record) states[current].weight += 1.0 - a;
          const bool accept = rng.next1D() < a;
          if (a > 0.0 && (record || accept)) {
            if (record) proposal.weight = a;
            states.push_back(std::move(proposal));
            if (accept) current = states.size() - 1;
          }
          if (record && accept) ++out.accepted;
          // A burn-in state that was left is not needed any more.
          if (!record && accept && states.size() > 1) {
            states.erase(states.begin(), states.end() - 1);
            current = 0;
          }
          // After a burn-in the state it reached is the chain's recorded start.
          if (step + 1 == s.mirBurnIn) states[current].weight += 1.0;
        }
      },
      ctx.control);

  uint64_t accepted = 0;
  for (const ChainResult& r : results) {
    accepted += r.accepted;
    for (const PathState& p : r.states) {
      if (!(p.weight > 0.0)) continue;
      const float scale = static_cast<float>(p.weight * b / (recorded * p.f));
      for (Vpl v : p.vpls) {
        v.flux *= scale;
        set.vpls.push_back(v);
      }
    }
  }
  set.stats.candidates = set.vpls.size();
  set.stats.pathsTraced = static_cast<uint64_t>(nB);
  set.stats.chainSteps = static_cast<uint64_t>(totalSteps);
  set.stats.mutationAcceptance = totalSteps > 0 ? static_cast<double>(accepted) / static_cast<double>(totalSteps) : 0.0;
  return set;
}

}  // namespace vplab
