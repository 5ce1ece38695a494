#pragma once
// VPL generation (docs/methods.md, "VPL generation"): light tracing (Keller 1997) with optional rejection of
// unimportant VPLs (Georgiev & Slusallek 2010), bidirectional instant radiosity (Segovia et al. 2006) and Metropolis
// instant radiosity (Segovia et al. 2007), chosen by Settings::generation (the method list is
// renderer/vpl/generation_methods.h). Every method returns the same VplSet, which the GL preview and the CPU pass
// consume unchanged.
//
// What Settings::vplCount means: with light tracing the expected number of VPLs (accepted VPLs with rejection). The
// number of light paths N_paths is fixed *before* the main paths are traced, from a pilot with its own random
// stream (mean VPLs per path, times the mean acceptance probability with rejection). Because N_paths does not depend
// on the paths it normalises, every VPL flux alpha / N_paths (/ p_accept) is an unbiased estimate; stopping "when N
// VPLs exist" would make N_paths depend on the paths and bias the estimate by O(1/N). Bidirectional generation
// resamples exactly vplCount VPLs from its candidate pool; Metropolis plans its chain length for about vplCount.
// VplStats::accepted holds the count actually produced.
//
// Light path j draws its emission point and direction and its first bounce from a Halton point (index j,
// Cranley-Patterson rotated by the seed) and its later decisions from a PCG stream keyed by (seed, j). The same seed
// gives the same VPLs on any thread count, and a small light move moves every VPL a little instead of reshuffling
// them (the Metropolis chains: docs/methods.md, "Metropolis instant radiosity").

#include "renderer/core/parallel.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

#include <cstdint>
#include <vector>

namespace vplab {

/// Light paths traced to estimate the mean number of VPLs per path before the main paths are planned.
inline constexpr int kVplPilotPaths = 256;
/// Neighbour rank whose distance sets a VSL's radius when Settings::vslRadiusFromDensity is on.
inline constexpr int kVslDensityNeighbour = 8;

/// VPLs by settings.generation: a VPL stands for light that arrived at a surface after 1..vplMaxBounces bounces
/// (the vertex on the light is not a VPL: direct light is computed exactly). Fills Vpl::radius as vslRadii() does.
/// An importance-driven method whose importance points see nothing falls back to plain light tracing and says so
/// in VplStats::warnings. A cancelled generation returns what was finished (normalised by the planned counts).
VplSet generateVpls(const OfflineScene& offline, const Settings& settings, RenderControl* control = nullptr);

/// VSL radius of every VPL (docs/methods.md, "Virtual spherical lights"): settings.vslRadius, or with vslRadiusFromDensity, vslRadius times the
/// distance to the kVslDensityNeighbour-th nearest other VPL (Hasan et al. 2009 tie r to the local VPL density;
/// the distance is capped at the scene diagonal when there are too few VPLs).
std::vector<float> vslRadii(const std::vector<Vpl>& vpls, const Settings& settings, float sceneDiagonal);

}  // namespace vplab
