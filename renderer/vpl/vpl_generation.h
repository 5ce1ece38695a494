#pragma once
// VPL generation by light tracing (MANYLIGHTS.md section 2; Keller 1997, instant radiosity) with optional rejection
// of unimportant VPLs (section 3; Georgiev & Slusallek 2010).
//
// What Settings::vplCount means: the expected number of VPLs (accepted VPLs with rejection). The number of light
// paths N_paths is fixed *before* the main paths are traced, from a pilot with its own random stream (mean VPLs per
// path, times the mean acceptance probability with rejection). Because N_paths does not depend on the paths it
// normalises, every VPL flux alpha / N_paths (/ p_accept) is an unbiased estimate; stopping "when N VPLs exist"
// would make N_paths depend on the paths and bias the estimate by O(1/N). VplStats::accepted holds the count
// actually produced; it is close to vplCount, not equal to it.
//
// Paths are indexed 0..N_paths-1; path j draws its emission point and direction and its first bounce from a
// Halton point (index j, Cranley-Patterson rotated by the seed) and its later decisions from a PCG stream keyed by
// (seed, j). The same seed gives the same VPLs on any thread count, and a small light move moves every VPL a little
// instead of reshuffling them.

#include "renderer/core/parallel.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"
#include "renderer/vpl/vpl_contribution.h"

#include <cstdint>
#include <vector>

namespace vplab {

/// Light paths traced to estimate the mean number of VPLs per path before the main paths are planned.
inline constexpr int kVplPilotPaths = 256;
/// Neighbour rank whose distance sets a VSL's radius when Settings::vslRadiusFromDensity is on.
inline constexpr int kVslDensityNeighbour = 8;

/// Traces light paths and stores a VPL at every surface bounce 1..vplMaxBounces (the vertex on the light is not a
/// VPL: direct light is computed exactly). With settings.rejection, candidates are accepted with
/// p_i = min(Phi_i / Phi_v + epsilon, 1) and their flux divided by p_i. Fills Vpl::radius as vslRadii() does.
/// A cancelled generation returns the VPLs of the paths finished so far (normalised by the planned path count).
VplSet generateVpls(const OfflineScene& offline, const Settings& settings, RenderControl* control = nullptr);

/// VSL radius of every VPL (MANYLIGHTS 7): settings.vslRadius, or with vslRadiusFromDensity, vslRadius times the
/// distance to the kVslDensityNeighbour-th nearest other VPL (Hasan et al. 2009 tie r to the local VPL density;
/// the distance is capped at the scene diagonal when there are too few VPLs).
std::vector<float> vslRadii(const std::vector<Vpl>& vpls, const Settings& settings, float sceneDiagonal);

/// Camera-visible points used by rejection: primary hits through the centres of a coarse grid of about
/// settings.rejectionSamplePoints cells over the image (deterministic; misses and back faces are dropped).
std::vector<ShadingPoint> rejectionSamplePoints(const OfflineScene& offline, const Settings& settings);

}  // namespace vplab
